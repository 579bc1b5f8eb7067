"""The limit rule (kin.ik.limit_rule): one rule for the single call, solve_batch and the C twins.

The rule is checked against a brute force over many ``2 pi`` copies written here; the solvers
against each other on the same targets, random angles and random seeds inside the limits.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kin import Configuration, load_robot
from kin.ik import PoseTarget, solve_batch
from kin.ik.analytic.batch import BatchSolver
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.limit_rule import (
    LIMIT_TOL,
    nearest_copies,
    nearest_copy,
    nearest_inside,
    turn_copies,
    wrap_into,
)


def _brute_force(value: float, seed: float, lower: float, upper: float) -> tuple[float, bool]:
    """The copy ``value + 2 pi k`` (|k| <= 12) inside the limits nearest ``seed``, else the least outside."""
    best, best_key = math.nan, (math.inf, math.inf)
    for k in range(-12, 13):
        copy = value + 2.0 * math.pi * k
        violation = max(lower - LIMIT_TOL - copy, copy - upper - LIMIT_TOL, 0.0)
        if (violation, abs(copy - seed)) < best_key:
            best, best_key = copy, (violation, abs(copy - seed))
    return best, best_key[0] == 0.0


def _cases(n: int, seed: int) -> tuple[np.ndarray, ...]:
    """Random angles [rad] up to +-20, limits of spans 0.5 to 4 pi, seeds around the limits."""
    rng = np.random.default_rng(seed)
    middle = rng.uniform(-1.0, 1.0, n)
    span = rng.uniform(0.5, 4.0 * math.pi, n)
    lower, upper = middle - span / 2, middle + span / 2
    seeds = rng.uniform(lower - 0.5, upper + 0.5)
    values = rng.uniform(-20.0, 20.0, n)
    return values, seeds, lower, upper


def test_every_form_of_the_rule_gives_the_brute_force_copy():
    """nearest_copy, wrap_into, nearest_copies and nearest_inside: the brute force's copy."""
    values, seeds, lower, upper = _cases(4000, seed=1)
    array_q, array_inside = nearest_copies(values, seeds, lower, upper)
    inside_count = 0
    for i, (v, s, lo, hi) in enumerate(zip(values, seeds, lower, upper)):
        expected, inside = _brute_force(v, s, lo, hi)
        inside_count += inside
        for got, ok in (nearest_copy(v, s, lo, hi), wrap_into(v, s, lo, hi)):
            assert ok == inside and abs(got - expected) < 1e-12, (v, s, lo, hi)
        assert array_inside[i] == inside and abs(array_q[i] - expected) < 1e-12
        assert nearest_inside(v, s, lo, hi) == (array_q[i] if inside else None)
    assert 0 < inside_count < len(values)  # both cases met


def test_an_angle_a_hair_outside_a_limit_counts_as_inside():
    """Within LIMIT_TOL of a limit: inside, unchanged; NaN: outside, NaN."""
    assert nearest_copy(1.0 + 0.5 * LIMIT_TOL, 0.0, -1.0, 1.0) == (1.0 + 0.5 * LIMIT_TOL, True)
    assert nearest_copy(1.0 + 2 * LIMIT_TOL, 0.0, -1.0, 1.0)[1] is False
    q, inside = nearest_copies([[math.nan, 0.5]], [[0.0, 0.0]], [-1.0, -1.0], [1.0, 1.0])
    assert math.isnan(q[0, 0]) and q[0, 1] == 0.5 and inside.tolist() == [[False, True]]


@pytest.mark.parametrize("name", ["ur5", "puma560"])
def test_single_call_batch_and_twin_move_branches_alike(name):
    """Random poses and seeds: the twin, the Python single call and both batches, same q."""
    robot = load_robot(name)
    configuration = Configuration(robot)
    rng = np.random.default_rng(7)
    n = 60
    qs = rng.uniform(robot.lower, robot.upper, size=(n, robot.nq))
    seeds = rng.uniform(robot.lower, robot.upper, size=(n, robot.nq))
    poses = np.array([configuration.fk(q).homogeneous for q in qs])
    twin, python = ClosedFormSolver(robot), ClosedFormSolver(robot, compiled=False)
    branches = BatchSolver(robot).solve_poses(poses, seeds)
    batch = solve_batch(robot, poses[:, :3, 3], poses[:, :3, :3], seeds)
    labels = branches.branch_names
    compared = 0
    for i in range(n):
        target = PoseTarget(poses[i, :3, 3], poses[i, :3, :3])
        answers = [solver.solve(target, seeds[i]) for solver in (twin, python)]
        for result in answers:
            assert result.success and bool(batch.success[i]), (name, i)
            assert np.allclose(result.solutions[0].q, batch.q[i], atol=1e-8), (name, i)
            for solution in result.solutions + result.rejected:
                b = labels.index(solution.branch)
                assert bool(branches.within_limits[i, b]) == solution.within_limits, (name, i)
                assert np.allclose(solution.q, branches.q[i, b], atol=1e-8), (name, i)
                compared += 1
    assert compared >= 2 * n * 4


def test_turn_copies_are_the_brute_force_nearest_inside():
    """``turn_copies``: the value and the copies within the limits nearest ``near``, against a
    brute force over |k| <= 12; never more than ``most``; hostile values give the value alone."""
    rng = np.random.default_rng(12)
    for _ in range(2000):
        lower = rng.uniform(-4 * math.pi, 0.0)
        upper = lower + rng.uniform(0.0, 8 * math.pi)
        value, near = rng.uniform(lower, upper), rng.uniform(lower, upper)
        most = int(rng.integers(1, 5))
        found = turn_copies(value, lower, upper, near, most)
        inside = [
            value + 2 * math.pi * k
            for k in range(-12, 13)
            if k != 0 and lower - LIMIT_TOL <= value + 2 * math.pi * k <= upper + LIMIT_TOL
        ]
        inside.sort(key=lambda c: abs(c - near))
        assert found[0] == value and len(found) <= most
        assert found[1:] == pytest.approx(inside[: most - 1], abs=0.0), (value, lower, upper, near)
    assert turn_copies(0.5, -math.inf, math.inf, 0.0) == [0.5]
    assert turn_copies(0.5, -1e300, 1e300, 0.0, 3) == [0.5, 0.5 - 2 * math.pi, 0.5 + 2 * math.pi]
    copies = turn_copies(math.nan, -1.0, 1.0, 0.0)
    assert len(copies) == 1 and math.isnan(copies[0])
