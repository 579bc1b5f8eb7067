"""Unit slips give one warning line that names the value and the likely fix (not an error)."""

from __future__ import annotations

import warnings

import pytest

from dh2urdf import get_robot, load_table
from dh2urdf.exceptions import UnitWarning
from kin.commands import fk, ik


def _table(tmp_path, old: str, new: str):
    text = get_robot("scorbot").table_path.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "slip.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def _one_warning(err: str, *needles: str) -> None:
    """Exactly one line on stderr, a warning holding every needle (a slip and its limits too)."""
    lines = err.splitlines()
    assert len(lines) == 1 and "warning:" in lines[0], err
    assert all(needle in lines[0] for needle in needles), lines[0]


def test_degrees_in_a_radian_table(tmp_path, capsys):
    """scorbot's degree values with angle_unit = "rad": alpha -90 rad is named, with the fix."""
    path = _table(tmp_path, 'angle_unit = "deg"', 'angle_unit = "rad"')
    with pytest.warns(UnitWarning, match="field 'alpha': -90 rad"):
        load_table(path)
    assert fk.main(["--robot", str(path), "--q", "0", "0", "0", "0", "0"]) == 0
    _one_warning(capsys.readouterr().err, "kin fk: warning:", 'angle_unit = "deg"')


def test_millimeters_in_a_meter_table(tmp_path, capsys):
    """scorbot's millimeters with length_unit = "m": a 952 m arm, length_unit = "mm" suggested."""
    path = _table(tmp_path, 'length_unit = "mm"', 'length_unit = "m"')
    assert fk.main(["--robot", str(path), "--q", "0", "0", "0", "0", "0", "--deg"]) == 0
    _one_warning(capsys.readouterr().err, "952 m", 'length_unit = "mm"')


def test_degrees_without_deg(capsys):
    """--q 6.5 without --deg (outside ur5's wrist limits, inside as degrees): one warning line
    that says --deg; the command runs."""
    assert fk.main(["--robot", "ur5", "--q", "0", "0", "0", "0", "6.5", "0"]) == 0
    _one_warning(capsys.readouterr().err, "--q value 6.5", "--deg")


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["ik", "--target", "0.4", "0.1", "0.3", "--rpy", "180", "0", "0"], "--rpy value 180"),
        (["ik", "--target", "0.4", "0.1", "0.3", "--rpy", "0", "-7", "0"], "--rpy value -7"),
        (["path", "--from", "0.4", "0", "0.3", "--rpy", "180", "0", "0", "--to", "0.4", "0.2",
          "0.3", "--rpy", "180", "0", "0", "--steps", "4"], "--rpy value 180"),
        (["preview", "--target", "0.4", "0.1", "0.3", "--rpy", "180", "0", "0", "--html",
          "{tmp}/p.html"], "--rpy value 180"),
    ],
)  # fmt: skip
def test_target_angles_beyond_a_turn_without_deg_are_refused(argv, needle, tmp_path, capsys):
    """--rpy 180 0 0 without --deg solved 180 rad (another pose) with exit 0: now exit 2, one
    line naming --rpy and the fix --deg, and nothing written."""
    from support.cli_helper import assert_one_line_error, call

    from kin.commands import main

    argv = [argv[0], "--robot", "ur5", *(a.replace("{tmp}", str(tmp_path)) for a in argv[1:])]
    code = call(main, argv)
    err = capsys.readouterr().err
    assert_one_line_error(code, err, needle)
    assert "then add --deg" in err
    assert not (tmp_path / "p.html").exists()


def test_target_angles_within_a_turn_or_with_deg_are_solved(capsys):
    """The same target with --deg, or pi given in radians: solved, no warning."""
    target = ["--robot", "ur5", "--target", "0.4", "0.1", "0.3"]
    assert ik.main([*target, "--rpy", "180", "0", "0", "--deg"]) == 0
    assert ik.main([*target, "--rpy", "3.14159", "0", "0"]) == 0
    assert ik.main([*target, "--rpy", "-6.28", "0", "0"]) == 0
    assert capsys.readouterr().err == ""


def test_pitch_beyond_a_turn_without_deg_is_refused(capsys):
    """--pitch 90 without --deg (a five-joint arm's approach angle): exit 2, one line."""
    from support.cli_helper import assert_one_line_error, call

    code = call(ik.main, ["--robot", "lab5", "--target", "0.3", "0", "0.2", "--pitch", "90"])
    assert_one_line_error(code, capsys.readouterr().err, "--pitch value 90 rad")


def test_stream_line_with_degrees_without_deg_is_an_error_line():
    """kin ik --stdin: an "rpy" beyond a turn without --deg is that line's error (with --deg
    the same line is solved), the other lines answered."""
    import json

    from support.cli_helper import run

    lines = '{"target": [0.4, 0.1, 0.3], "rpy": [180, 0, 0]}\n{"target": [0.4, 0.1, 0.3]}\n'
    done = run(["ik", "--robot", "ur5", "--stdin"], stdin=lines)
    first, second = (json.loads(line) for line in done.stdout.splitlines())
    assert "--rpy value 180 rad" in first["error"] and "--deg" in first["error"]
    assert second["success"] is True and done.returncode == 1
    done = run(["ik", "--robot", "ur5", "--stdin", "--deg"], stdin=lines.splitlines()[0] + "\n")
    assert json.loads(done.stdout)["success"] is True, done.stdout


def test_shipped_tables_and_radian_values_warn_nothing(capsys):
    """No warning for any shipped table, nor for a turn or less without --deg."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        for name in ("humanoid7", "lab5", "ned5", "panda", "pickplace3", "planar2", "puma560"):
            load_table(get_robot(name).table_path)
        for name in ("scorbot", "ur3", "ur5", "ur10", "xarm7"):
            load_table(get_robot(name).table_path)
    assert (
        ik.main(["--robot", "ur5", "--target", "0.4", "0.1", "0.3", "--rpy", "3.14", "0", "0"]) == 0
    )
    assert "warning" not in capsys.readouterr().err


def _document(**changes) -> dict:
    """A two-joint table in m and rad (revolute, then prismatic), with ``changes`` applied."""
    document = {
        "convention": "standard",
        "length_unit": "m",
        "angle_unit": "rad",
        "joints": [
            {"type": "revolute", "a": 0.5, "alpha": 0.0, "d": 0.2, "theta": 0.0, "limits": [-3, 3]},
            {"type": "prismatic", "a": 0.0, "alpha": 0.0, "d": 0.0, "theta": 0.0, "limits": [0, 8]},
        ],
    }
    document.update(changes)
    return document


def _unit_warnings(document: dict) -> list[str]:
    from dh2urdf import parse_table

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        parse_table(document, "arm.toml")
    return [str(w.message) for w in caught if issubclass(w.category, UnitWarning)]


def test_prismatic_travel_in_a_radian_table_is_a_length_not_an_angle():
    """A prismatic joint moving 8 m in a rad table: no angle warning (8 > 2 pi, but meters)."""
    assert _unit_warnings(_document()) == []


@pytest.mark.parametrize(
    ("section", "needle"),
    [
        ({"base": {"xyz": [0, 0, 0], "rpy": [0, 0, 90.0]}}, "field 'base.rpy': 90 rad"),
        ({"tool": {"a": 0.0, "alpha": -90.0, "d": 0.1, "theta": 0.0}}, "field 'tool.alpha': -90"),
    ],
)
def test_base_and_tool_angles_in_a_radian_table(section, needle):
    """Degrees in [base] rpy or a DH-style [tool]: one warning naming the field and the fix."""
    messages = _unit_warnings(_document(**section))
    assert len(messages) == 1 and needle in messages[0] and 'angle_unit = "deg"' in messages[0]


def test_many_degree_values_give_one_angle_warning():
    """Every angle in degrees (rows, limits, base): still one warning line, the first value."""
    joints = _document()["joints"]
    joints[0].update(alpha=-90.0, theta=90.0, limits=[-165.0, 165.0])
    messages = _unit_warnings(_document(joints=joints, base={"rpy": [0, 0, 180.0]}))
    assert len(messages) == 1 and "joint row 1, field 'alpha': -90 rad" in messages[0]


def test_the_tool_offset_counts_in_the_arm_length():
    """Links of 8.7 m (a, d, travel) and a 12 m tool offset: over 20 m, one length warning."""
    assert _unit_warnings(_document(tool={"xyz": [0, 0, 11.0]})) == []
    messages = _unit_warnings(_document(tool={"xyz": [0, 0, 12.0]}))
    assert len(messages) == 1 and "20.7 m" in messages[0] and 'length_unit = "mm"' in messages[0]


def test_nearly_parallel_axes_are_no_unit_slip(tmp_path):
    """Kinova's Gen3 lite URDF rounds pi to 3.1416: axes 2 and 3 are 7e-6 rad from parallel and
    their common normal lies 38 km away (d = -38113.8 m out, -38113.8 m back). Its extracted
    table lays 76 km end to end, but the tool stays within a meter: no length warning."""
    from pathlib import Path

    from dh2urdf.table_writer import write_table
    from dh2urdf.urdf_to_dh import table_from_urdf

    urdf = Path(__file__).parents[1] / "data" / "six_r" / "gen3_lite.urdf"
    path = tmp_path / "gen3_lite.toml"
    write_table(table_from_urdf(urdf), path)
    table = load_table(path)
    assert sum(abs(row.d) for row in table.rows) > 7e4  # the far common normal
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        load_table(path)
    assert _unit_warnings(_document(tool={"xyz": [0, 0, 12.0]}))  # a long arm still warns


def _six_r_urdf(wrist_limit: str) -> str:
    """A 6R arm (an ABB-like offset wrist) whose joint 6 turns +-``wrist_limit`` rad."""
    joints = []
    origins = ["0 0 0.29", "0 0 0", "0 0.27 0", "0.07 0.3 0", "0 0 0", "0 0.07 0"]
    axes = ["0 0 1", "0 1 0", "0 1 0", "1 0 0", "0 1 0", "1 0 0"]
    for i, (origin, axis) in enumerate(zip(origins, axes), start=1):
        limit = wrist_limit if i == 6 else "2.9"
        joints.append(
            f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
            f'<origin xyz="{origin}"/><axis xyz="{axis}"/>'
            f'<limit lower="-{limit}" upper="{limit}" effort="10" velocity="4"/></joint>'
        )
    links = "".join(f'<link name="l{i}"/>' for i in range(7))
    return f'<robot name="wrist450">{links}{"".join(joints)}</robot>'


def test_multi_turn_wrist_from_urdf_then_load_warns_nothing(tmp_path, capsys):
    """Joint 6 at +-450 deg (7.854 rad): from-urdf writes the limits, the loader does not warn,
    and kin fk at 400 deg given in rad (6.98) warns nothing: it is inside the arm's limits."""
    from dh2urdf import from_urdf_command

    urdf = tmp_path / "wrist450.urdf"
    urdf.write_text(_six_r_urdf("7.853981633974483"), encoding="utf-8")
    table = tmp_path / "wrist450.toml"
    assert from_urdf_command.main([str(urdf), "-o", str(table)]) == 0
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        loaded = load_table(table)
    assert loaded.rows[5].upper == pytest.approx(7.853981633974483, abs=1e-12)
    capsys.readouterr()
    assert fk.main(["--robot", str(table), "--q", "0", "0", "0", "0", "0", "6.98"]) == 0
    assert "warning" not in capsys.readouterr().err
    assert fk.main(["--robot", str(urdf), "--q", "0", "0", "0", "0", "0", "-6.98"]) == 0
    assert "warning" not in capsys.readouterr().err


def test_degrees_outside_the_limits_warn_with_the_joint(capsys):
    """ur5 (+-360 deg): --q 90 rad is outside, 90 deg inside: one warning naming the joint."""
    assert fk.main(["--robot", "ur5", "--q", "0", "90", "0", "0", "0", "0"]) == 0
    _one_warning(capsys.readouterr().err, "--q value 90 rad", "shoulder_lift_joint", "--deg")


def test_beyond_the_limits_even_as_degrees_is_no_unit_slip(capsys):
    """ur5's elbow (+-180 deg): --q 500 is outside as rad and as deg: the limit line only."""
    assert fk.main(["--robot", "ur5", "--q", "0", "0", "500", "0", "0", "0"]) == 0
    err = capsys.readouterr().err
    assert "degrees?" not in err and "outside its limits" in err


@pytest.mark.parametrize(
    ("limit", "warned"), [(7.854, False), (25.1, False), (25.2, True), (170.0, True)]
)
def test_revolute_limits_warn_beyond_four_turns(limit, warned):
    """Limits up to four turns (8 pi = 25.13 rad) are multi-turn joints; beyond, degrees."""
    joints = _document()["joints"]
    joints[0]["limits"] = [-limit, limit]
    messages = _unit_warnings(_document(joints=joints))
    assert bool(messages) == warned, messages
    if warned:
        assert "more than four turns" in messages[0] and "field 'limits'" in messages[0]


@pytest.mark.parametrize(
    ("q", "needles"),
    [
        (["0", "90", "0", "0", "0", "0"], ["--q value 90 rad", "shoulder_lift_joint", "--deg"]),
        (["90", "90", "90", "90", "90", "90"], ["--q value 90 rad", "--deg", "6 joints"]),
        (
            ["0", "0", "4", "500", "0", "0"],
            ["2 joints are outside their limits", "'elbow_joint' 4"],
        ),
    ],
)
def test_fk_warns_in_one_line(q, needles, capsys):
    """kin fk on degree-looking values without --deg printed a line per joint outside its limits
    and one for the slip (four and more lines): one line now, the slip first, the count after;
    joints outside their limits without a slip are one line too."""
    assert fk.main(["--robot", "ur5", "--q", *q]) == 0
    _one_warning(capsys.readouterr().err, *needles)


@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # pyzmq's, shown under pytest only
def test_preview_warns_in_one_line(tmp_path, capsys):
    """kin preview --q 90 ... without --deg: one warning line, as kin fk."""
    from kin.commands import preview

    argv = ["--robot", "ur5", "--q", "90", "90", "0", "0", "0", "0", "--html", str(tmp_path / "p.html")]  # fmt: skip
    assert preview.main(argv) == 0
    _one_warning(capsys.readouterr().err, "--q value 90 rad", "--deg", "2 joints")
