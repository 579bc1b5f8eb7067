"""``kin preview --plan FILE.json``: the plan of ``kin plan -o`` animated in its cell.

The page's tool keyframes and trace are checked against Pinocchio's FK of the plan's joint
vectors; a file that is not a plan, or a plan without a path, is one line and exit 2.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call
from support.plan_support import SWING, write_ball
from support.preview_page import (
    animation_tracks,
    cloud_points,
    object_paths,
    page_commands,
    write_page,
)

from kin import Configuration, load_robot
from kin.commands import plan as plan_command
from kin.commands import preview as command

pytest.importorskip("umsgpack")  # comes with meshcat


@pytest.fixture
def ball(tmp_path):
    return write_ball(tmp_path)


def _plan_file(tmp_path, capsys, ball: str, *extra: str) -> tuple[str, dict]:
    """``kin plan ... -o plan.json`` around the ball; the file and its record."""
    file = tmp_path / "plan.json"
    code = call(plan_command.main, [*SWING, "--scene", ball, "-o", str(file), *extra])
    capsys.readouterr()
    assert code == 0
    return str(file), json.loads(file.read_text(encoding="utf-8"))


@pytest.mark.parametrize("timed", [False, True])
def test_the_plan_is_animated_around_the_ball(timed, tmp_path, capsys, ball):
    """Without --robot (the plan's own): tool keyframes from FK(first q) to FK(last q), the trace
    FK of every joint vector, the ball drawn; timed: real time at 30 frames/s."""
    file, plan = _plan_file(tmp_path, capsys, ball, *(["--time"] if timed else []))
    assert len(plan["path"]) > 2  # around the ball, not the straight swing
    commands = page_commands(write_page(tmp_path, capsys, ["--plan", file, "--scene", ball]))
    robot = load_robot("planar2")
    positions = np.array(
        [Configuration(robot, q).transform_frame_to_world("tool").translation for q in plan["path"]]
    )
    keys = np.array(animation_tracks(commands)["/meshcat/scene/frames/tool"])
    np.testing.assert_allclose(keys[0], positions[0], atol=1e-6)
    np.testing.assert_allclose(keys[-1], positions[-1], atol=1e-6)
    np.testing.assert_allclose(positions[-1], [0.0, 0.5, 0.0], atol=1e-9)  # straight up
    frames = int(np.ceil(plan["t"][-1] * 30)) + 1 if timed else len(plan["path"])
    assert len(keys) == frames
    np.testing.assert_allclose(cloud_points(commands, "trace"), positions, atol=1e-6)
    assert any("ball" in path for path in object_paths(commands))


def _written(tmp_path, name: str, record: object) -> str:
    file = tmp_path / name
    file.write_text(json.dumps(record), encoding="utf-8")
    return str(file)


def test_bad_plans_are_one_line_exit_2_and_no_page(tmp_path, capsys, ball):
    """Not JSON, a kin path file, a plan without a path, another robot's plan, no robot."""
    file, plan = _plan_file(tmp_path, capsys, ball)
    files = tmp_path / "in"
    files.mkdir()
    path_file = _written(files, "path.json", {"robot": "planar2", "q": plan["q"]})
    stopped = _written(files, "none.json", {**plan, "status": "not_found", "message": "spent"})
    nameless = _written(files, "nameless.json", {k: v for k, v in plan.items() if k != "robot"})
    page = tmp_path / "out" / "page.html"
    page.parent.mkdir()
    cases = [
        (["--plan", ball], "not JSON"),
        (["--plan", path_file], "(a kin path --json file goes with --path)"),
        (["--plan", stopped], "no path to show (status 'not_found': spent)"),
        (["--plan", file, "--robot", "ur5"], "made for 'planar2', not 'ur5'"),
        (["--plan", nameless], "does not name its robot: give --robot"),
        (["--plan", str(tmp_path / "missing.json")], "no such file"),
        (["--plan", file, "--path", file], "give --plan or --path, not both"),
        ([], "required: --robot (or --plan FILE)"),
    ]
    for argv, needle in cases:
        code = call(command.main, [*argv, "--html", str(page)])
        assert_one_line_error(code, capsys.readouterr().err, needle)
    assert list(page.parent.iterdir()) == []
