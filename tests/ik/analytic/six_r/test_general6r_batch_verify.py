"""The general 6R batch verified in the compiled twin against the NumPy judge of BatchSolver.

``kin.ik.solve_batch`` of a general 6R arm whose twin is built moves each of the 16 branches
into the limits and measures it in C (``check_branches_n`` of ``kin/_native/ik/analytic/six_r/_six_r_twin.h``,
the 6R twins' verifier widened to 16 branches); ``BatchSolver.solve_poses`` does it in NumPy
(:func:`kin.ik.limit_rule.nearest_copies`, ``batch_forward_kinematics``): the same joint
vectors, the same verdicts (reached, inside the limits), the same errors to 1e-12; tight limits,
a reversed joint and seeds far from zero (several turns) included.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from dh2urdf import load_table
from kin import batch_forward_kinematics, robot_from_table
from kin._native import twin, why_missing
from kin.ik import PoseTarget, solve_batch
from kin.ik.analytic.six_r._general_6r_verify import check_block, verified_batch
from kin.ik.solver_table import vectorized_solver

SIX_R = Path(__file__).parents[3] / "data" / "six_r"
PI = math.pi
pytestmark = pytest.mark.skipif(twin("_general6r") is None, reason=f"{why_missing('_general6r')}")


def _table(name: str, reverse: bool, tight: bool):
    """A maker's table; ``reverse``: joint 3 turns the other way; ``tight``: +-2 rad limits."""
    table = load_table(SIX_R / f"{name}.toml")
    rows = list(table.rows)
    if reverse:
        rows[2] = dataclasses.replace(rows[2], direction=-1)
    if tight:
        rows = [dataclasses.replace(row, lower=-2.0, upper=2.0) for row in rows]
    return dataclasses.replace(table, rows=tuple(rows))


@pytest.mark.parametrize(
    ("name", "reverse", "tight"),
    [("xarm6", False, False), ("jaco2_6dof", True, True), ("crx10ia", False, True)],
)
def test_compiled_verdicts_are_the_numpy_judges(name, reverse, tight):
    """300 poses, seeds zero, random inside the limits and several turns away."""
    robot = robot_from_table(_table(name, reverse, tight))
    solver = vectorized_solver(robot, PoseTarget)
    check = check_block(solver)
    assert check is not None
    rng = np.random.default_rng(8)
    q = rng.uniform(robot.lower, robot.upper, (300, 6))
    poses = batch_forward_kinematics(robot.table, q)
    seeds = rng.uniform(robot.lower, robot.upper, (300, 6))
    seeds[:100] = 0.0
    seeds[100:150] += 2 * PI * rng.integers(-3, 4, (50, 6))
    expected = solver.solve_poses(poses, seeds)
    got = verified_batch(solver, check, poses, seeds)
    label = f"{name=} {reverse=} {tight=}"
    assert got.branch_names == expected.branch_names
    np.testing.assert_array_equal(got.q, expected.q, err_msg=label)
    for verdict in ("reached", "within_limits", "elbow_up"):
        np.testing.assert_array_equal(getattr(got, verdict), getattr(expected, verdict), label)
    for error in ("position_error", "rotation_error"):
        np.testing.assert_allclose(getattr(got, error), getattr(expected, error), atol=1e-12)
    assert expected.valid[:100].any(axis=1).all()  # zero seeds: q (inside) is a valid branch
    assert (~expected.valid & expected.reached).any()  # some branches outside the limits


def test_solve_batch_takes_the_compiled_judge(monkeypatch):
    """kin.ik.solve_batch answers through verified_batch, with the NumPy judge's answers."""
    robot = robot_from_table(_table("xarm6", True, True))
    rng = np.random.default_rng(9)
    q = rng.uniform(robot.lower, robot.upper, (50, 6))
    poses = batch_forward_kinematics(robot.table, q)
    points, frames = poses[:, :3, 3], poses[:, :3, :3]
    compiled = solve_batch(robot, points, frames, q + 0.1)
    from kin.ik import batch_solve

    monkeypatch.setattr(batch_solve, "_compiled_poses", lambda *args: None)
    numpy_judge = solve_batch(robot, points, frames, q + 0.1)
    np.testing.assert_array_equal(compiled.q, numpy_judge.q)
    assert compiled.success.all()
    np.testing.assert_allclose(compiled.q, q, atol=1e-7)  # the nearest the seed: q itself
