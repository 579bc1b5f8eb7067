"""The planner's fast checks (kin.path.pair_distances with spheres): same verdicts, same paths.

Judged apart from the code under test: the verdicts against the checker's own
``in_collision`` at random configurations; every path planned with the fast checks against the
exact rule (``check_path_collisions``, no spheres) and against a direct coal check of the URDF
built apart from kin (tests/support/collision_reference.py) at a 0.005 rad resample; and the path itself
against the plan made without the spheres (the same seed must give the same path and checks).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from support.collision_reference import CollisionReference
from support.plan_support import (
    _resampled,  # every configuration of the motions, no joint step > 0.005 rad
)
from support.urdf_reference import erd

import kin
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.requests import CONTACT_TOLERANCE
from kin.path.collision_check import check_path_collisions
from kin.path.pair_distances import PairDistances
from kin.plan import ompl_problem, plan

CELL = Path(__file__).resolve().parents[2] / "examples" / "cell.toml"
BOX = "[[box]]\nname = 'box'\nsize = [0.2, 0.2, 0.2]\nxyz = [0.5, 0.0, 0.3]\n"

#: Plans bounded by work alone: the 10 s default cap was reached on a busy machine by the exact
#: checks' plan and not the fast one ('timeout' against 'not_found'), a verdict of the load.
WORK_ONLY = {"max_checks": 50_000, "time_limit": math.inf}


def _panda(scene: Path):
    robot = kin.load_robot(erd("panda_description/urdf/panda.urdf"), None, "panda_link8")
    model = load_collision_model(robot, srdf=erd("panda_description/srdf/panda.srdf"), scene=scene)
    path, base, _ = robot.urdf_source
    text = Path(path).read_text(encoding="utf-8")
    reference = CollisionReference(text, Path(path), robot.joint_names, base, scene)
    return robot, CollisionChecker(model), reference, list(model.pairs)


def _ur5():
    robot = kin.load_robot("ur5")
    model = load_collision_model(robot, scene=CELL)
    reference = CollisionReference(robot.urdf, None, robot.joint_names, None, CELL)
    pairs = [(link, obj) for link in reference.links for obj in reference.scene_names]
    pairs += [p for p in model.pairs if p[1] not in reference.scene_names]
    return robot, CollisionChecker(model), reference, pairs


@pytest.fixture(scope="module")
def cells(tmp_path_factory):
    box = tmp_path_factory.mktemp("fast") / "box.toml"
    box.write_text(BOX, encoding="utf-8")
    return {"panda": _panda(box), "ur5": _ur5()}


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_the_fast_verdict_is_the_checkers(cells, name):
    """At 2,000 random configurations the fast verdict is in_collision's, and the spheres
    decide most free ones without coal."""
    robot, checker, _, _ = cells[name]
    fast = PairDistances(checker, fast=True)
    rng = np.random.default_rng(3)
    free = 0
    for q in rng.uniform(robot.lower, robot.upper, (2000, robot.nq)):
        verdict = checker.in_collision(q)
        fast.at(q)  # the bounds at q: the verdict is theirs, coal only where they fail
        assert fast.in_collision(q) == verdict, q
        free += not verdict
    assert free > 200
    assert fast.exact_pairs < 0.5 * 2000 * fast.count  # coal asked of a fraction of the pairs


PROBLEMS = {
    # around the box in front of Panda
    "panda": ([-1.0, 0.3, 0.0, -1.8, 0.0, 2.0, 0.8], [1.0, 0.3, 0.0, -1.8, 0.0, 2.0, 0.8]),
    # the straight pan crosses the wall (test_plan's UR5 cell)
    "ur5": ([-1.2, -1.3, 1.4, -1.6, -1.5, 0.0], [2.0, -1.2, 1.2, -1.6, -1.5, 0.3]),
}


@pytest.mark.parametrize("name", ["panda", "ur5"])
@pytest.mark.parametrize("seed", [0, 1])
def test_fast_plans_are_the_exact_plans_and_certified(cells, name, seed, monkeypatch):
    """(c) With the spheres from the first check: the path and checks of the exact plan; the
    exact rule and the reference at a 0.005 rad resample find it free."""
    robot, checker, reference, pairs = cells[name]
    start, goal = (np.array(v) for v in PROBLEMS[name])
    monkeypatch.setattr(ompl_problem, "FAST_AFTER", 10**9)  # never: the exact checks
    exact = plan(robot, start, goal, collisions=checker, seed=seed, time_limit=math.inf)
    monkeypatch.setattr(ompl_problem, "FAST_AFTER", 0)  # the spheres from the first check
    fast = plan(robot, start, goal, collisions=checker, seed=seed, time_limit=math.inf)
    assert fast.status == exact.status == "ok", fast.message
    assert np.array_equal(fast.path, exact.path) and fast.checks == exact.checks
    assert len(fast.path) > 2  # it went around
    assert check_path_collisions(checker, fast.path).free
    for q in _resampled(fast.path):
        closest = min(d for d, _ in reference.signed_distances(q, pairs).values())
        assert closest > -CONTACT_TOLERANCE, (q, closest)


def _dh(name: str):
    robot = kin.load_robot(name)
    model = load_collision_model(robot, scene=CELL)
    reference = CollisionReference(robot.urdf, None, robot.joint_names, None, CELL)
    pairs = [(link, obj) for link in reference.links for obj in reference.scene_names]
    pairs += [p for p in model.pairs if p[1] not in reference.scene_names]
    return robot, CollisionChecker(model), reference, pairs


@pytest.mark.slow
@pytest.mark.parametrize("name", ["panda", "ur5", "humanoid7"])
def test_many_fast_plans_are_certified(cells, name, monkeypatch):
    """(c) Ten random free start and goal pairs per arm whose straight joint line collides
    (Panda by its maker's URDF and SRDF around the box, UR5 and humanoid7 DH tables in the
    example cell): every path the fast checks return is the exact checks' path and free by the
    exact rule and the reference."""
    robot, checker, reference, pairs = cells[name] if name in cells else _dh(name)
    rng = np.random.default_rng(11)
    found = around = 0
    while found < 10:
        start, goal = rng.uniform(robot.lower, robot.upper, (2, robot.nq))
        line = start + np.linspace(0.0, 1.0, 60)[:, None] * (goal - start)
        if checker.in_collision(start) or checker.in_collision(goal):
            continue
        if not checker.in_collision_batch(line).any():  # the planner must go around
            continue
        found += 1
        monkeypatch.setattr(ompl_problem, "FAST_AFTER", 10**9)
        exact = plan(robot, start, goal, collisions=checker, seed=found, **WORK_ONLY)
        monkeypatch.setattr(ompl_problem, "FAST_AFTER", 0)
        fast = plan(robot, start, goal, collisions=checker, seed=found, **WORK_ONLY)
        assert fast.status == exact.status and fast.checks == exact.checks, fast.message
        assert np.array_equal(fast.path, exact.path)
        if fast.status != "ok":
            continue
        around += 1
        assert check_path_collisions(checker, fast.path).free
        for q in _resampled(fast.path):
            closest = min(d for d, _ in reference.signed_distances(q, pairs).values())
            assert closest > -CONTACT_TOLERANCE, (q, closest)
    assert around >= 3  # paths around something were judged
