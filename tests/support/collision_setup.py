"""The robots of the collision engine tests, each loaded with its direct coal reference (the maker's
URDF and SRDF via Pinocchio), and the scene cell they are placed in.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from functools import cache
from pathlib import Path

from kin import load_robot
from support import DATA
from support.collision_reference import CollisionReference
from support.urdf_reference import erd

CELL = DATA / "collision" / "cell.toml"
#: robot -> (URDF in example-robot-data or None for a shipped table, tip link, SRDF or None).
ROBOTS = {
    "panda": (
        "panda_description/urdf/panda.urdf",
        "panda_link8",
        "panda_description/srdf/panda.srdf",
    ),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0", None),
    "humanoid7": (None, None, None),
}


@cache
def setup(name: str):
    """(robot, collision model, checker, reference, the pairs expected: of all the links)."""
    from kin.collision import CollisionChecker, load_collision_model

    urdf, tip, srdf = ROBOTS[name]
    if urdf is None:
        robot = load_robot(name)
        reference = CollisionReference(robot.urdf, None, robot.joint_names, None, CELL)
    else:
        robot = load_robot(erd(urdf), None, tip)
        path, base, _ = robot.urdf_source
        text = Path(path).read_text(encoding="utf-8")
        reference = CollisionReference(text, Path(path), robot.joint_names, base, CELL)
    srdf_path = erd(srdf) if srdf else None
    # every joint off the chain at 0, as the reference holds it (the SRDF's state says 0.001)
    hold = {"panda_finger_joint1": 0.0} if name == "panda" else None
    model = load_collision_model(robot, srdf=srdf_path, scene=CELL, hold=hold)
    skipped = reference.adjacent() | (_srdf_disabled(srdf_path) if srdf_path else set())
    links = sorted(reference.links)  # every link: the chain's and those off it (the fingers)
    chain = set(robot.joint_names)
    skipped |= {  # links carried by one chain joint: never moving against each other
        frozenset((a, b))
        for a in links
        for b in links
        if a != b and reference.carrier(a, chain) == reference.carrier(b, chain)
    }
    expected = {
        frozenset((a, b))
        for i, a in enumerate(links)
        for b in links[i + 1 :]
        if frozenset((a, b)) not in skipped
    } | {frozenset((a, s)) for a in links for s in reference.scene_names}
    return robot, model, CollisionChecker(model), reference, expected


def _srdf_disabled(path: Path) -> set[frozenset[str]]:
    root = ET.parse(path).getroot()
    return {frozenset((e.get("link1"), e.get("link2"))) for e in root.iter("disable_collisions")}
