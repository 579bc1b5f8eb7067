"""``kin path``: JSON and CSV in SI, the units rule, exit codes 0 / 1 / 2 with one-line errors."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call, run, write_rrpr4

from kin.commands import path as path_command

#: A scorbot line well inside the workspace, pitch 17 deg: [mm], [deg].
SCORBOT = ["--robot", "scorbot", "--unit", "mm", "--deg", "--steps", "20"]
SCORBOT_LINE = ["--from", "450", "100", "300", "--pitch", "17", "--to", "400", "0", "350", "--pitch", "17"]  # fmt: skip


def run_main(capsys, argv):
    code = call(path_command.main, argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_json_answer_is_si_with_unit_keys(capsys):
    """Exit 0; q per sample in rad, deviation in m, no branch change, not stopped."""
    code, out, err = run_main(capsys, SCORBOT + SCORBOT_LINE + ["--json"])
    assert code == 0, err
    record = json.loads(out)
    assert record["success"] is True and record["stopped_at"] is None
    assert record["q_units"] == ["rad"] * 5
    assert np.array(record["q"]).shape == (21, 5)
    assert record["max_deviation_m"] < 1e-4
    assert record["branch_changes"] == []
    assert record["max_joint_step_unit"] == "rad" and 0 < record["max_joint_step"] < 0.1
    assert "t_s" not in record


def test_units_do_not_change_the_joint_path(capsys):
    """The same line in m and rad gives the same SI joint path as in mm and deg."""
    _, out_mm, _ = run_main(capsys, SCORBOT + SCORBOT_LINE + ["--json"])
    si_line = ["--from", "0.45", "0.1", "0.3", "--pitch", str(math.radians(17))]
    si_line += ["--to", "0.4", "0", "0.35", "--pitch", str(math.radians(17))]
    _, out_m, _ = run_main(capsys, ["--robot", "scorbot", "--steps", "20", "--json"] + si_line)
    np.testing.assert_allclose(json.loads(out_mm)["q"], json.loads(out_m)["q"], atol=1e-12)


def test_timed_json_respects_the_velocity_limit(capsys):
    """--time --vmax 30 deg/s: t_s rises with q, |qd| <= 30 deg/s, at rest at both ends."""
    argv = SCORBOT + SCORBOT_LINE + ["--time", "--vmax", "30", "--amax", "60", "--json"]
    code, out, err = run_main(capsys, argv)
    assert code == 0, err
    record = json.loads(out)
    t, qd = np.array(record["t_s"]), np.array(record["qd"])
    assert t.shape == (21,) and qd.shape == (21, 5)
    assert (np.diff(t) > 0).all() and t[-1] == pytest.approx(record["duration_s"])
    assert np.abs(qd).max() <= math.radians(30) * 1.01
    np.testing.assert_allclose(qd[[0, -1]], 0.0, atol=1e-9)
    assert record["qd_units"] == ["rad/s"] * 5


def test_csv_has_a_header_with_units(tmp_path, capsys):
    """--csv with --time --dt: one row per 10 ms, t [s], joints [rad], velocities [rad/s]."""
    file = tmp_path / "path.csv"
    argv = SCORBOT + SCORBOT_LINE + ["--time", "--dt", "0.01", "--csv", str(file)]
    code, out, err = run_main(capsys, argv)
    assert code == 0, err
    rows = list(csv.reader(file.open(encoding="utf-8")))
    assert rows[0][:3] == ["sample", "t [s]", "base [rad]"]
    assert rows[0][-1] == "wrist_roll velocity [rad/s]"
    assert float(rows[3][1]) == pytest.approx(0.02)
    assert "max deviation from the path" in out


def test_prismatic_joint_values_follow_the_unit(tmp_path, capsys):
    """rrpr4 (prismatic joint 3) in --unit mm: the CSV is SI (m), the text in mm."""
    table = write_rrpr4(tmp_path)
    argv = ["--robot", str(table), "--steps", "4", "--unit", "mm"]
    argv += ["--from", "250", "100", "150", "--to", "250", "150", "150", "--csv", str(tmp_path / "p.csv")]  # fmt: skip
    code, out, err = run_main(capsys, argv)
    assert code == 0, (out, err)
    header = next(csv.reader((tmp_path / "p.csv").open(encoding="utf-8")))
    assert header[3] == "slide [m]"
    assert "slide [mm]" in out


def test_line_out_of_reach_exits_1_with_stopped_at(capsys):
    """A line leaving the workspace: exit 1, success false, stopped_at the first sample not reached."""
    argv = ["--robot", "scorbot", "--steps", "30", "--json", "--from", "0.4", "0", "0.3"]
    argv += ["--pitch", "0.3", "--to", "1.2", "0", "0.3", "--pitch", "0.3", "--time"]
    code, out, err = run_main(capsys, argv)
    assert code == 1, err
    record = json.loads(out)
    assert record["success"] is False and isinstance(record["stopped_at"], int)
    assert len(record["q"]) == record["stopped_at"] == len(record["t_s"])
    assert record["message"].startswith(f"stopped at sample {record['stopped_at']}: ")
    assert record["max_joint_step"] <= 0.35


def test_humanoid7_polyline_with_poses(capsys):
    """humanoid7 through a via point, full poses: followed by differential IK, deviation < 1e-4 m."""
    argv = ["--robot", "humanoid7", "--steps", "24", "--json", "--from", "0.46", "0.53", "-0.11"]
    argv += [
        "--rpy",
        "23",
        "0.7",
        "92",
        "--via",
        "0.44",
        "0.53",
        "-0.09",
        "--rpy",
        "23",
        "0.7",
        "92",
    ]
    argv += ["--to", "0.44", "0.51", "-0.08", "--rpy", "23", "0.7", "97", "--deg"]
    code, out, err = run_main(capsys, argv)
    record = json.loads(out)
    assert code == 0, (record["message"], err)
    assert record["method"] == "differential" and len(record["q"]) == 25
    assert record["max_deviation_m"] < 1e-4 and record["max_rotation_error_rad"] < 1e-4
    assert record["max_joint_step"] < 0.1


def test_quat_and_rpy_give_the_same_path(capsys):
    """ur5: --quat 1 0 0 0 at every point is --rpy 0 0 0."""
    line = ["--robot", "ur5", "--steps", "6", "--json", "--from", "0.4", "0.1", "0.3"]
    rpy = line + ["--rpy", "0", "0", "0", "--to", "0.4", "0.2", "0.3", "--rpy", "0", "0", "0"]
    quat = line + ["--quat", "1", "0", "0", "0", "--to", "0.4", "0.2", "0.3", "--quat", "1", "0", "0", "0"]  # fmt: skip
    first, second = (json.loads(run_main(capsys, argv)[1]) for argv in (rpy, quat))
    assert first["success"], first["message"]
    np.testing.assert_allclose(first["q"], second["q"], atol=1e-9)


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (
            [
                "--robot",
                "planar2",
                "--from",
                "0.3",
                "0.1",
                "0",
                "--axis",
                "0",
                "0",
                "1",
                "--to",
                "0.3",
                "0.2",
                "0",
                "--axis",
                "0",
                "0",
                "1",
                "--tool-axis",
                "w",
            ],
            "--tool-axis: invalid choice",
        ),  # fmt: skip
        (
            [
                "--robot",
                "ur5",
                "--rpy",
                "0",
                "0",
                "0",
                "--from",
                "0.3",
                "0",
                "0",
                "--to",
                "0.3",
                "0.1",
                "0",
            ],
            "--rpy must follow",
        ),  # fmt: skip
        (["--robot", "ur5", "--from", "0.3", "0", "0"], "--to exactly once"),
        (
            [
                "--robot",
                "ur5",
                "--from",
                "0.3",
                "0",
                "0",
                "--rpy",
                "0",
                "0",
                "0",
                "--to",
                "0.3",
                "0.1",
                "0",
            ],
            "same orientation",
        ),  # fmt: skip
        (
            ["--robot", "ur5", "--from", "0.3", "0", "0", "--to", "0.3", "0.1", "0", "--vmax", "1"],
            "--vmax needs --time",
        ),  # fmt: skip
        (
            [
                "--robot",
                "pickplace3",
                "--from",
                "0.3",
                "0.1",
                "0.3",
                "--rpy",
                "0",
                "0",
                "0",
                "--to",
                "0.3",
                "0.2",
                "0.3",
                "--rpy",
                "0",
                "0",
                "0",
                "--tool-axis",
                "x",
            ],
            "--tool-axis needs --axis at the points",
        ),  # fmt: skip
        (
            [
                "--robot",
                "scorbot",
                "--from",
                "0.4",
                "0",
                "0.3",
                "--pitch",
                "0.3",
                "--to",
                "0.4",
                "0.1",
                "0.3",
                "--pitch",
                "0.3",
                "--seed-q",
                "0",
                "0",
            ],
            "--seed-q needs 5 values",
        ),  # fmt: skip
        (["--robot", "nosuchrobot", "--from", "0", "0", "0", "--to", "1", "0", "0"], "nosuchrobot"),
    ],
)
def test_bad_input_exits_2_with_one_line(capsys, argv, needle):
    """Bad input: exit 2, one stderr line naming the problem."""
    code, _, err = run_main(capsys, argv + ([] if "--steps" in argv else ["--steps", "5"]))
    assert_one_line_error(code, err, needle)


def test_kin_path_is_a_kin_command():
    """``python -m kin path`` runs the command (exit 2 and one line for a missing --to)."""
    process = run(["path", "--robot", "scorbot", "--from", "0.4", "0", "0.3", "--steps", "3"])
    assert_one_line_error(process.returncode, process.stderr, "--to")


def test_script_shim_names_itself_in_errors(capsys):
    """scripts/path.py is ``kin path`` with its own name: --steps 0 exits 2 with one line."""
    from support.scripts_helper import load_script

    code = call(load_script("path").main, ["--robot", "scorbot", "--steps", "0"])
    _, err = capsys.readouterr()
    assert_one_line_error(code, err, "path.py: error: argument --steps")


def test_kin_path_all_is_sorted_and_exists():
    """kin.path re-exports each name of its sorted __all__."""
    import kin.path

    names = list(kin.path.__all__)
    assert names == sorted(names) and all(hasattr(kin.path, n) for n in names)


def test_unreachable_start_is_valid_json_with_nulls(capsys):
    """A start out of reach: exit 1, stopped_at 0, no joint vectors, null measures (no NaN)."""
    argv = ["--robot", "scorbot", "--steps", "3", "--json", "--time", "--from", "2", "0", "0.3"]
    argv += ["--pitch", "0.3", "--to", "1.2", "0", "0.3", "--pitch", "0.3"]
    code, out, err = run_main(capsys, argv)
    record = json.loads(out)
    assert code == 1 and record["stopped_at"] == 0 and record["q"] == []
    assert record["max_deviation_m"] is None and "NaN" not in out


def test_timing_uses_the_table_velocity_and_acceleration(tmp_path, capsys):
    """rrpr4 with velocity 20 deg/s and acceleration 40 deg/s^2 rows: --time keeps |qd| under them."""
    from support.cli_helper import RRPR4_TOML

    text = RRPR4_TOML.replace("limits = [-150.0, 150.0]", "limits = [-150.0, 150.0]\nvelocity = 20.0\nacceleration = 40.0")  # fmt: skip
    table = tmp_path / "slow.toml"
    table.write_text(text, encoding="utf-8")
    argv = ["--robot", str(table), "--steps", "10", "--unit", "mm", "--time", "--dt", "0.002"]
    argv += ["--from", "250", "100", "150", "--to", "250", "200", "150", "--json"]
    code, out, err = run_main(capsys, argv)
    assert code == 0, err
    trajectory = json.loads(out)["trajectory"]
    t, qd = np.array(trajectory["t_s"]), np.array(trajectory["qd"])
    assert np.abs(qd[:, :2]).max() <= math.radians(20) * 1.01
    qdd = np.diff(qd[:, :2], axis=0) / np.diff(t)[:, None]
    assert np.abs(qdd).max() <= math.radians(40) * 1.02
    assert np.abs(qd[:, :2]).max() > math.radians(20) * 0.5  # the limits, not defaults, bind
