"""MotionCheck.between(first=False): the planner's question (free or not), the same verdict.

Judged apart from the mode under test: against the first-contact search of the same rule (which
``kin path`` and its tests hold to a coal reference), and against the checker's own verdict at a
dense resample of each motion (a motion called free has no sample in contact; a motion called
colliding is named at a joint vector the checker calls in contact, or not proven apart).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.path.collision_check import MotionCheck

CELL = Path(__file__).resolve().parents[2] / "examples" / "cell.toml"


@pytest.fixture(scope="module")
def ur5():
    robot = load_robot("ur5")
    return robot, CollisionChecker(load_collision_model(robot, scene=CELL))


def _motions(robot, checker, count: int, seed: int):
    """Random motions with free ends, at most 3 rad a joint (many cross the cell's shapes)."""
    rng = np.random.default_rng(seed)
    found = []
    while len(found) < count:
        q0 = rng.uniform(-np.pi, np.pi, robot.nq)
        q1 = q0 + rng.uniform(-3.0, 3.0, robot.nq)
        if not (checker.in_collision(q0) or checker.in_collision(q1)):
            found.append((q0, q1))
    return found


def test_any_contact_gives_the_first_contact_verdict_with_less_work(ur5):
    robot, checker = ur5
    first, anyone = MotionCheck(checker, 1e-4), MotionCheck(checker, 1e-4)
    colliding = 0
    first_work = any_work = 0
    for q0, q1 in _motions(robot, checker, 60, 5):
        d0, d1 = first.distances(q0), first.distances(q1)
        before_first, before_any = first.checks, anyone.checks
        by_first = first.between(q0, q1, d0, d1)
        by_any = anyone.between(q0, q1, d0.copy(), d1.copy(), first=False)
        assert (by_first is None) == (by_any is None), (q0, q1)
        samples = q0 + np.linspace(0.0, 1.0, 400)[:, None] * (q1 - q0)
        if by_any is None:  # free: the checker agrees at every sample
            assert not checker.in_collision_batch(samples).any()
            continue
        colliding += 1
        if by_any.proven:  # named where the checker calls it in contact
            assert checker.in_collision(by_any.q)
        first_work += first.checks - before_first
        any_work += anyone.checks - before_any
    assert colliding >= 10  # both kinds were judged
    assert any_work < 0.5 * first_work  # the coarse midpoints catch most contacts at once
