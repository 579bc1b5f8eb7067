"""A plan's final check and clearance: motions the search showed free are known, others judged.

Judged apart from the shortcuts under test: the clearance against the checker's own
``distance`` (Pinocchio's ``computeDistances`` of every pair), the final check against a path
through a shape that the search never showed free, the memory of shown motions against the
motions put in, and every motion a real plan puts in against the checker's verdicts along it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.sphere_bound import sphere_bound
from kin.plan import plan, planner
from kin.plan.final_check import certified
from kin.plan.ompl_problem import Budget, CertifiedSpace, ShownMotions, exact_rule, joint_bounds

CELL = Path(__file__).resolve().parents[2] / "examples" / "cell.toml"


@pytest.fixture(scope="module")
def ur5():
    robot = load_robot("ur5")
    return robot, CollisionChecker(load_collision_model(robot, scene=CELL))


def test_shown_motions_are_known_either_way_round_and_only_they():
    shown = ShownMotions()
    a, b, c = np.array([0.0, 1.0]), np.array([0.5, -1.0]), np.array([0.5, -1.0 + 1e-15])
    shown.add(a, b)
    assert shown.holds(a, b) and shown.holds(b, a)
    assert not shown.holds(a, c) and not shown.holds(b, c)  # bit for bit, not "close"


def test_the_smallest_distance_is_the_checkers(ur5):
    """At 500 random configurations, free and colliding, the bounded search gives the value of
    the checker's distance over every pair, to the bit."""
    robot, checker = ur5
    rng = np.random.default_rng(8)
    qs = rng.uniform(-np.pi, np.pi, (500, robot.nq))
    below = sphere_bound(checker.model).lower_bounds(qs)
    measured = exact_rule(checker).helper.measured
    before = measured.exact_pairs
    for q, bounds in zip(qs, below):
        assert measured.smallest(q, bounds) == checker.distance(q).distance, q
    assert measured.exact_pairs - before < 0.5 * len(qs) * measured.count  # most pairs skipped


def test_a_plans_clearance_is_the_checkers_at_its_joint_vectors(ur5):
    robot, checker = ur5
    start, goal = (
        np.array([-1.2, -1.3, 1.4, -1.6, -1.5, 0.0]),
        np.array([2.0, -1.2, 1.2, -1.6, -1.5, 0.3]),
    )
    result = plan(robot, start, goal, collisions=checker, seed=2, time_limit=math.inf)
    assert result.status == "ok" and len(result.path) > 2, result.message
    assert result.clearance == min(checker.distance(q).distance for q in result.path)


def test_a_motion_never_shown_free_is_judged_by_the_final_check(ur5):
    """A two-point path through the wall: its motion is not among the shown ones, so the final
    check judges it (the exact rule) and refuses it; once marked shown, it is taken as known."""
    robot, checker = ur5
    start, goal = (
        np.array([-1.2, -1.3, 1.4, -1.6, -1.5, 0.0]),
        np.array([2.0, -1.2, 1.2, -1.6, -1.5, 0.3]),
    )
    assert checker.in_collision_batch(start + np.linspace(0, 1, 50)[:, None] * (goal - start)).any()
    path = np.array([start, goal])
    lower, upper = joint_bounds(robot, path)
    space = CertifiedSpace(checker, lower, upper, Budget(1000, math.inf))
    goals = planner.joint_goal(robot, goal, checker)

    def answer(status, message, **fields):
        return status, message

    status, message = certified(checker, path, goals, space.budget, answer, space)
    assert status == "not_found" and "final check" in message
    space.shown.add(start, goal)  # the memory is trusted: only the search puts motions there
    status, _ = certified(checker, path, goals, space.budget, answer, space)
    assert status == "ok"


def test_every_motion_the_search_marks_shown_is_free_at_every_sampled_point(ur5, monkeypatch):
    """What makes the final check's trust sound: the rules put only free motions in the memory.

    Every motion a real plan marks shown (the spheres' rule and the exact one, through the cell's
    wall) is sampled at 200 evenly spaced points and judged by the checker's own batch verdict
    (coal on every pair): none may collide.
    """
    robot, checker = ur5
    marked: list[tuple[np.ndarray, np.ndarray]] = []
    add = ShownMotions.add

    def recorded(self, q0, q1):
        marked.append((np.array(q0, dtype=float), np.array(q1, dtype=float)))
        add(self, q0, q1)

    monkeypatch.setattr(ShownMotions, "add", recorded)
    start, goal = (
        np.array([-1.2, -1.3, 1.4, -1.6, -1.5, 0.0]),
        np.array([2.0, -1.2, 1.2, -1.6, -1.5, 0.3]),
    )
    for seed in range(3):
        result = plan(robot, start, goal, collisions=checker, seed=seed, time_limit=math.inf)
        assert result.status == "ok", result.message
    assert len(marked) > 20, len(marked)  # the search showed many motions free
    s = np.linspace(0.0, 1.0, 200)[:, None]
    for q0, q1 in marked:
        assert not checker.in_collision_batch(q0 + s * (q1 - q0)).any(), (q0, q1)
