"""DH table files: shipped tables read right, malformed ones fail with file, row and field named.

Also the errors of ``kin`` at its edges: unknown robot, bad joint vector, unknown frame.
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest
from support.dh_reference import load_reference

import kin
from dh2urdf import Dh2UrdfError, TableError, UnknownRobotError, get_robot, load_table, robot_names
from kin import Configuration, FrameError, JointVectorError, load_robot

VALID = textwrap.dedent(
    """
    convention = "standard"
    length_unit = "mm"
    angle_unit = "deg"

    [[joints]]
    name = "first"
    type = "revolute"
    a = 10.0
    alpha = 90.0
    d = 100.0
    theta = 0.0
    limits = [-90.0, 90.0]

    [[joints]]
    name = "second"
    type = "revolute"
    a = 200.0
    alpha = 0.0
    d = 0.0
    theta = 0.0
    limits = [-45.0, 135.0]
    """
)


def write(tmp_path, text: str, name: str = "arm.toml"):
    """Write a table file and return its path."""
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def second_row(text: str, old: str, new: str) -> str:
    """VALID with ``old`` replaced by ``new`` in the second [[joints]] row only."""
    head, row2 = text.rsplit("[[joints]]", 1)
    assert old in row2
    return head + "[[joints]]" + row2.replace(old, new, 1)


@pytest.mark.parametrize("robot", robot_names())
def test_shipped_table_values_in_si_units(robot):
    """dh2urdf reads each shipped table to the same SI values as the independent reader."""
    table = load_table(get_robot(robot).table_path)
    ref = load_reference(get_robot(robot).table_path)
    assert table.joint_names == ref.names, f"{robot=}"
    assert table.convention == ref.convention, f"{robot=}"
    for field in ("a", "alpha", "d", "theta"):
        got = np.array([getattr(row, field) for row in table.rows])
        assert np.allclose(got, getattr(ref, field), rtol=1e-15, atol=1e-15), f"{robot=} {field=}"
    assert np.allclose(table.lower, ref.lower, atol=1e-15) and np.allclose(
        table.upper, ref.upper, atol=1e-15
    ), f"{robot=}"
    assert np.all(table.lower <= table.upper), f"{robot=}"
    assert np.allclose(table.T_world_base, ref.T_world_base, atol=1e-15), f"{robot=}"
    assert np.allclose(table.T_last_tool, ref.T_last_tool, atol=1e-15), f"{robot=}"


@pytest.mark.parametrize("robot", robot_names())
def test_model_limits_are_table_limits(robot):
    """The Pinocchio model built from the committed URDF has the table's joint names and limits."""
    robot_model = load_robot(robot)
    ref = load_reference(get_robot(robot).table_path)
    assert robot_model.joint_names == ref.names, f"{robot=}"
    assert np.allclose(robot_model.lower, ref.lower, atol=1e-12), f"{robot=}"
    assert np.allclose(robot_model.upper, ref.upper, atol=1e-12), f"{robot=}"


def test_units_convert_mm_and_deg_to_si(tmp_path):
    """mm/deg values a = 10, alpha = 90, limits [-45, 135] read as 0.01 m, pi/2, [-pi/4, 3 pi/4]."""
    table = load_table(write(tmp_path, VALID))
    first, second = table.rows
    assert (first.a, first.d) == pytest.approx((0.01, 0.1), abs=1e-15)
    assert first.alpha == pytest.approx(math.pi / 2, abs=1e-15)
    assert (second.lower, second.upper) == pytest.approx((-math.pi / 4, 3 * math.pi / 4), abs=1e-15)
    assert table.name == "arm"
    assert [row.index for row in table.rows] == [1, 2]


# case -> (mutated table text, row named in the message or None, field named in the message)
MALFORMED = {
    "missing field": (second_row(VALID, "d = 0.0\n", ""), 2, "d"),
    "unknown field": (second_row(VALID, "a = 200.0", "lenght = 200.0\na = 200.0"), 2, "lenght"),
    "wrong type": (second_row(VALID, "a = 200.0", 'a = "200"'), 2, "a"),
    "nan": (second_row(VALID, "alpha = 0.0", "alpha = nan"), 2, "alpha"),
    "infinite": (second_row(VALID, "theta = 0.0", "theta = inf"), 2, "theta"),
    "boolean": (second_row(VALID, "d = 0.0", "d = true"), 2, "d"),
    "lower above upper": (
        second_row(VALID, "limits = [-45.0, 135.0]", "limits = [135.0, -45.0]"),
        2,
        "limits",
    ),
    "nan limit": (
        second_row(VALID, "limits = [-45.0, 135.0]", "limits = [nan, 135.0]"),
        2,
        "limits",
    ),
    "one limit": (second_row(VALID, "limits = [-45.0, 135.0]", "limits = [-45.0]"), 2, "limits"),
    "unknown joint type": (second_row(VALID, '"revolute"', '"spherical"'), 2, "type"),
    "unknown length unit": (VALID.replace('"mm"', '"inch"'), None, "length_unit"),
    "unknown angle unit": (VALID.replace('"deg"', '"grad"'), None, "angle_unit"),
    "unknown convention": (VALID.replace('"standard"', '"craig"'), None, "convention"),
    "missing convention": (VALID.replace('convention = "standard"\n', ""), None, "convention"),
    "unknown top-level field": (
        VALID.replace('angle_unit = "deg"', 'angle_unit = "deg"\nunits = "SI"'),
        None,
        "units",
    ),
    "no joints": (VALID.split("[[joints]]")[0], None, "joints"),
    "base xyz of two numbers": (VALID + "[base]\nxyz = [1.0, 2.0]\n", None, "base.xyz"),
    "base rpy not numbers": (VALID + '[base]\nrpy = [0.0, "a", 0.0]\n', None, "base.rpy"),
    "base mixes forms": (VALID + "[base]\nxyz = [0.0, 0.0, 1.0]\nalpha = 90.0\n", None, "base"),
    "base not a table": (
        VALID.replace('angle_unit = "deg"', 'angle_unit = "deg"\nbase = 3.0'),
        None,
        "base",
    ),
    "tool nan": (VALID + "[tool]\nd = nan\n", None, "tool.d"),
    "tool unknown key": (VALID + "[tool]\nlength = 5.0\n", None, "tool"),
    "duplicate joint name": (second_row(VALID, '"second"', '"first"'), 2, "name"),  # the repeat
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_malformed_table_raises_table_error_naming_file_row_and_field(case, tmp_path):
    """Each malformed table raises TableError whose message names the file, joint row and field."""
    text, row, field = MALFORMED[case]
    path = write(tmp_path, text)
    with pytest.raises(TableError) as info:
        load_table(path)
    error = info.value
    message = str(error)
    assert str(path) in message, f"{case=} {message=}"
    assert f"field '{field}'" in message, f"{case=} {message=}"
    assert (error.path, error.row, error.field) == (str(path), row, field), f"{case=} {message=}"
    if row is not None:
        assert f"joint row {row}" in message, f"{case=} {message=}"
    else:
        assert "joint row" not in message, f"{case=} {message=}"
    assert isinstance(error, Dh2UrdfError) and isinstance(error, ValueError), f"{case=}"


@pytest.mark.parametrize(
    ("case", "choices"),
    [
        ("unknown length unit", ("cm", "m", "mm")),
        ("unknown angle unit", ("deg", "rad")),
        ("unknown convention", ("modified", "standard")),
        ("unknown joint type", ("prismatic", "revolute")),
    ],
)
def test_choice_errors_list_the_valid_choices(case, choices, tmp_path):
    """Unknown unit, convention or joint type: the message names the bad value and every choice."""
    with pytest.raises(TableError) as info:
        load_table(write(tmp_path, MALFORMED[case][0]))
    message = str(info.value)
    for choice in choices:
        assert choice in message, f"{case=} {choice=} {message=}"


def test_missing_and_non_toml_files_raise_table_error(tmp_path):
    """A missing file and a file that is not TOML both raise TableError naming the file."""
    missing = tmp_path / "absent.toml"
    with pytest.raises(TableError, match="absent.toml"):
        load_table(missing)
    broken = write(tmp_path, "convention = \n", "broken.toml")
    with pytest.raises(TableError, match="broken.toml.*not valid TOML"):
        load_table(broken)


def test_malformed_table_through_kin_raises_table_error(tmp_path):
    """kin.load_robot(path) lets the TableError of a bad table through, row and field named."""
    path = write(tmp_path, MALFORMED["nan"][0])
    with pytest.raises(TableError, match=r"joint row 2, field 'alpha'"):
        load_robot(path)


@pytest.mark.parametrize(
    "loader", [get_robot, load_robot], ids=["dh2urdf.get_robot", "kin.load_robot"]
)
def test_unknown_robot_lists_known_robots(loader):
    """An unknown robot name raises UnknownRobotError whose message lists every known robot."""
    with pytest.raises(UnknownRobotError) as info:
        loader("ur16e")
    message = str(info.value)
    assert "ur16e" in message
    for name in robot_names():
        assert name in message, f"{name=} {message=}"
    assert info.value.known == robot_names()
    assert isinstance(info.value, KeyError)


@pytest.mark.parametrize(
    "q",
    [
        np.zeros(1),
        np.zeros(3),
        [],
        [0.0, math.nan],
        [math.inf, 0.0],
        ["a", "b"],
        [None, 0.0],
        "0 0",
    ],
    ids=["too few", "too many", "empty", "nan", "inf", "strings", "none", "string"],
)
def test_bad_joint_vector_raises_joint_vector_error(q):
    """Wrong number of values, NaN/inf or non-numeric q raise JointVectorError (update and fk)."""
    robot = load_robot("planar2")
    configuration = Configuration(robot)
    with pytest.raises(JointVectorError) as info:
        configuration.update(q)
    assert info.value.expected == 2
    with pytest.raises(JointVectorError):
        Configuration(robot, q)
    try:
        q_float = np.array(q, dtype=float)
    except ValueError:
        q_float = None  # fk's fast path takes float arrays only (its documented contract)
    if q_float is not None:
        with pytest.raises(JointVectorError):
            configuration.fk(q_float, "tool")
    assert np.array_equal(configuration.q, np.zeros(2)), (
        "a refused q must not change the configuration"
    )


def test_wrong_size_message_names_robot_and_counts():
    """The size error names the robot, its joints and how many values came."""
    with pytest.raises(JointVectorError, match=r"'planar2' has 2 joints \(joint1, joint2\), got 3"):
        Configuration(load_robot("planar2"), [0.0, 0.0, 0.0])


@pytest.mark.parametrize("method", ["transform_frame_to_world", "frame_jacobian", "fk"])
def test_unknown_frame_raises_frame_error_listing_frames(method):
    """An unknown frame raises FrameError listing the model's frames (tool, frame0..frame{n})."""
    robot = load_robot("ur5")
    configuration = Configuration(robot)
    call = getattr(configuration, method)
    with pytest.raises(FrameError) as info:
        call(np.zeros(6), "tool0") if method == "fk" else call("tool0")
    message = str(info.value)
    assert "'tool0' does not exist" in message
    for frame in ("tool", "frame0", "frame6", "base_link"):
        assert frame in message, f"{frame=} {message=}"
    assert info.value.available == robot.frame_names
    assert isinstance(info.value, kin.KinError)
