"""Stepper drives (paper 003 eqs. 27-28): the paper's pulse counts, round trips, table errors."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from dh2urdf import TableError, get_robot, parse_table
from kin.commands.drives import main as drives_main
from kin.configuration import Configuration
from kin.drives import (
    DrivesError,
    angles_to_pulses,
    from_pulses,
    pulses_to_angles,
    quantize,
    table_drives,
)
from kin.robot_model import load_robot


@pytest.fixture(scope="module")
def table():
    return get_robot("pickplace3").load_table()


def _toml(drives: dict) -> dict:
    row = {"type": "revolute", "a": 0.1, "alpha": 0.0, "d": 0.0, "theta": 0.0}
    return {
        "convention": "standard",
        "length_unit": "m",
        "angle_unit": "deg",
        "joints": [
            {**row, "name": "j1", "limits": [-90.0, 90.0]},
            {**row, "name": "j2", "limits": [-90.0, 90.0]},
        ],
        "drives": drives,
    }


def test_table2_pulses_per_revolution_and_step_sizes(table):
    """Table 2: 12800, 42962 (200 x 8 x 26.851 = 42961.6), 24000 pulses/rev; 0.0281/0.00838/0.015 deg."""
    drives = table_drives(table)
    assert [d.pulses_per_revolution for d in drives] == [12800, 42962, 24000]
    assert drives[1].geared_pulses_per_revolution == pytest.approx(42961.6)
    steps = [round(math.degrees(d.step_size), p) for d, p in zip(drives, (4, 5, 3), strict=True)]
    assert steps == [0.0281, 0.00838, 0.015]


def test_fig4_pulses_from_the_gui_home(table):
    """Fig. 4: q = (-20, 2.0223, -14.9999) deg sends -711, -10499 and (sign aside) 5000 pulses."""
    pulses = angles_to_pulses(table_drives(table), np.radians([-20.0, 2.0223, -14.9999]))
    assert pulses.tolist() == [-711, -10499, 5000]


def test_table4_actual_column(table):
    """Table 4 case 2: the Actual position (398.3570, -218.5304, 187.1793) mm and Abs. Different."""
    result = quantize(table, np.radians([-30.0, 5.0, -5.0]))
    assert result.pulses.tolist() == [[-1067, -10144, 5667]]
    np.testing.assert_allclose(
        result.p_world_tool_reached[0] * 1000, [398.3570, -218.5304, 187.1793], atol=5e-5
    )
    np.testing.assert_allclose(
        np.abs(result.tool_position_error[0]) * 1000, [0.035329, 0.065428, 0.009597], atol=5e-7
    )


def test_round_trip_error_below_half_a_step(table):
    """angle -> pulses -> angle: every joint error at most half a step; pulses of it are the same."""
    rng = np.random.default_rng(3)
    q = rng.uniform(table.lower, table.upper, size=(2000, table.dof))
    result = quantize(table, q)
    assert np.all(np.abs(result.joint_error) <= result.step_size / 2 + 1e-12)
    drives = table_drives(table)
    np.testing.assert_array_equal(angles_to_pulses(drives, result.q_reached), result.pulses)
    again = from_pulses(table, result.pulses, q)
    np.testing.assert_allclose(again.q_reached, result.q_reached, atol=1e-15)
    np.testing.assert_allclose(again.tool_position_error, result.tool_position_error, atol=1e-15)


def test_tool_error_matches_pinocchio(table):
    """The reached tool point is Pinocchio's FK at the reached angles."""
    robot = load_robot("pickplace3")
    result = quantize(table, np.radians([12.3, 45.6, -78.9]))
    pose = Configuration(robot, result.q_reached[0]).transform_frame_to_world("tool")
    np.testing.assert_allclose(result.p_world_tool_reached[0], pose.translation, atol=1e-12)
    assert 0 < result.tool_position_error_norm[0] < 1e-4


def test_halves_round_away_from_zero_and_direction_flips(table):
    """ROUND is MATLAB's (2.5 -> 3, -2.5 -> -3); direction -1 sends the opposite count."""
    drive = dataclasses.replace(table_drives(table)[0], pulses_per_revolution=360.0)
    q = np.radians([[2.5], [-2.5], [0.5]])
    assert angles_to_pulses([drive], q).ravel().tolist() == [3, -3, 1]
    flipped = dataclasses.replace(drive, direction=-1)
    assert angles_to_pulses([flipped], q).ravel().tolist() == [-3, 3, -1]
    np.testing.assert_allclose(pulses_to_angles([flipped], [[-3]]), np.radians([[3.0]]))


def test_drives_section_by_name_and_row_index():
    """[drives] entries by joint name or row number; home in the table's angle unit."""
    parsed = parse_table(
        _toml(
            {
                "j1": {"steps_per_revolution": 200, "microstepping": 4},
                "2": {"steps_per_revolution": 200, "microstepping": 2, "gear_ratio": 3, "home": 90},
            }
        )
    )
    assert [d.joint for d in parsed.drives] == ["j1", "j2"]
    assert [d.pulses_per_revolution for d in parsed.drives] == [800, 1200]
    assert parsed.drives[1].home == pytest.approx(math.pi / 2)


@pytest.mark.parametrize(
    ("drives", "where"),
    [
        ({"j1": {"steps_per_revolution": 200, "microstepping": 4, "ratio": 2}}, "drives.ratio"),
        ({"j1": {"steps_per_revolution": 200}}, "drives.microstepping"),
        ({"j3": {"steps_per_revolution": 200, "microstepping": 4}}, "drives.j3"),
        ({"j1": {"steps_per_revolution": -1, "microstepping": 4}}, "drives.steps_per_revolution"),
        ({"j1": {"steps_per_revolution": 200, "microstepping": 4, "direction": 2}}, "direction"),
        (
            {"j1": {"steps_per_revolution": 200, "microstepping": 4, "pulses_per_revolution": 802}},
            "drives.pulses_per_revolution",
        ),
    ],
)
def test_bad_drives_raise_table_error(drives, where):
    """Unknown or bad [drives] fields raise TableError naming the row and the field."""
    with pytest.raises(TableError, match=where) as info:
        parse_table(_toml(drives), "arm.toml")
    assert info.value.path == "arm.toml"
    if where != "drives.j3":
        assert info.value.row == 1


def test_table_without_drives_names_the_section():
    """quantize of a table without [drives] raises DrivesError naming the joints' sections."""
    with pytest.raises(DrivesError, match=r"\[drives\.base\]"):
        quantize(get_robot("scorbot").load_table(), np.zeros(5))


def test_cli_text_and_json(capsys):
    """kin drives prints pulses and the tool error in --unit; --json is SI with unit-named keys."""
    assert (
        drives_main(["--robot", "pickplace3", "--q", "-30", "5", "-5", "--deg", "--unit", "mm"])
        == 0
    )
    out = capsys.readouterr().out
    assert "-1067" in out and "-0.035329" in out and "[mm]" in out
    assert (
        drives_main(["--robot", "pickplace3", "--pulses", "-711", "-10499", "5000", "--json"]) == 0
    )
    record = json.loads(capsys.readouterr().out)
    assert record["pulses"] == [-711, -10499, 5000]
    assert record["q_reached_rad"][2] == pytest.approx(math.radians(-15.0))
    assert record["tool_position_error_norm_m"] == 0.0


def test_cli_robot_without_drives_exits_2(capsys):
    """A robot without [drives]: one line on stderr naming the table and the section, exit 2."""
    assert drives_main(["--robot", "scorbot", "--q", "0", "0", "0", "0", "0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "scorbot.toml" in err and "[drives." in err
