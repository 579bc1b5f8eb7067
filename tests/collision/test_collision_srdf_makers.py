"""``generate_disabled_pairs`` on the makers' URDFs (no SRDF) against the makers' SRDFs.

example-robot-data ships the SRDFs; Panda's and xArm7's were written by MoveIt's setup assistant
(each pair with its reason), UR5's by hand (no reasons). Compared on the pairs of the links our
collision model holds (chain and attached links; xArm7's ``link_eef`` has no shape in this URDF):

* Panda (tip ``panda_hand``, 11 links, 55 pairs): the maker's 35 pairs are all ours, every one
  with the maker's reason (10 Adjacent, 3 Default, 22 Never). Ours disables 2 more, Never:
  ``panda_leftfinger``/``panda_link5`` and ``panda_link5``/``panda_rightfinger``. Our states hold
  the fingers closed (0 m, the URDF zero); the assistant sampled the finger joints too, and open
  fingers reach link5 (held at 0.04 m, the right finger touches it at q = 0).
* xArm7 (tip ``link7``, 8 links, 28 pairs): ours (7 Adjacent, 9 Never) are all the maker's with
  its reasons; the maker also disables ``link5``/``link7`` (Never), which ours keeps: our meshes
  are their convex hulls, and those touch when joint6 nears its upper limit (136 of 10,000
  states), where coal finds the meshes themselves 2 cm apart or more.
* UR5 (tip ``tool0``, 8 links): ours disables 7 Adjacent and 3 Never; all are the maker's but
  the three with ``ee_link`` (a 1 cm cube the maker's SRDF never names). The maker disables three
  pairs ours keeps, ``base_link``/``upper_arm_link``, ``forearm_link``/``wrist_2_link`` and
  ``forearm_link``/``wrist_3_link``: their meshes do touch (3 to 7 % of random states, coal).

The Never pairs are statistical. The same seed draws the same Always batches, and then the
Never states of a 1,000-sample run are the first 1,000 of a 10,000-sample run: its Never pairs are
a superset. Here both runs give the same pairs (the default run 1,000, the slow one 10,000).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from support.collision_reference import CollisionReference
from support.urdf_reference import erd

from kin import load_robot
from kin.collision import load_collision_model
from kin.collision.pair_contacts import sampling_bounds
from kin.collision.srdf_generator import generate_disabled_pairs

#: robot -> (URDF, tip, the maker's SRDF) in example-robot-data's robots folder.
MAKERS = {
    "panda": (
        "panda_description/urdf/panda.urdf",
        "panda_hand",
        "panda_description/srdf/panda.srdf",
    ),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", "link7", "xarm_description/srdf/xarm7.srdf"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0", "ur_description/srdf/ur5.srdf"),
}
#: robot -> (pairs ours disables that the maker's keeps, with our reason; pairs the maker's
#: disables that ours keeps), as the module docstring explains them.
DIFFERENCES = {
    "panda": (
        {
            ("panda_leftfinger", "panda_link5"): "Never",
            ("panda_link5", "panda_rightfinger"): "Never",
        },
        set(),
    ),
    "xarm7": ({}, {("link5", "link7")}),
    "ur5": (
        {
            ("ee_link", "wrist_1_link"): "Never",
            ("ee_link", "wrist_2_link"): "Never",
            ("ee_link", "wrist_3_link"): "Adjacent",
        },
        {
            ("base_link", "upper_arm_link"),
            ("forearm_link", "wrist_2_link"),
            ("forearm_link", "wrist_3_link"),
        },
    ),
}


def makers_pairs(path: Path, links: set[str]) -> dict[tuple[str, str], str]:
    """``(link1, link2)`` (sorted) -> reason ("" when none) of an SRDF, on ``links`` only."""
    pairs = {}
    for element in ET.parse(path).getroot().iter("disable_collisions"):
        a, b = sorted((element.get("link1", ""), element.get("link2", "")))
        if a in links and b in links:
            pairs[(a, b)] = element.get("reason", "")
    return pairs


def _compare(name: str, samples: int) -> None:
    urdf, tip, srdf = MAKERS[name]
    model = load_collision_model(load_robot(erd(urdf), None, tip))
    ours = generate_disabled_pairs(model, samples=samples, random_seed=0)
    maker = makers_pairs(erd(srdf), set(model.links))
    extra, missing = DIFFERENCES[name]
    assert {p: r for p, r in ours.items() if p not in maker} == extra, f"{name=}"
    assert set(maker) - set(ours) == missing, f"{name=}"
    if name != "ur5":  # the assistant's reasons: ours are the same on every pair both disable
        both = set(ours) & set(maker)
        assert {p: ours[p] for p in both} == {p: maker[p] for p in both}, f"{name=}"


@pytest.mark.parametrize("name", sorted(MAKERS))
def test_against_the_makers_srdf(name):
    """At 1,000 samples: the makers' pairs, reasons and the explained differences."""
    _compare(name, 1000)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(MAKERS))
def test_against_the_makers_srdf_at_moveits_sample_count(name):
    """At MoveIt's 10,000 samples: the same pairs (no Never pair was a 1,000-sample accident)."""
    _compare(name, 10_000)


def _reference_distances(
    name: str, pairs: list[tuple[str, str]], count: int
) -> dict[str, np.ndarray]:
    """Signed distances [m] of ``pairs`` at ``count`` random states: hulls and meshes, by coal.

    Returns mode -> array (count, len(pairs)); the states drawn by ``default_rng(1)``.
    """
    urdf, tip, _ = MAKERS[name]
    path = erd(urdf)
    robot = load_robot(path, None, tip)
    lower, upper = sampling_bounds(robot.model)
    states = np.random.default_rng(1).uniform(lower, upper, (count, robot.nq))
    out = {}
    for mode in ("convex", "bvh"):
        reference = CollisionReference(path.read_text(), path, robot.joint_names, None, None, mode)
        out[mode] = np.array(
            [[reference.signed_distances(q, pairs)[p][0] for p in pairs] for q in states]
        )
    return out


def test_xarm7_link5_link7_touch_as_hulls_not_as_meshes():
    """Ours keeps link5/link7: their hulls touch at some states; the meshes there do not."""
    distances = _reference_distances("xarm7", [("link5", "link7")], 400)
    hulls_touch = distances["convex"][:, 0] < 0.0
    assert hulls_touch.any()
    assert distances["bvh"][hulls_touch, 0].min() > 0.015
    assert (distances["bvh"][:, 0] > 0.0).all()


def test_ur5_pairs_the_maker_skips_do_touch():
    """The three pairs UR5's hand-written SRDF disables and ours keeps collide as meshes."""
    pairs = sorted(DIFFERENCES["ur5"][1])
    distances = _reference_distances("ur5", pairs, 150)
    touching = (distances["bvh"] < 0.0).sum(axis=0)
    assert (touching > 0).all(), dict(zip(pairs, touching.tolist(), strict=True))


def test_panda_open_fingers_reach_link5():
    """Held open (0.04 m), the right finger touches link5 at q = 0: the pair is not Never."""
    urdf, tip, _ = MAKERS["panda"]
    robot = load_robot(erd(urdf), None, tip)
    model = load_collision_model(robot, hold={"panda_finger_joint1": 0.04})
    disabled = generate_disabled_pairs(model, samples=200)
    assert disabled[("panda_link5", "panda_rightfinger")] == "Default"
    assert ("panda_leftfinger", "panda_rightfinger") in disabled  # apart now, so Never
