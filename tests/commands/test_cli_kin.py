"""The ``kin`` command: dispatcher, ``kin robots``, ``kin fk`` (units rule, JSON in SI, pipes)."""

from __future__ import annotations

import json
import math
import subprocess

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call, kin_command, run, write_rrpr4
from support.dh_reference import fk_frames, load_reference, random_configurations

import kin
from dh2urdf import ROBOTS, robot_names
from kin import Configuration, load_robot
from kin.commands import COMMANDS, fk, main, robots


def _json(capsys, argv: list[str], module=fk) -> dict:
    assert module.main(argv) == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def test_help_lists_every_subcommand():
    """`python -m kin --help` exits 0 and names fk, ik and robots with their summaries."""
    done = run(["--help"])
    assert done.returncode == 0, done.stderr
    for name, summary in COMMANDS.items():
        assert f"  {name}" in done.stdout and summary in done.stdout
    assert {"fk", "ik", "robots"} <= set(COMMANDS) and list(COMMANDS) == sorted(COMMANDS)


def test_no_subcommand_prints_usage_and_exits_2():
    """`kin` alone: the usage line on stderr, nothing on stdout, exit code 2."""
    done = run([])
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.startswith("usage: kin") and "Traceback" not in done.stderr


def test_version_of_console_script_and_module():
    """`kin --version` (console script) and `python -m kin --version` print kin's version."""
    for module in (True, False):
        done = run(["--version"], module=module)
        assert done.returncode == 0 and done.stdout.strip() == f"kin {kin.__version__}", (
            kin_command()
        )


def test_unknown_subcommand_exits_2_with_one_line(capsys):
    """An unknown subcommand: exit 2, one line naming the choices."""
    code = call(main, ["bogus"])
    err = capsys.readouterr().err
    assert_one_line_error(code, err, "invalid choice: 'bogus'")
    assert all(f"'{name}'" in err for name in COMMANDS)


def test_robots_table_and_json(capsys):
    """`kin robots`: one row per shipped robot with its joint count and types; --json the same."""
    assert robots.main([]) == 0
    rows = capsys.readouterr().out.splitlines()[1:]
    assert [row.split()[0] for row in rows] == list(robot_names())
    records = _json(capsys, ["--json"], robots)
    assert [r["name"] for r in records] == sorted(ROBOTS)
    joints = {r["name"]: r["joints"] for r in records}
    assert joints == {
        "humanoid7": "7R",
        "lab5": "5R",
        "ned5": "5R",
        "panda": "7R",
        "pickplace3": "3R",
        "planar2": "2R",
        "puma560": "6R",
        "scorbot": "5R",
        "ur10": "6R",
        "ur3": "6R",
        "ur5": "6R",
        "xarm7": "7R",
    }
    for record, row in zip(records, rows):
        table = ROBOTS[record["name"]].load_table()
        assert record["dof"] == table.dof and record["source"] == table.source
        assert row.split(None, 2)[1:] == [record["joints"], table.source]


def test_robots_joint_code_counts_runs(tmp_path):
    """A revolute, revolute, prismatic, revolute table is coded 2R1P1R."""
    from dh2urdf import load_table
    from kin.commands.joint_units import joint_types_code

    assert joint_types_code(load_table(write_rrpr4(tmp_path))) == "2R1P1R"


@pytest.mark.parametrize("name", robot_names())
def test_fk_json_equals_configuration_fk(name, capsys):
    """`kin fk --json` gives Configuration's tool pose, in meters, for random q within limits."""
    robot = load_robot(name)
    configuration = Configuration(robot)
    rng = np.random.default_rng(len(name))
    for q in rng.uniform(robot.lower, robot.upper, size=(3, robot.nq)):
        out = _json(capsys, ["--robot", name, "--q", *map(repr, q.tolist()), "--json"])
        pose = configuration.fk(q)
        np.testing.assert_allclose(out["position_m"], pose.translation, atol=1e-12, err_msg=name)
        np.testing.assert_allclose(out["rotation"], pose.rotation, atol=1e-12, err_msg=name)
        assert out["q"] == q.tolist() and out["q_units"] == ["rad"] * robot.nq
        assert "unit" not in out and "position" not in out


def test_fk_deg_json_stays_in_radians(capsys):
    """`kin fk --deg --json`: q is printed in radians under "rad", not degrees."""
    out = _json(
        capsys, ["--robot", "ur5", "--q", "0", "90", "-45", "0", "30", "0", "--deg", "--json"]
    )
    np.testing.assert_allclose(out["q"], np.radians([0, 90, -45, 0, 30, 0]), atol=1e-15)
    assert out["q_units"] == ["rad"] * 6


def test_fk_text_units_round_trip(capsys):
    """Text output in mm and deg: the position equals the JSON meters x 1000, q in degrees."""
    argv = ["--robot", "scorbot", "--q", "10", "-20", "30", "-40", "50", "--deg"]
    meters = _json(capsys, [*argv, "--json"])["position_m"]
    assert fk.main([*argv, "--unit", "mm"]) == 0
    lines = capsys.readouterr().out.splitlines()
    position = [float(v) for v in lines[2].split(":")[1].split()]
    assert lines[2].startswith("position [mm]:")
    np.testing.assert_allclose(position, np.array(meters) * 1000, atol=1e-6)
    assert "base 10 deg" in lines[1] and "wrist_roll 50 deg" in lines[1]


@pytest.mark.parametrize("unit, scale", [("m", 1.0), ("cm", 0.01), ("mm", 0.001)])
def test_fk_prismatic_value_in_unit(unit, scale, tmp_path, capsys):
    """A prismatic joint value is a length in --unit: 100 mm = 10 cm = 0.1 m, checked by NumPy DH."""
    path = write_rrpr4(tmp_path)
    q_si = np.array([math.radians(10), math.radians(-35), 0.1, math.radians(40)])
    q_cli = [10, -35, 0.1 / scale, 40]
    out = _json(
        capsys, ["--robot", str(path), "--q", *map(str, q_cli), "--deg", "--unit", unit, "--json"]
    )
    reference = fk_frames(load_reference(path), q_si)[0, -1]
    np.testing.assert_allclose(out["position_m"], reference[:3, 3], atol=1e-12)
    np.testing.assert_allclose(out["q"], q_si, atol=1e-15)
    assert out["q_units"] == ["rad", "rad", "m", "rad"]


def test_fk_prismatic_text_names_units(tmp_path, capsys):
    """The text output gives the slide in mm and the tool height 300 - 20 - 100 - 50 = 130 mm."""
    path = write_rrpr4(tmp_path)
    assert fk.main(["--robot", str(path), "--q", "0", "0", "100", "0", "--unit", "mm"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "slide 100 mm" in lines[1] and "shoulder 0 rad" in lines[1]
    np.testing.assert_allclose(
        [float(v) for v in lines[2].split(":")[1].split()], [350, 0, 130], atol=1e-9
    )


def test_fk_random_prismatic_against_reference(tmp_path, capsys):
    """Random q (mm, deg) within the limits: kin fk equals the independent NumPy DH product."""
    path = write_rrpr4(tmp_path)
    reference = load_reference(path)
    for q_si in random_configurations(reference.lower, reference.upper, 5, seed=7):
        q_cli = np.where(reference.prismatic, q_si * 1000, np.degrees(q_si))
        argv = ["--robot", str(path), "--q", *map(repr, q_cli.tolist()), "--unit", "mm", "--deg"]
        out = _json(capsys, [*argv, "--json"])
        expected = fk_frames(reference, q_si)[0, -1]
        np.testing.assert_allclose(out["position_m"], expected[:3, 3], atol=1e-12)
        np.testing.assert_allclose(out["rotation"], expected[:3, :3], atol=1e-12)


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--robot", "nope", "--q", "0"], "known robots: humanoid7"),
        (
            ["--robot", "ur5", "--q", "0", "0"],
            "'ur5' (shoulder_pan_joint [rad], shoulder_lift_joint",
        ),
        (["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "nan"], "not a finite number"),
        (["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "x"], "not a number"),
        (["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0", "--unit", "km"], "invalid choice"),
        (
            ["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0", "--frame", "no"],
            "available frames",
        ),
        (["--robot", "missing.toml", "--q", "0"], "missing.toml"),
        (["--robot", "ur5"], "--q"),
    ],
)
def test_fk_bad_input_exits_2_with_one_line(argv, needle, capsys):
    """Bad input to `kin fk`: exit 2, one stderr line naming the problem, no traceback."""
    assert_one_line_error(call(fk.main, argv), capsys.readouterr().err, needle)
    assert capsys.readouterr().out == ""


def test_fk_bad_count_names_prismatic_unit(tmp_path, capsys):
    """A wrong --q count names the robot and every joint with its unit (slide in mm)."""
    path = write_rrpr4(tmp_path)
    code = call(fk.main, ["--robot", str(path), "--q", "0", "0", "--unit", "mm", "--deg"])
    needle = "--q needs 4 values for 'rrpr4' (shoulder [deg], elbow [deg], slide [mm], roll [deg]), got 2"
    assert_one_line_error(code, capsys.readouterr().err, needle)


def test_fk_bad_input_in_a_subprocess():
    """The same through `python -m kin fk`: exit 2, one line, no traceback."""
    done = run(["fk", "--robot", "ur5", "--q", "1", "2"])
    assert_one_line_error(
        done.returncode, done.stderr, "kin fk: error: --q needs 6 values for 'ur5'"
    )


def test_fk_negative_scientific_notation_is_a_value(capsys):
    """`--q -1.2e-16 ...` is a number, not an option."""
    out = _json(capsys, ["--robot", "planar2", "--q", "-1.2e-16", "-1e-3", "--json"])
    assert out["q"] == [-1.2e-16, -1e-3]


@pytest.mark.parametrize(
    "argv",
    [
        ["fk", "--robot", "humanoid7", "--q", *["0.1"] * 7],
        ["robots", "--json"],
    ],
)
def test_closed_pipe_exits_quietly(argv):
    """`kin ... | head -c 10`: the reader gets 10 bytes, kin exits 0 without a word on stderr."""
    writer = subprocess.Popen(kin_command() + argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    reader = subprocess.Popen(["head", "-c", "10"], stdin=writer.stdout, stdout=subprocess.PIPE)
    writer.stdout.close()
    head, _ = reader.communicate(timeout=60)
    err = writer.stderr.read()
    writer.stderr.close()
    assert writer.wait(timeout=60) == 0 and err == b"" and len(head) == 10
