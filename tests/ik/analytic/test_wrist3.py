"""Three revolute axes through one point (a wrist alone) in closed form: ``closed_form:wrist3``.

The tables are small inline wrists (Valkyrie's forearm model has that shape: yaw, roll, pitch
through one centre). Targets are the FK of random joint vectors inside the limits; every returned
branch is measured by the plain NumPy DH product of the table (:mod:`dh_reference`), and the
original joint vector must be among the branches.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle

from dh2urdf import load_table
from kin import load_robot
from kin.ik import PoseTarget, PositionTarget, get_solver
from kin.ik.analytic.three_joint.wrist3 import Wrist3, rotation_pair
from kin.ik.exceptions import StructureError

WRIST = """
name = "{name}"
convention = "standard"
length_unit = "m"
angle_unit = "deg"
[[joints]]
name = "yaw"
type = "revolute"
a = 0.0
alpha = 90.0
d = 0.3
theta = 0.0
limits = [-170.0, 170.0]
[[joints]]
name = "roll"
type = "revolute"
a = 0.0
alpha = 90.0
d = 0.0
theta = -90.0
limits = [-60.0, 60.0]
[[joints]]
name = "pitch"
type = "revolute"
a = 0.0
alpha = 0.0
d = {d3}
theta = 0.0
limits = [-80.0, 80.0]
"""


def _wrist(tmp_path: Path, d3: float, name: str = "wrist") -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(WRIST.format(name=name, d3=d3))
    return path


@pytest.mark.parametrize("d3", [0.0, 0.12])
def test_every_pose_is_solved_with_its_joint_vector_among_the_branches(tmp_path, d3):
    """300 FK poses (tool on the centre, and 0.12 m off it): 100 %, each branch on target."""
    path = _wrist(tmp_path, d3)
    robot = load_robot(path)
    reference = load_reference(path)
    solver = get_solver(robot)
    assert solver.name == "closed_form:wrist3"
    rng = np.random.default_rng(5)
    for q in rng.uniform(robot.lower, robot.upper, size=(300, 3)):
        tool = fk_frames(reference, q)[0, -1]
        result = solver.solve(PoseTarget(tool[:3, 3], tool[:3, :3]), np.zeros(3))
        assert result.success and result.method == "closed_form", f"{q=} {result.message}"
        for solution in result.solutions:
            reached = fk_frames(reference, solution.q)[0, -1]
            assert np.linalg.norm(reached[:3, 3] - tool[:3, 3]) < 1e-9, f"{q=}"
            assert rotation_angle(reached[:3, :3], tool[:3, :3]) < 1e-9, f"{q=}"
        assert min(np.abs(s.q - q).max() for s in result.solutions) < 1e-8, f"{q=}"


def test_both_sides_of_the_wrist_without_limits():
    """Unlimited joints: two branches per pose, distinct, both on target (independent FK)."""
    u1, u2 = (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)
    rng = np.random.default_rng(1)
    for _ in range(100):
        p = rng.normal(size=3)
        p = tuple(p / np.linalg.norm(p))
        q1, q2 = rng.uniform(-math.pi, math.pi, size=2)
        rot = lambda axis, angle: _rotation(np.array(axis), angle)  # noqa: E731
        d = tuple(rot(u1, q1) @ rot(u2, q2) @ np.array(p))
        pairs = rotation_pair(u1, u2, p, d)
        assert len(pairs) == 2
        for a, b in pairs:
            assert np.allclose(rot(u1, a) @ rot(u2, b) @ np.array(p), d, atol=1e-12)
        assert any(abs(math.remainder(a - q1, 2 * math.pi)) < 1e-9 for a, _ in pairs)


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' formula (independent of the code under test)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def test_a_position_on_the_centre_keeps_the_seed_and_says_so(tmp_path):
    """The tool on the centre: every joint vector reaches it; the answer is the seed, stated."""
    path = _wrist(tmp_path, 0.0)
    robot = load_robot(path)
    centre = fk_frames(load_reference(path), np.zeros(3))[0, -1][:3, 3]
    seed = np.array([0.3, -0.2, 0.1])
    result = get_solver(robot).solve(PositionTarget(centre), seed)
    assert result.success, result.message
    assert np.allclose(result.solutions[0].q, seed)
    assert "every joint free" in result.solutions[0].branch
    away = get_solver(robot).solve(PositionTarget(centre + [0.0, 0.0, 0.01]), seed)
    assert not away.success and away.status == "out_of_reach", away.status


def test_a_position_off_the_centre_keeps_joint_3(tmp_path):
    """The tool off the centre: joint 3 keeps the seed's value, the branches reach the point."""
    path = _wrist(tmp_path, 0.12)
    robot = load_robot(path)
    reference = load_reference(path)
    rng = np.random.default_rng(9)
    solved = 0
    for q in rng.uniform(robot.lower, robot.upper, size=(100, 3)):
        point = fk_frames(reference, q)[0, -1][:3, 3]
        result = get_solver(robot).solve(PositionTarget(point), q * [0.0, 0.0, 1.0])
        solved += result.success
        for s in result.solutions:
            assert np.linalg.norm(fk_frames(reference, s.q)[0, -1][:3, 3] - point) < 1e-9
            assert math.isclose(s.q[2], q[2], abs_tol=1e-12) and "joint 3 free" in s.branch
    assert solved == 100


def test_axes_that_do_not_meet_are_not_a_wrist(tmp_path):
    """An offset between the axes is named in the refusal."""
    path = tmp_path / "offset.toml"
    path.write_text(
        _wrist(tmp_path, 0.0)
        .read_text()
        .replace("a = 0.0\nalpha = 90.0\nd = 0.0", "a = 0.05\nalpha = 90.0\nd = 0.0")
    )
    with pytest.raises(StructureError, match="do not meet"):
        Wrist3(load_table(path))
