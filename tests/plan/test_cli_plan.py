"""``kin plan``: exit codes (0 a path, 1 none, 2 bad input), JSON in SI, the path files."""

from __future__ import annotations

import csv
import io
import json
import math

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call, run
from support.plan_support import SWING, write_ball

from kin.commands import plan as plan_command
from kin.path.joint_path_file import read_joint_path


@pytest.fixture
def ball(tmp_path):
    return write_ball(tmp_path)


def test_a_plan_around_the_ball_in_json(capsys, ball):
    assert call(plan_command.main, [*SWING, "--scene", ball, "--json", "--seed", "4"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["status"] == "ok" and record["planner"] == "RRTConnect" and record["seed"] == 4
    path = np.array(record["path"])
    assert np.allclose(path[0], np.radians([-90.0, 0.0])) and np.allclose(
        path[-1], [math.pi / 2, 0]
    )
    assert len(path) > 2 and record["q_units"] == ["rad", "rad"]
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1).sum()
    assert math.isclose(record["length"], steps, rel_tol=1e-12)
    assert record["clearance_m"] > 0 and record["checks"] > 0


def test_text_names_the_status_and_the_joint_vectors_in_degrees(capsys, ball):
    assert call(plan_command.main, [*SWING, "--scene", ball]) == 0
    out = capsys.readouterr().out
    assert "status: ok" in out and "joint1 [deg]" in out
    assert "  0: -90 0\n" in out


def test_no_path_exits_1_with_the_status(capsys, ball):
    argv = ["--robot", "planar2", "--start", "0", "0", "--goal", "90", "0", "--deg"]
    assert call(plan_command.main, [*argv, "--scene", ball]) == 1
    out = capsys.readouterr().out
    assert "status: start_in_collision" in out and "ball" in out
    assert call(plan_command.main, [*SWING, "--scene", ball, "--max-checks", "3", "--json"]) == 1
    assert json.loads(capsys.readouterr().out)["status"] == "not_found"


def test_a_target_goal(capsys, ball):
    """--target X Y Z: planar2's tool at (0, 0.5) is the arm straight up (+90 deg, 0)."""
    argv = ["--robot", "planar2", "--start", "-90", "0", "--target", "0", "0.5", "0", "--deg"]
    assert call(plan_command.main, [*argv, "--scene", ball, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert np.allclose(record["path"][-1], [math.pi / 2, 0.0], atol=1e-6)


def test_path_files_csv_and_json_with_times(capsys, ball, tmp_path):
    out_json, out_csv = tmp_path / "plan.json", tmp_path / "plan.csv"
    assert call(plan_command.main, [*SWING, "--scene", ball, "--time", "-o", str(out_json)]) == 0
    capsys.readouterr()
    path = read_joint_path(out_json, 2)  # what kin preview --path reads
    assert path.t is not None and path.t[0] == 0.0 and (np.diff(path.t) > 0).all()
    assert call(plan_command.main, [*SWING, "--scene", ball, "--time", "-o", str(out_csv)]) == 0
    rows = list(csv.reader(out_csv.read_text(encoding="utf-8").splitlines()))
    assert rows[0][:4] == ["sample", "t [s]", "joint1 [rad]", "joint2 [rad]"]
    assert len(rows) - 1 == len(path.q)
    assert np.allclose([[float(v) for v in row[2:4]] for row in rows[1:]], path.q)


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--planner", "RRTx"], "--planner"),
        (["--start", "nan", "0"], "--start"),
        (["--goal", "1", "2", "3"], "--goal needs 2 values"),
        (["--goal", "400", "0"], "--goal: joint 'joint1'"),
        (["--start", "-190", "0"], "--start: joint 'joint1'"),
        (["--goal", "1", "nan"], "--goal"),
        (["--start", "0"], "--start needs 2 values"),
        (["--target", "0", "0.5", "0"], "one of them"),
        (["--rpy", "0", "0", "0"], "--rpy"),
        (["--seed", "-1"], "--seed"),
        (["-o", "plan.txt"], "-o"),
    ],
)
def test_bad_input_is_one_line_exit_2(capsys, ball, extra, needle):
    code = call(plan_command.main, [*SWING, "--scene", ball, *extra])
    assert_one_line_error(code, capsys.readouterr().err, needle)


def test_the_output_is_never_an_input(capsys, ball):
    code = call(plan_command.main, [*SWING, "--scene", ball, "-o", ball])
    assert_one_line_error(code, capsys.readouterr().err, "-o")
    assert "sphere" in open(ball, encoding="utf-8").read()


def test_the_console_command_prints_nothing_on_stderr(ball):
    """As a process: exit 0, stdout the answer, stderr empty (OMPL's log and nanobind quiet)."""
    done = run(["plan", *SWING, "--scene", ball, "--json"], module=False)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["status"] == "ok" and done.stderr == ""


def test_no_plan_statuses_exit_1_naming_why(capsys, ball):
    """A goal in the ball (named), a target beyond reach: exit 1, the status in the answer."""
    argv = ["--robot", "planar2", "--start", "-90", "0", "--deg", "--scene", ball, "--json"]
    assert call(plan_command.main, [*argv, "--goal", "0", "0"]) == 1
    record = json.loads(capsys.readouterr().out)
    assert record["status"] == "goal_in_collision" and "ball" in record["message"]
    assert call(plan_command.main, [*argv, "--target", "3", "0", "0"]) == 1
    record = json.loads(capsys.readouterr().out)
    assert record["status"] == "out_of_reach" and record["path"] == []


def test_padding_without_a_scene_pads_the_arm(capsys):
    """--padding alone: UR5's own pairs padded (the start collides with 5 cm, not without); the
    library's checker at the same padding says the same."""
    from kin import load_robot
    from kin.collision import CollisionChecker, load_collision_model

    argv = ["--robot", "ur5", "--start", "0", "-90", "0", "-90", "0", "0", "--deg", "--json"]
    argv += ["--goal", "10", "-90", "0", "-90", "0", "0"]
    assert call(plan_command.main, argv) == 0
    assert json.loads(capsys.readouterr().out)["status"] == "ok"
    assert call(plan_command.main, [*argv, "--padding", "0.05"]) == 1
    record = json.loads(capsys.readouterr().out)
    assert record["status"] == "start_in_collision" and "self:" in record["message"]
    robot = load_robot("ur5")
    q = np.radians([0, -90, 0, -90, 0, 0])
    assert CollisionChecker(load_collision_model(robot, padding=0.05)).in_collision(q)
    assert not CollisionChecker(load_collision_model(robot)).in_collision(q)


def test_named_states_as_start_and_goal(capsys, tmp_path):
    """--start home --goal up (the shipped UR5 table's [states], the maker's MoveIt values) plan
    from and to those joint vectors; a stream line's "start": "home" too; an unknown name is one
    line listing the names there are."""
    home, up = [0.0, -1.5707, 0.0, 0.0, 0.0, 0.0], [0.0, -1.5707, 0.0, -1.5707, 0.0, 0.0]
    argv = ["--robot", "ur5", "--json", "--seed", "1"]
    assert call(plan_command.main, [*argv, "--start", "home", "--goal", "up"]) == 0
    by_name = json.loads(capsys.readouterr().out)
    assert by_name["status"] == "ok"
    np.testing.assert_allclose(by_name["path"][0], home, atol=1e-12)
    np.testing.assert_allclose(by_name["path"][-1], up, atol=1e-12)
    numbers = ["--start", *map(str, home), "--goal", *map(str, up)]
    assert call(plan_command.main, [*argv, *numbers]) == 0
    assert json.loads(capsys.readouterr().out)["path"] == by_name["path"]
    code = call(plan_command.main, [*argv, "--start", "home", "--goal", "nowhere"])
    assert_one_line_error(code, capsys.readouterr().err, "home")


def test_a_stream_line_names_its_start(monkeypatch, capsys):
    lines = [json.dumps({"start": "home", "goal": "up"}), json.dumps({"start": 5, "goal": "up"})]
    monkeypatch.setattr("sys.stdin", io.StringIO("\n".join(lines) + "\n"))
    assert call(plan_command.main, ["--robot", "ur5", "--stdin", "--seed", "1"]) == 1
    first, second = (json.loads(line) for line in capsys.readouterr().out.splitlines())
    assert first["status"] == "ok" and first["path"][0][1] == -1.5707
    assert first["path"][-1][3] == -1.5707
    assert '"start" must be a list of numbers' in second["error"]
