"""`kin ik`: JSON in SI, units rule (mm, deg, prismatic), target-kind errors, solver choice."""

from __future__ import annotations

import json

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import assert_one_line_error, call, run, write_rrpr4
from support.dh_reference import fk_frames, load_reference

from kin import Configuration, load_robot
from kin.commands import ik
from kin.commands.solver_choice import NewtonRaphsonSolver, choose_solver, solve_function
from kin.ik import IKResult, PositionTarget

Q7 = np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2])


def _json(capsys, argv: list[str], code: int = 0) -> dict:
    assert ik.main(argv) == code, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def test_humanoid7_full_pose_json_is_si_and_on_target(capsys):
    """Full pose in cm: success, q (rad) puts the tool on the pose; keys carry their units."""
    robot = load_robot("humanoid7")
    pose = Configuration(robot).fk(Q7)
    rpy = pin.rpy.matrixToRpy(pose.rotation)
    argv = ["--robot", "humanoid7", "--target", *map(repr, (pose.translation * 100).tolist())]
    out = _json(capsys, [*argv, "--unit", "cm", "--rpy", *map(repr, rpy.tolist()), "--json"])
    assert out["success"] and out["q_units"] == ["rad"] * 7 and "unit" not in out
    assert out["time_s"] > 0 and out["iterations"] >= 0 and isinstance(out["method"], str)
    solution = out["solutions"][0]
    reached = Configuration(robot).fk(np.array(solution["q"]))
    np.testing.assert_allclose(reached.translation, pose.translation, atol=1e-5)
    np.testing.assert_allclose(reached.rotation, pose.rotation, atol=1e-4)
    assert solution["position_error_m"] < 1e-5 and solution["rotation_error_rad"] < 1e-4


def test_negative_scientific_target_works(capsys):
    """`--target -1.2e-16 0.5 0.3`: read as numbers, a verified position solution."""
    out = _json(capsys, ["--robot", "humanoid7", "--target", "-1.2e-16", "0.5", "0.3", "--json"])
    assert out["success"]
    reached = Configuration(load_robot("humanoid7")).fk(np.array(out["solutions"][0]["q"]))
    np.testing.assert_allclose(reached.translation, [-1.2e-16, 0.5, 0.3], atol=1e-5)
    assert out["solutions"][0]["rotation_error_rad"] is None


def test_position_target_rotation_error_is_null(capsys):
    """A position target does not constrain the rotation: rotation_error_rad is null."""
    out = _json(
        capsys, ["--robot", "pickplace3", "--target", "390", "80", "300", "--unit", "mm", "--json"]
    )
    assert [s["rotation_error_rad"] for s in out["solutions"] + out["rejected"]] == [None] * 4
    assert out["solver"].startswith("closed_form") and out["q_units"] == ["rad"] * 3


def test_mm_deg_text_equals_json_radians(capsys):
    """pickplace3 in mm / deg: the text rows are the JSON radians in degrees (003 Table 5)."""
    argv = ["--robot", "pickplace3", "--target", "390", "80", "300", "--unit", "mm", "--all"]
    out = _json(capsys, [*argv, "--json"])
    assert ik.main([*argv, "--deg"]) == 0
    text = capsys.readouterr().out.splitlines()
    assert "waist [deg]" in text[2] and "pos.err [mm]" in text[2] and "rot.err [rad]" in text[2]
    assert text[1].startswith("iterations: 0, time: ") and text[1].endswith(" ms")
    rows = [line.split(",", 1)[1].split()[2:5] for line in text[3:]]
    q_deg = np.array([[float(v) for v in row] for row in rows])
    q_json = np.array([s["q"] for s in out["solutions"] + out["rejected"]])
    np.testing.assert_allclose(q_deg, np.degrees(q_json), atol=1e-4)
    assert "10.1529" in text[3] and sum("OUT" in line for line in text) == 2


def test_round_trip_fk_mm_deg_to_ik(capsys):
    """scorbot: `kin fk` in mm/deg, its pose back through `kin ik --rpy` in mm/deg gives q."""
    from kin.commands import fk

    q_deg = [20.0, -30.0, 40.0, -50.0, 60.0]
    assert fk.main(["--robot", "scorbot", "--q", *map(str, q_deg), "--deg", "--json"]) == 0
    pose = json.loads(capsys.readouterr().out)
    rpy = np.degrees(pin.rpy.matrixToRpy(np.array(pose["rotation"])))
    argv = [
        "--robot",
        "scorbot",
        "--target",
        *map(repr, (np.array(pose["position_m"]) * 1000).tolist()),
    ]
    argv += ["--unit", "mm", "--deg", "--rpy", *map(repr, rpy.tolist()), "--json"]
    argv += ["--seed-q", *map(str, q_deg)]
    out = _json(capsys, argv)
    np.testing.assert_allclose(out["solutions"][0]["q"], np.radians(q_deg), atol=1e-9)


def test_prismatic_seed_and_answer_in_mm(tmp_path, capsys):
    """A prismatic joint: --seed-q in mm, the slide printed in mm, the tool on target (NumPy DH)."""
    path = write_rrpr4(tmp_path)
    argv = ["--robot", str(path), "--target", "300", "100", "100", "--unit", "mm", "--deg"]
    argv += ["--solver", "nr", "--seed-q", "10", "10", "50", "0"]
    out = _json(capsys, [*argv, "--json"])
    q = np.array(out["solutions"][0]["q"])
    assert out["q_units"] == ["rad", "rad", "m", "rad"]
    np.testing.assert_allclose(q[2], 0.130, atol=1e-9)  # 300 - 20 - q3 - 50 = 100 mm
    reached = fk_frames(load_reference(path), q)[0, -1, :3, 3]
    np.testing.assert_allclose(reached, [0.3, 0.1, 0.1], atol=1e-7)
    assert ik.main(argv) == 0
    text = capsys.readouterr().out.splitlines()
    assert "slide [mm]" in text[2] and "shoulder [deg]" in text[2]
    assert f"{q[2] * 1000:.4f}" in text[3] and f"{np.degrees(q[1]):.4f}" in text[3]


def test_solver_choice():
    """--solver nr and mink force their solver; by default the robot's own."""
    robot = load_robot("humanoid7")
    assert isinstance(choose_solver(robot, "nr"), NewtonRaphsonSolver)
    assert type(choose_solver(robot, "mink")).__name__ == "NumericIK"
    assert choose_solver(load_robot("pickplace3")).name.startswith("closed_form")


def test_solve_function_passes_the_budget_and_all_branches():
    """The time budget [s] and ``all_branches`` reach the solve (one interface, no sniffing)."""
    seen = []

    class Fake:
        def solve(self, target, seed=None, *, timeout=None, all_branches=False):
            seen.append((timeout, all_branches))
            return IKResult(True, "fake", "ok", "")

    target = PositionTarget([0, 0, 0])
    solve_function(Fake(), 0.25)(target, None)
    solve_function(Fake(), None, all_branches=True)(target, None)
    assert seen == [(0.25, False), (None, True)]


def test_nr_reports_the_limits(capsys):
    """--solver nr reaches Table IX case 1 outside the limits: exit 1, its q in rejected."""
    argv = ["--robot", "humanoid7", "--target", "-37.457", "-2.759", "18.861", "--unit", "cm"]
    out = _json(capsys, [*argv, "--solver", "nr", "--json"], code=1)
    assert out["status"] == "outside_limits" and out["solver"] == "nr"
    assert out["rejected"][0]["position_error_m"] < 1e-7


@pytest.mark.parametrize(
    "argv, needle",
    [
        (
            ["--robot", "pickplace3", "--target", "0.3", "0", "0.3", "--mask", "1", "1", "1", "0"]
            + ["0", "1"],
            "--mask needs --rpy or --quat",
        ),
        (
            ["--robot", "planar2", "--target", "0.3", "0", "0", "--quat", "1", "0", "0", "0"]
            + ["--mask", "1", "1", "1", "0", "0", "2"],
            "--mask must be 6 flags 0 or 1",
        ),
        (
            ["--robot", "pickplace3", "--target", "0.3", "0", "0.3", "--pitch", "0"],
            "'pickplace3' (3 joints) takes: --rpy, --quat, --axis, or a position target; got --pitch",
        ),
        (
            ["--robot", "humanoid7", "--target", "0.4", "0", "0", "--pitch", "1"],
            "'humanoid7' (7 joints) takes: --rpy, --quat, --axis, or a position target; got --pitch",
        ),
        (
            ["--robot", "ur5", "--target", "0.4", "0", "0", "--axis", "0", "0", "0"],
            "axis must be a nonzero direction",
        ),
        (
            ["--robot", "humanoid7", "--target", "0.4", "0", "0", "--seed-q", "1", "2"],
            "--seed-q needs 7 values for 'humanoid7' (shoulder_yaw [rad], shoulder_pitch [rad]",
        ),
        (["--robot", "lab5", "--target", "1", "2"], "expected 3 arguments"),
        (["--robot", "lab5", "--target", "1", "nan", "3", "--pitch", "0"], "not a finite number"),
        (["--robot", "lab5", "--target", "1", "2", "3", "--unit", "km"], "invalid choice"),
        (["--robot", "nope", "--target", "1", "2", "3"], "known robots: humanoid7"),
        (["--robot", "lab5", "--target", "0.2", "0", "0.2", "--roll", "1"], "--roll needs --pitch"),
        (
            ["--robot", "humanoid7", "--target", "0.5", "0", "0", "--quat", "0", "0", "0", "0"],
            "zero",
        ),
        (
            [
                "--robot",
                "humanoid7",
                "--target",
                "0.5",
                "0",
                "0",
                "--position-only",
                "--rpy",
                "0",
                "0",
                "0",
            ],
            "--position-only excludes --rpy",
        ),
        (
            [
                "--robot",
                "humanoid7",
                "--target",
                "0.5",
                "0",
                "0",
                "--quat",
                "1",
                "0",
                "0",
                "0",
                "--rpy",
                "0",
                "0",
                "0",
            ],
            "give one of --rpy, --quat, --axis, --pitch",
        ),
        (
            [
                "--robot",
                "humanoid7",
                "--target",
                "0.5",
                "0",
                "0",
                "--solver",
                "nr",
                "--rpy",
                "0",
                "0",
                "0",
            ],
            "--solver nr is the paper's position-only method",
        ),
        (
            ["--robot", "humanoid7", "--target", "0.4", "0.2", "-0.1", "--timeout", "-5"],
            "must be positive",
        ),
        (["--robot", "humanoid7"], "--target (or --stdin)"),
        (["--robot", "humanoid7", "--stdin", "--target", "0", "0", "0"], "drop --target"),
    ],
)
def test_bad_input_exits_2_with_one_line(argv, needle, capsys):
    """Bad input to `kin ik`: exit 2, exactly one stderr line in CLI terms, no traceback."""
    assert_one_line_error(call(ik.main, argv), capsys.readouterr().err, needle)
    assert capsys.readouterr().out == ""


def test_bad_kind_in_a_subprocess_has_no_class_names():
    """Through `python -m kin ik`: one line, no internal class names (PoseTarget, ...)."""
    done = run(["ik", "--robot", "pickplace3", "--target", "0.3", "0", "0.3", "--pitch", "0"])
    assert_one_line_error(
        done.returncode, done.stderr, "kin ik: error: 'pickplace3' (3 joints) takes"
    )
    assert "Target" not in done.stderr and "closed_form" not in done.stderr


def test_script_shim_runs_the_command():
    """`python scripts/solve_ik.py --robot humanoid7 --target ...` still works, same options."""
    import subprocess
    import sys
    from pathlib import Path

    script = Path(__file__).resolve().parents[2] / "scripts" / "solve_ik.py"
    argv = ["--robot", "humanoid7", "--target", "40", "20", "-10", "--unit", "cm", "--json"]
    done = subprocess.run([sys.executable, str(script), *argv], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    q = np.array(json.loads(done.stdout)["solutions"][0]["q"])
    reached = Configuration(load_robot("humanoid7")).fk(q).translation
    np.testing.assert_allclose(reached, [0.4, 0.2, -0.1], atol=1e-5)
    bad = subprocess.run(
        [sys.executable, str(script), "--robot", "humanoid7"], capture_output=True, text=True
    )
    assert_one_line_error(bad.returncode, bad.stderr, "solve_ik.py: error:")


def test_kind_message_lists_every_kind_in_cli_terms():
    """A solver taking poses and pitch targets but not positions: all named, in CLI terms."""
    from kin.commands.targets import build_target, check_kind
    from kin.ik import PitchTarget, PoseTarget
    from kin.ik.exceptions import TargetError

    target, given = build_target([0.2, 0, 0.1])
    with pytest.raises(TargetError) as caught:
        check_kind("arm5", 5, (PoseTarget, PitchTarget), target, given)
    assert str(caught.value) == (
        "'arm5' (5 joints) takes: --rpy, --quat, or --pitch [--roll]; got a position target"
    )
    check_kind("ned5", 5, (PoseTarget, PitchTarget, PositionTarget), target, given)  # no error


def test_five_joint_arm_takes_a_position_target(capsys):
    """ned5 with a position target: its solver answers, the tool is on the point."""
    out = _json(capsys, ["--robot", "ned5", "--target", "20", "0", "10", "--unit", "cm", "--json"])
    assert out["success"] and out["solutions"][0]["rotation_error_rad"] is None
    reached = Configuration(load_robot("ned5")).fk(np.array(out["solutions"][0]["q"]))
    np.testing.assert_allclose(reached.translation, [0.2, 0.0, 0.1], atol=1e-5)


@pytest.mark.parametrize("start", [None, ["0", "-1", "1", "0", "0", "0"]])
def test_kin_ik_and_preview_ik_agree_from_the_same_start(start, capsys, tmp_path):
    """ur5 position target: `kin ik` (default start q = 0) and `kin preview --ik` (--q) agree."""
    from kin.commands import preview

    target = ["--target", "0.4", "0.1", "0.3"]
    seed = [] if start is None else ["--seed-q", *start]
    answer = _json(capsys, ["--robot", "ur5", *target, *seed, "--json"])
    q_ik = np.array(answer["solutions"][0]["q"])
    html = tmp_path / "p.html"
    q_flag = [] if start is None else ["--q", *start]
    assert preview.main(["--robot", "ur5", *target, *q_flag, "--ik", "--html", str(html)]) == 0
    shown = capsys.readouterr().out.split("q = ")[1].split(",")
    q_preview = np.array([float(value.split()[0]) for value in shown])
    np.testing.assert_allclose(q_preview, q_ik, atol=5e-4)  # printed with 4 digits
    reached = Configuration(load_robot("ur5")).fk(q_ik).translation
    np.testing.assert_allclose(reached, [0.4, 0.1, 0.3], atol=1e-5)
