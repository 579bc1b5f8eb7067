"""The checker's fast verdict (coal's broad phase of world boxes, verdict-only GJK) is the verdict of
the full contact query, with and without padding, in single calls and batches.

``in_collision`` runs Pinocchio's computeCollisions through a naive broad-phase manager whose
boxes grow by half the padding; ``collisions`` runs every pair with contacts and no broad phase.
A box grown too little, or GJK stopped too early, would show as a configuration called free that
``collisions`` finds in contact. The UR5 configuration below is one that coal's default GJK
tolerance (1e-6) called free although its forearm and wrist_2 hulls overlap by 2 cm (found by
tests/collision/test_collision_engines.py's 10,000-configuration run against tests/support/collision_reference.py).
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from support.collision_reference import CollisionReference
from support.urdf_reference import erd

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model

CELL = Path(__file__).parents[1] / "data" / "collision" / "cell.toml"
UR5 = "ur_description/urdf/ur5_robot.urdf"
#: Found by the reference run: forearm_link and wrist_2_link overlap by 1.97 cm.
UR5_DEEP = [
    5.588971132345858,
    -2.614554687455688,
    0.8058129543316914,
    -4.741753636040998,
    -5.945201145537829,
    -5.62618297656382,
]


@cache
def robot(name: str):
    return load_robot(erd(UR5), None, "tool0") if name == "ur5" else load_robot(name)


def checker(name: str, padding: float) -> CollisionChecker:
    return CollisionChecker(load_collision_model(robot(name), scene=CELL, padding=padding))


@pytest.mark.parametrize("name", ["ur5", "humanoid7"])
@pytest.mark.parametrize("padding", [0.0, 0.004])
def test_fast_verdict_is_the_contact_query(name, padding):
    """in_collision(q) == bool(collisions(q)) and the batch gives the same, 400 configurations."""
    check = checker(name, padding)
    arm = check.model.robot
    qs = np.random.default_rng(11).uniform(arm.lower, arm.upper, (400, arm.nq))
    fast = np.array([check.in_collision(q) for q in qs])
    full = np.array([bool(check.collisions(q)) for q in qs])
    np.testing.assert_array_equal(fast, full, err_msg=f"{name=} {padding=}")
    np.testing.assert_array_equal(check.in_collision_batch(qs), full, err_msg=f"{name=}")
    assert 0 < full.sum() < len(qs), f"{name=} {padding=}: {full.sum()} colliding"


def test_broad_phase_where_a_shape_is_a_mesh():
    """UR5's maker meshes (convex hulls) go through the broad phase; humanoid7's cylinders do not."""
    assert checker("ur5", 0.0).broad_phase is True
    assert checker("humanoid7", 0.0).broad_phase is False


def test_padding_grows_the_boxes():
    """A UR5 configuration just outside contact is free, and colliding with more padding."""
    check = checker("ur5", 0.0)
    arm = check.model.robot
    qs = np.random.default_rng(5).uniform(arm.lower, arm.upper, (300, arm.nq))
    gaps = [(check.distance(q).distance, q) for q in qs if not check.in_collision(q)]
    gap, q = min((g for g in gaps if g[0] > 0.002), key=lambda g: g[0])
    assert gap < 0.05, f"closest free gap {gap} m"
    padded = checker("ur5", gap + 0.001)
    assert padded.in_collision(q) is True, f"gap {gap} m, padding {gap + 0.001} m"
    assert padded.in_collision_batch(q[None])[0]
    assert not checker("ur5", gap - 0.001).in_collision(q)


def test_verdict_does_not_depend_on_the_calls_before():
    """lab5, 300 configurations: one checker in sequence gives each fresh checker's verdict.

    With coal's GJK started from the previous call's answer (Pinocchio's default), configuration
    25 of this draw (upper arm and wrist axes crossing, 2 cm deep) was called free in sequence.
    """
    arm = robot("lab5")
    model = load_collision_model(arm)
    lower = np.where(np.isfinite(arm.lower), arm.lower, -np.pi)
    upper = np.where(np.isfinite(arm.upper), arm.upper, np.pi)
    qs = np.random.default_rng(1).uniform(lower, upper, (300, arm.nq))
    sequence = CollisionChecker(model)
    in_sequence = [sequence.in_collision(q) for q in qs]
    fresh = [CollisionChecker(model).in_collision(q) for q in qs]
    assert in_sequence == fresh
    assert in_sequence[25] is True
    assert bool(sequence.collisions(qs[25]))


def test_deep_ur5_overlap_is_a_collision():
    """The reference's 2 cm overlap of forearm and wrist_2 is in collision, single and batched."""
    q = np.array(UR5_DEEP)
    path = erd(UR5)
    arm = robot("ur5")
    reference = CollisionReference(
        path.read_text(encoding="utf-8"), path, arm.joint_names, None, CELL
    )
    distance, _ = reference.signed_distances(q, [("forearm_link", "wrist_2_link")])[
        ("forearm_link", "wrist_2_link")
    ]
    assert distance < -0.019
    check = checker("ur5", 0.0)
    assert check.in_collision(q) is True
    assert check.in_collision_batch(q[None])[0]
