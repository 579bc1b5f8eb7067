"""The shipped DH arms' self-collisions: links that meet at a joint of the drawing are not a collision.

The rule (kin/collision/always_pairs.py, MoveIt's setup assistant's "always in collision"): a
link pair of a DH table robot in contact at every sampled configuration is not checked, and the
model's shape note names it. Checked against tests/support/collision_reference.py (Pinocchio and coal on
the DH writer's URDF, pair by pair, no broad phase): the pairs called "always" are in contact at
fresh random configurations too; every other verdict is the reference's over the checked pairs,
so a configuration is called in self-collision only where two checked links really overlap by
more than the padding. pickplace3, whose column and upper arm meet at the shoulder, was in
self-collision at 100 % of random configurations before the rule.
"""

from __future__ import annotations

import numpy as np
import pytest
from support.cli_helper import call
from support.collision_reference import CollisionReference

from dh2urdf.robots import robot_names
from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.srdf_generator import generate_disabled_pairs

#: Closer to contact than this [m], either verdict is right.
CONTACT_TOL = 1e-6


def _samples(robot, count: int, seed: int) -> np.ndarray:
    lower = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    upper = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return np.random.default_rng(seed).uniform(lower, upper, (count, robot.nq))


def _reference(robot) -> CollisionReference:
    return CollisionReference(robot.urdf, None, robot.joint_names)


@pytest.mark.parametrize("name", robot_names())
@pytest.mark.parametrize("padding", [0.0, 0.002])
def test_self_collision_only_where_checked_links_overlap(name, padding):
    """Verdicts equal the reference's over the checked pairs; 'always' pairs never separate."""
    robot = load_robot(name)
    model = load_collision_model(robot, padding=padding)
    checker = CollisionChecker(model)
    reference = _reference(robot)
    always = [pair for pair, reason in model.disabled.items() if reason == "always"]
    adjacent = {pair for pair, reason in model.disabled.items() if reason != "always"}
    links = sorted(model.links)
    every = {(a, b) for a in links for b in links if a < b}
    # the pairs checked and the ones called "always" together are all but the adjacent/rigid
    assert {frozenset(p) for p in (*model.pairs, *always)} == {
        frozenset(p) for p in every if p not in adjacent and p[::-1] not in adjacent
    }, f"{name=}"
    for q in _samples(robot, 150, seed=1):
        distances = reference.signed_distances(q, [*model.pairs, *always])
        for pair in always:
            assert distances[pair][0] < padding, f"{name=} {pair=} separates at {q.tolist()}"
        checked = [distances[pair][0] - padding for pair in model.pairs]
        if not checked or min(abs(d) for d in checked) <= CONTACT_TOL:
            continue
        expected = min(checked) < 0.0
        assert checker.in_collision(q) == expected, (
            f"{name=} {padding=} q={q.tolist()}: reference {min(checked) + padding:.4g} m"
        )


def test_pickplace3_column_and_upper_arm_meet_at_the_shoulder():
    """pickplace3's frame0/link2 is 'always', stated; random configurations are now free."""
    robot = load_robot("pickplace3")
    model = load_collision_model(robot)
    assert model.disabled[("frame0", "link2")] == "always"
    assert "frame0/link2" in model.shape_note and "1000 sampled" in model.shape_note
    qs = _samples(robot, 300, seed=2)
    reference = _reference(robot)
    touching = [reference.signed_distances(q, [("frame0", "link2")]) for q in qs]
    assert max(t[("frame0", "link2")][0] for t in touching) < 0.0  # truly never apart
    colliding = CollisionChecker(model).in_collision_batch(qs)
    assert colliding.mean() < 0.05, f"{colliding.mean():.0%} of random configurations collide"


def test_scorbot_arm_through_its_column_stays_a_collision():
    """A pair that leaves contact stays checked: scorbot's upper arm through its column collides."""
    robot = load_robot("scorbot")
    model = load_collision_model(robot)
    assert ("frame0", "link2") in model.pairs
    assert not any(reason == "always" for reason in model.disabled.values())


def test_generated_srdf_keeps_always_pairs():
    """kin collisions --write-srdf lists the model's 'always' pair: Default, as MoveIt names it.

    pickplace3's column and upper arm touch in every state, the default one (every joint at 0)
    too, and MoveIt's assistant tries Default before Always.
    """
    model = load_collision_model(load_robot("pickplace3"))
    assert model.disabled[("frame0", "link2")] == "always"
    assert generate_disabled_pairs(model, samples=20)[("frame0", "link2")] == "Default"


def test_kin_check_states_the_rule(capsys):
    """kin check on pickplace3 names the unchecked pair in its shapes line and calls zero free."""
    from kin.commands import check

    assert call(check.main, ["--robot", "pickplace3", "--q", "0", "0", "0"]) == 0
    out = capsys.readouterr().out
    assert "collision-free" in out and "frame0/link2" in out, out
