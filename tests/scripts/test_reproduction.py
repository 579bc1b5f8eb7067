"""The reproduction report is up to date, and the papers' key numbers hold through kin directly."""

from __future__ import annotations

import dataclasses
import importlib.util
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from dh2urdf import get_robot
from dh2urdf.urdf_writer import urdf_string
from kin.configuration import Configuration
from kin.robot_model import RobotModel, load_robot

ROOT = Path(__file__).resolve().parents[2]


def _script():
    spec = importlib.util.spec_from_file_location(
        "reproduce_papers", ROOT / "scripts" / "reproduce_papers.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _position(robot: RobotModel, q_deg, unit: float) -> np.ndarray:
    q = np.radians(np.asarray(q_deg, dtype=float))
    return Configuration(robot, q).transform_frame_to_world("tool").translation / unit


def _humanoid7_with_l2(l2_m: float) -> RobotModel:
    table = get_robot("humanoid7").load_table()
    rows = list(table.rows)
    rows[2] = dataclasses.replace(rows[2], d=l2_m)
    changed = dataclasses.replace(table, rows=tuple(rows))
    urdf = urdf_string(changed)
    return RobotModel("humanoid7_l2", changed, pin.buildModelFromXML(urdf), urdf)


def _humanoid7_q(robot: RobotModel, dh_angles_deg) -> list[float]:
    """The paper's cases print DH angles: q = angle - Table I offset."""
    return [
        a - math.degrees(row.theta) for a, row in zip(dh_angles_deg, robot.table.rows, strict=True)
    ]


def test_committed_report_is_up_to_date():
    """--check exits 0 on the committed docs/reproduction.md."""
    assert _script().main(["--check"]) == 0


def test_check_fails_on_a_stale_file(tmp_path, capsys):
    """--check exits 1 with one line on stderr when the file differs; a plain run then writes it."""
    script = _script()
    output = tmp_path / "reproduction.md"
    output.write_text("stale\n", encoding="utf-8")
    assert script.main(["--check", "--output", str(output)]) == 1
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert script.main(["--output", str(output)]) == 0
    assert script.main(["--check", "--output", str(output)]) == 0
    assert output.read_text(encoding="utf-8") == (ROOT / "docs" / "reproduction.md").read_text(
        encoding="utf-8"
    )


def test_section_providers_give_rows():
    """Every provider returns sections with rows and known verdicts."""
    from reproduction import SECTION_PROVIDERS

    for provider in SECTION_PROVIDERS:
        sections = provider()
        assert sections, f"{provider=}"
        for section in sections:
            assert section.rows, f"{section.title=}"
            assert {row.verdict for row in section.rows} <= {
                "reproduced",
                "flagged",
                "not reproduced",
            }


def test_humanoid7_home_depends_on_l2():
    """Case 1 X is 86.404 cm with Table I's L2 = 28.774 cm, 86.33 cm with the equations' 28.7 cm."""
    case1 = (0, -90, 90, 0, 0, 90, 0)
    ours = load_robot("humanoid7")
    assert _humanoid7_q(ours, case1) == [0.0] * 7
    np.testing.assert_allclose(_position(ours, [0.0] * 7, 0.01), [86.404, 0.0, 0.0], atol=1e-9)
    short = _humanoid7_with_l2(0.287)
    np.testing.assert_allclose(_position(short, [0.0] * 7, 0.01), [86.33, 0.0, 0.0], atol=1e-9)


@pytest.mark.parametrize(
    ("l2_m", "printed_y", "places"),
    [(0.287, -58.788, 3), (0.2877, -58.8489, 4)],  # DH / Peter Corke columns; RoboAnalyzer column
)
def test_humanoid7_case2_y(l2_m, printed_y, places):
    """Table III Y: L2 = 28.7 cm gives the DH column, L2 = 28.77 cm the RoboAnalyzer column."""
    robot = _humanoid7_with_l2(l2_m)
    y = _position(robot, _humanoid7_q(robot, (-90, -60, -30, 0, 30, 60, 90)), 0.01)[1]
    assert round(y, places) == pytest.approx(printed_y, abs=1e-12), f"{l2_m=} {y=}"


def test_ned5_home():
    """Paper 001: home (43.8, 0, 1) cm at q = 0."""
    np.testing.assert_allclose(
        _position(load_robot("ned5"), [0.0] * 5, 0.01), [43.8, 0.0, 1.0], atol=1e-9
    )


def test_pickplace3_case2():
    """Paper 003 Table 4 case 2: (398.3923, -218.4649, 187.1697) mm at q = [-30, 5, -5] deg."""
    position = _position(load_robot("pickplace3"), [-30.0, 5.0, -5.0], 0.001)
    np.testing.assert_allclose(position, [398.3923, -218.4649, 187.1697], atol=5e-5)


def test_pickplace3_case1_is_the_gui_home():
    """Table 4 case 1 (258, 10, 367) mm is the GUI home [0, 90, -90] deg, not [0, -90, 90]."""
    robot = load_robot("pickplace3")
    np.testing.assert_allclose(
        _position(robot, [0.0, 90.0, -90.0], 0.001), [258.0, 10.0, 367.0], atol=1e-9
    )
    assert _position(robot, [0.0, -90.0, 90.0], 0.001)[2] == pytest.approx(-27.0)


def test_pickplace3_case2_actual():
    """Table 4 case 2 Actual: stepper pulses (Table 2) counted from the GUI home, eqs. (27)-(28)."""
    home, target, pulses = (0.0, 90.0, -90.0), (-30.0, 5.0, -5.0), (12800, 42962, 24000)
    q = [
        h + round((t - h) * n / 360.0) * 360.0 / n
        for h, t, n in zip(home, target, pulses, strict=True)
    ]
    position = _position(load_robot("pickplace3"), q, 0.001)
    np.testing.assert_allclose(position, [398.3570, -218.5304, 187.1793], atol=5e-5)


def test_scorbot_home():
    """Paper 004: 0T5 at q = 0 is p = (603, 0, 349) mm with the approach axis along +x."""
    robot = load_robot("scorbot")
    pose = Configuration(robot, np.zeros(robot.nq)).transform_frame_to_world("tool")
    np.testing.assert_allclose(pose.translation * 1000.0, [603.0, 0.0, 349.0], atol=1e-9)
    np.testing.assert_allclose(pose.rotation[:, 2], [1.0, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("case", [2, 4])
def test_closest_configuration_row_is_the_same_for_permuted_and_perturbed_starts(case):
    """Table IX, cases 2 and 4 (no answer inside the limits): the row is the same when the
    searches run in another order and the target moves by 1e-13 m (ties of equally close joint
    vectors are broken by the last bits of the arithmetic: the row prints only the distance)."""
    from kin.ik.numeric.solver import NumericIK
    from reproduction.ik_humanoid7 import _CASES, _SEEDS, our_solver_row

    solver = NumericIK(load_robot("humanoid7"))
    desired = np.array([float(v) for v in _CASES[case - 1][0]])
    reference = our_solver_row(solver, case, desired, "printed")
    assert reference.verdict == "flagged" and "closest found" in reference.ours
    for seeds, offset in (
        (tuple(reversed(_SEEDS)), 0.0),
        (_SEEDS, 1e-11),
        (_SEEDS[1:] + _SEEDS[:1], -1e-11),
    ):
        row = our_solver_row(solver, case, desired + offset, "printed", seeds)  # 1e-11 cm = 1e-13 m
        assert row == reference, f"{case=} {seeds=} {offset=}"
