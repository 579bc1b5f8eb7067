"""The whole Panda (arm, hand, fingers) as an independent coal reference for the held-joint and
attached-object collision tests: Pinocchio's forward kinematics and coal's distances, no kin code.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin

from support.collision_reference import Shape, scene_shapes
from support.collision_reference import _signed_distance as signed_distance
from support.urdf_reference import erd

#: The issue's posture: Panda's hand pointing straight down [rad].
HAND_DOWN = [0.0, 0.0, 0.0, -math.pi / 2, 0.0, math.pi / 2, math.pi / 4]
PANDA = "panda_description/urdf/panda.urdf"
PANDA_SRDF = "panda_description/srdf/panda.srdf"


class FullPanda:
    """Pinocchio FK + coal on the whole maker URDF; the fingers at ``finger`` [m]."""

    def __init__(self, finger: float, scene: Path | None):
        path = erd(PANDA)
        self.model, self.collision, _ = pin.buildModelsFromUrdf(
            str(path), package_dirs=[str(path.parents[4])]
        )
        self.data = self.model.createData()
        self.geometry_data = self.collision.createData()
        for g in self.collision.geometryObjects:
            if isinstance(g.geometry, coal.BVHModelBase):  # a mesh: its convex hull, as kin says
                g.geometry.buildConvexHull(True, "Qt")
                g.geometry = g.geometry.convex
        self.geometry_data = self.collision.createData()
        self.finger = finger
        self.owner = [self.model.frames[g.parentFrame].name for g in self.collision.geometryObjects]
        self.scene = scene_shapes(scene) if scene is not None else []
        root = ET.parse(erd(PANDA_SRDF)).getroot()
        disabled = {
            frozenset((e.get("link1"), e.get("link2"))) for e in root.iter("disable_collisions")
        }
        links = sorted(set(self.owner))
        self.self_pairs = [
            (a, b)
            for i, a in enumerate(links)
            for b in links[i + 1 :]
            if frozenset((a, b)) not in disabled
        ]

    def distances(self, q: np.ndarray) -> dict[tuple[str, str], float]:
        """Each checked pair's signed distance [m] at the arm's ``q`` (7,) [rad]."""
        full = np.concatenate([q, [self.finger, self.finger]])  # finger_joint2 mimics joint1
        pin.forwardKinematics(self.model, self.data, full)
        pin.updateGeometryPlacements(self.model, self.data, self.collision, self.geometry_data)
        placed: dict[str, list] = {}
        for g, m in zip(self.collision.geometryObjects, self.geometry_data.oMg, strict=True):
            placed.setdefault(self.owner[self.collision.getGeometryId(g.name)], []).append(
                (g.geometry, m)
            )
        for shape in self.scene:
            placed.setdefault(shape.owner, []).append((shape.geometry, shape.local))
        links = {owner for owner in placed if owner not in {s.owner for s in self.scene}}
        pairs = self.self_pairs + [(a, s.owner) for a in sorted(links) for s in self.scene]
        return {(a, b): _distance(placed[a], placed[b]) for a, b in pairs}


def _distance(shapes_a: list, shapes_b: list) -> float:
    """The smallest signed distance between two owners' placed shapes [m]."""
    return min(
        signed_distance(Shape("", ga, ma, False), ma, Shape("", gb, mb, False), mb)
        for ga, ma in shapes_a
        for gb, mb in shapes_b
    )
