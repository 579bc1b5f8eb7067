"""Paths of partial poses (issue #21): a free tool axis, a masked pose, a pose on a SCARA.

Every sample of the joint path is judged again by the plain NumPy DH product
(``tests/support/dh_reference.py``) on the constrained components.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import call
from support.dh_reference import fk_frames, load_reference

from dh2urdf import get_robot
from kin import load_robot
from kin.commands.path import main as path_main
from kin.ik import AxisTarget, PoseTarget
from kin.path import follow_path, line

COBRA = Path(__file__).parents[1] / "data" / "toolbox" / "cobra600.toml"


def _tools(reference, q: np.ndarray) -> np.ndarray:
    return fk_frames(reference, q)[:, -1]


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_axis_path_keeps_the_axis_on_every_sample(name):
    """A drill moving along a line while tilting: every sample on the line and on its axis."""
    robot = load_robot(name)
    start = AxisTarget([0.4, 0.2, 0.3], [0.0, 0.0, -1.0])
    end = AxisTarget([0.4, -0.2, 0.3], [0.0, 0.3, -1.0])
    path = line(start, end, 20)
    seed = np.array([0.0, -1.57, -1.57, -1.57, 1.57, 0.0]) if name == "ur5" else None
    result = follow_path(robot, path, seed)
    assert result.success, result.message
    tools = _tools(load_reference(get_robot(name).table_path), result.q)
    for i, tool in enumerate(tools):
        target = path.target(i)
        assert np.linalg.norm(tool[:3, 3] - target.position) < 1e-5
        assert math.acos(min(1.0, float(tool[:3, 2] @ target.axis))) < 1e-4
    assert result.max_rotation_error < 1e-4
    assert result.max_joint_step < 0.35


def test_masked_scara_path_and_its_limit():
    """A SCARA path of positions and yaws (tilt free): followed until its slide's limit, verified."""
    robot = load_robot(str(COBRA))
    flip = np.diag([1.0, -1.0, -1.0])
    start = PoseTarget([0.45, 0.2, 0.25], flip, mask=(1, 1, 1, 0, 0, 1))
    end = PoseTarget(
        [0.45, 0.0, 0.2], pin.exp3(np.array([0.0, 0.0, 0.5])) @ flip, mask=(1, 1, 1, 0, 0, 1)
    )
    result = follow_path(robot, line(start, end, 10))
    assert result.success, result.message
    tools = _tools(load_reference(COBRA), result.q)
    for i, tool in enumerate(tools):
        target = result.path.target(i)
        assert np.linalg.norm(tool[:3, 3] - target.position) < 1e-5
        assert abs(pin.log3(target.rotation @ tool[:3, :3].T)[2]) < 1e-4


def test_path_command_takes_axis_points(capsys):
    """kin path --from ... --axis ... --to ... --axis ...: followed (exit 0); --mask alone: exit 2."""
    argv = ["--robot", "ur5", "--from", "0.4", "0.2", "0.1", "--axis", "0", "0", "-1"]
    argv += ["--to", "0.4", "-0.2", "0.1", "--axis", "0", "0.3", "-1", "--steps", "10"]
    argv += ["--seed-q", "0", "-1.57", "-1.57", "-1.57", "1.57", "0"]
    assert call(path_main, argv) == 0
    assert "followed" in capsys.readouterr().out
    bad = ["--robot", "ur5", "--from", "0.4", "0.2", "0.1", "--to", "0.4", "0", "0.1"]
    assert call(path_main, [*bad, "--steps", "3", "--mask", "1", "1", "1", "0", "0", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--mask needs --rpy or --quat" in err
