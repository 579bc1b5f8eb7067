"""The parity checks of a 6R family's compiled twin against its NumPy algorithm (a test helper).

Used by the twins of the families' general cases (``test_six_r_family_twins.py``).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

import kin
from kin.ik import ClosedFormSolver, PoseTarget

PI = math.pi


def assert_solve_parity(table, found, label: str) -> None:
    """``solve``: the twin's 8 branches are NumPy's to 1e-10 rad, NaN rows alike, 300 targets.

    1e-10: the twin's libm (and LAPACK) and NumPy's differ in the last bits, grown near a singular
    wrist of random twists to a few 1e-12 rad on a few targets in 300.
    """
    reached = 0
    for T in targets(table, 300, 5):
        numpy = found.solve(T[:3, 3], T[:3, :3], compiled=False)
        twin = found.solve(T[:3, 3], T[:3, :3])
        np.testing.assert_array_equal(np.isnan(twin), np.isnan(numpy), err_msg=label)
        np.testing.assert_allclose(twin, numpy, rtol=0.0, atol=1e-10, equal_nan=True)
        reached += int(not np.isnan(twin[:, 0]).all())
    assert 200 <= reached < 300, f"{label} {reached=}"


def assert_batch_parity(table, found) -> None:
    """``solve_batch``: the twin's ``solve`` of each target, and the NumPy batch to 1e-9 rad."""
    poses = targets(table, 1000, 6)
    p, r = poses[:, :3, 3], poses[:, :3, :3]
    twin, numpy = found.solve_batch(p, r), found.solve_batch(p, r, compiled=False)
    one = np.array([found.solve(p[k], r[k]) for k in range(0, 1000, 7)])
    np.testing.assert_array_equal(twin[::7], one)
    np.testing.assert_array_equal(np.isnan(twin), np.isnan(numpy))
    np.testing.assert_allclose(twin, numpy, rtol=0.0, atol=1e-9, equal_nan=True)
    assert np.isnan(twin[:100]).mean() > 0.5 and not np.isnan(twin[100:, 0]).all()


def assert_solver_parity(table, narrow: bool, label: str) -> None:
    """ClosedFormSolver's compiled path returns what its Python path (Pinocchio judge) returns.

    ``narrow``: random narrow limits, which force the ``2 pi`` copies and rejections; seeds random
    or none.
    """
    rng = np.random.default_rng(17)
    robot = kin.robot_from_table(narrow_limits(table, rng) if narrow else table)
    solvers = ClosedFormSolver(robot), ClosedFormSolver(robot, compiled=False)
    assert solvers[0]._twin is not None and solvers[1]._twin is None
    rejected = 0
    for k, T in enumerate(targets(robot.table, 60, 7)):
        seeds = (None, rng.uniform(-2 * math.pi, 2 * math.pi, 6))
        ours, theirs = (s.solve(PoseTarget(T[:3, 3], T[:3, :3]), seeds[k % 2]) for s in solvers)
        assert_same_result(ours, theirs, f"{label} {narrow=} {k=}")
        rejected += len(ours.rejected)
    assert rejected > 0 or not narrow, "the narrow limits rejected no branch"


def targets(table, count: int, seed: int) -> np.ndarray:
    """FK poses of random q (N, 4, 4), the first tenth moved out of reach (x5 position)."""
    q = np.random.default_rng(seed).uniform(-PI, PI, (count, 6))
    poses = kin.batch_forward_kinematics(table, q)
    poses[: count // 10, :3, 3] *= 5.0
    return poses


def narrow_limits(table, rng: np.random.Generator):
    """The table with joint limits of random width 1.5 to 6 rad around a random centre."""
    rows = []
    for row in table.rows:
        centre, half = rng.uniform(-PI, PI), rng.uniform(0.75, 3.0)
        rows.append(dataclasses.replace(row, lower=centre - half, upper=centre + half))
    return dataclasses.replace(table, rows=tuple(rows))


def assert_same_result(compiled, python, label: str) -> None:
    assert compiled.success == python.success, label
    assert compiled.status == python.status, label
    assert compiled.message == python.message, label
    for ours, theirs in (
        (compiled.solutions, python.solutions),
        (compiled.rejected, python.rejected),
    ):
        assert [s.branch for s in ours] == [s.branch for s in theirs], label
        for a, b in zip(ours, theirs):
            np.testing.assert_allclose(a.q, b.q, rtol=0.0, atol=1e-12, err_msg=label)
            assert a.within_limits == b.within_limits, label
            # Two FKs of the same q: they differ by rounding, which grows with |q| (seeds of 2e5).
            rounding = 1e-12 * max(1.0, float(np.abs(b.q).max()))
            assert abs(a.position_error - b.position_error) < rounding, label
            assert abs(a.rotation_error - b.rotation_error) < rounding, label
