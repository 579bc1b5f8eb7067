"""The pairs a verdict tests and their order (kin/collision/pair_order.py).

Judged against Pinocchio's own ``computeCollisions`` on the collision model's geometry model (its
pairs in the model's order, a fresh GeometryData with Pinocchio's default requests but the
contact tolerance as security margin): the order
changes the cost, never the verdict.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import kin
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.requests import CONTACT_TOLERANCE

CELL = Path(__file__).parents[1] / "data" / "collision" / "cell.toml"


def _pinocchio(checker: CollisionChecker, qs: np.ndarray, stop: bool = True) -> np.ndarray:
    """Pinocchio's verdicts on the model's own pairs (``stop`` False: every pair's, (N, pairs))."""
    model, geometry = checker.model.robot.model, checker.model.geometry_model
    data, geometry_data = model.createData(), pin.GeometryData(geometry)
    for request in geometry_data.collisionRequests:  # in contact closer than the tolerance
        request.security_margin = CONTACT_TOLERANCE
    if stop:
        return np.array(
            [pin.computeCollisions(model, data, geometry, geometry_data, q, True) for q in qs]
        )
    rows = []
    for q in qs:
        pin.computeCollisions(model, data, geometry, geometry_data, q, False)
        rows.append([r.isCollision() for r in geometry_data.collisionResults])
    return np.array(rows)


def _pairs(geometry: pin.GeometryModel) -> list[tuple[int, int]]:
    return [(p.first, p.second) for p in geometry.collisionPairs]


def _qs(robot, count: int, seed: int = 11) -> np.ndarray:
    lower = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    upper = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return np.random.default_rng(seed).uniform(lower, upper, (count, robot.nq))


@pytest.mark.parametrize("name", ["humanoid7", "pickplace3", "scorbot"])
def test_verdicts_equal_pinocchio_on_the_model(name):
    """Single and batched verdicts equal Pinocchio's on the model's own pairs; both kinds occur."""
    checker = CollisionChecker(load_collision_model(kin.load_robot(name), scene=CELL))
    assert not checker.broad_phase, f"{name=}"
    qs = _qs(checker.model.robot, 1500)
    expected = _pinocchio(checker, qs)
    assert 0 < expected.sum() < len(qs), f"{name=}"
    np.testing.assert_array_equal([checker.in_collision(q) for q in qs], expected, f"{name=}")
    np.testing.assert_array_equal(checker.in_collision_batch(qs), expected, f"{name=}")


def test_pairs_most_often_in_contact_come_first():
    """humanoid7 in the cell: the upper arm on the table first; fewer pairs tested per verdict."""
    checker = CollisionChecker(load_collision_model(kin.load_robot("humanoid7"), scene=CELL))
    model_pairs = _pairs(checker.model.geometry_model)
    verdict_pairs = _pairs(checker._verdict_geometry)
    assert sorted(verdict_pairs) == sorted(model_pairs)  # no world pair on this arm
    contacts = _pinocchio(checker, _qs(checker.model.robot, 1000), stop=False)  # other samples
    assert verdict_pairs[0] == model_pairs[int(np.argmax(contacts.sum(axis=0)))]
    owners = checker.model.pair_owners[model_pairs.index(verdict_pairs[0])]
    assert owners == ("frame2", "table")

    def tested(order: list[int]) -> float:
        """Mean pairs a verdict tests, stopping at the first contact."""
        columns = contacts[:, order]
        hit = columns.any(axis=1)
        first = np.where(hit, columns.argmax(axis=1) + 1, len(order))
        return float(first.mean())

    ordered = [model_pairs.index(p) for p in verdict_pairs]
    assert tested(ordered) < 0.8 * tested(list(range(len(model_pairs))))


def test_free_world_pairs_are_left_out(tmp_path):
    """pickplace3's column (on the world) against the cell's objects: tested once, free, left out."""
    checker = CollisionChecker(load_collision_model(kin.load_robot("pickplace3"), scene=CELL))
    geometry = checker.model.geometry_model
    objects = geometry.geometryObjects
    world = [
        p for p in _pairs(geometry) if objects[p[0]].parentJoint == objects[p[1]].parentJoint == 0
    ]
    assert len(world) == 3  # frame0 with the table, the wall and the ball
    assert sorted(_pairs(checker._verdict_geometry)) == sorted(set(_pairs(geometry)) - set(world))
    data, geometry_data = checker.model.robot.model.createData(), pin.GeometryData(geometry)
    pin.updateGeometryPlacements(
        checker.model.robot.model, data, geometry, geometry_data, np.zeros(checker.model.robot.nq)
    )
    assert not any(
        pin.computeCollision(geometry, geometry_data, _pairs(geometry).index(p)) for p in world
    )


def test_world_pair_in_contact_is_tested_first(tmp_path):
    """A box around pickplace3's column: that pair first, every verdict True, as Pinocchio says."""
    scene = tmp_path / "column.toml"
    scene.write_text('[[box]]\nname = "post"\nsize = [0.3, 0.3, 0.2]\nxyz = [0.0, 0.0, 0.05]\n')
    checker = CollisionChecker(load_collision_model(kin.load_robot("pickplace3"), scene=scene))
    first = checker._verdict_geometry.collisionPairs[0]
    index = _pairs(checker.model.geometry_model).index((first.first, first.second))
    assert checker.model.pair_owners[index] == ("frame0", "post")
    qs = _qs(checker.model.robot, 200)
    assert _pinocchio(checker, qs).all()
    assert all(checker.in_collision(q) for q in qs)
    assert checker.in_collision_batch(qs).all()
