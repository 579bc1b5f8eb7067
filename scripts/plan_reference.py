"""The independent check that judges the planning scripts' paths (issue 44, items 3-5).

:class:`Reference` is built apart from :mod:`kin.collision`: Pinocchio's own URDF parser
(``buildGeomFromUrdf``) makes the link shapes (meshes as coal's convex hulls, as kin's collision
model takes them), the scene's boxes are coal boxes, Pinocchio's FK of the arm's FULL URDF (the
maker's, or the DH writer's for a table) places them, and ``pin.computeCollisions`` /
``pin.computeDistances`` judge every pair. Read from kin's model only as a specification: which
self pairs are checked (the SRDF's and the table's allowed pairs left out) and the value of the
held finger joints; every link is checked against every box of the scene.
:func:`resample` cuts a joint path so that no joint moves more than 0.005 rad between two
checked configurations (the issue's rule). Used by scripts/bench_plan.py and
scripts/certify_plans.py through :mod:`plan_problems`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import coal
import numpy as np
import pinocchio as pin
from bench_ik_urdf import erd

if TYPE_CHECKING:  # pragma: no cover
    from plan_parts import Arm, Box

#: Largest joint step between two configurations the reference checks [rad].
RESAMPLE = 0.005


def resample(path: np.ndarray, step: float = RESAMPLE) -> np.ndarray:
    """Every configuration of the path's straight motions, no joint moving more than ``step``."""
    rows = [path[:1]]
    for a, b in zip(path[:-1], path[1:]):
        count = max(1, math.ceil(float(np.abs(b - a).max()) / step))
        rows.append(a + np.linspace(0.0, 1.0, count + 1)[1:, None] * (b - a))
    return np.vstack(rows)


@dataclass(frozen=True)
class Verdict:
    """The reference's judgement of a path.

    Attributes:
        free: No resampled configuration is in contact.
        samples: Configurations checked.
        smallest: Smallest distance over every checked pair and configuration [m] (negative:
            penetration).
        first: (sample index, joint vector, (shape, shape)) of the first contact, or None.
    """

    free: bool
    samples: int
    smallest: float
    first: tuple[int, list[float], tuple[str, str]] | None = None


class Reference:
    """Pinocchio FK of the arm's full URDF + coal, built apart from kin's collision model.

    Args:
        arm: The arm.
        robot: Its kin robot (the joint names ``q`` holds, the chain's base).
        model: kin's collision model, read only for its self pairs and held joints.
        boxes: The scene.
    """

    def __init__(self, arm: Arm, robot, model, boxes: list[Box]):
        if arm.tip is None:  # the DH writer's URDF text: primitives only
            self.model = pin.buildModelFromXML(robot.urdf)
            geometry = pin.buildGeomFromUrdfString(self.model, robot.urdf, pin.COLLISION)
            base = "base_link"
        else:
            path = erd(arm.robot)
            self.model = pin.buildModelFromUrdf(str(path))
            share = str(path).split("/example-robot-data/")[0]
            geometry = pin.buildGeomFromUrdf(
                self.model, str(path), pin.COLLISION, package_dirs=[share]
            )
            base = robot.urdf_source[1]
        for obj in geometry.geometryObjects:  # meshes as their convex hulls
            if isinstance(obj.geometry, coal.BVHModelBase):
                obj.geometry.buildConvexHull(True, "Qt")
                obj.geometry = obj.geometry.convex
        self.data = self.model.createData()
        self.neutral = pin.neutral(self.model)
        for held in model.held.joints:
            joint = self.model.joints[self.model.getJointId(held.name)]
            self.neutral[joint.idx_q] = held.value
        self.joints = [self.model.joints[self.model.getJointId(n)] for n in robot.joint_names]
        pin.framesForwardKinematics(self.model, self.data, self.neutral)
        base_pose = self.data.oMf[self.model.getFrameId(base, pin.FrameType.BODY)]
        owners = [self.model.frames[o.parentFrame].name for o in geometry.geometryObjects]
        robot_shapes = len(owners)
        for b in boxes:
            pose = pin.SE3(pin.rpy.rpyToMatrix(0.0, 0.0, b.yaw), np.array(b.xyz))
            geometry.addGeometryObject(
                pin.GeometryObject(b.name, 0, base_pose * pose, coal.Box(*b.size))
            )
            owners.append(b.name)
        scene = {b.name for b in boxes}
        checked = {frozenset(p) for p in model.pairs if not scene & set(p)}
        for i in range(robot_shapes):
            for j in range(i + 1, len(owners)):
                if j >= robot_shapes or frozenset((owners[i], owners[j])) in checked:
                    geometry.addCollisionPair(pin.CollisionPair(i, j))
        self.geometry = geometry
        self.names = [o.name for o in geometry.geometryObjects]
        self.geometry_data = pin.GeometryData(geometry)

    def _full(self, q: np.ndarray) -> np.ndarray:
        full = self.neutral.copy()
        for joint, value in zip(self.joints, q, strict=True):
            if joint.nq == 2:  # continuous: (cos, sin)
                full[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
            else:
                full[joint.idx_q] = value
        return full

    def in_collision(self, q: np.ndarray) -> bool:
        """Whether any checked pair is in contact at ``q`` (coal's collide, first contact)."""
        args = (self.model, self.data, self.geometry, self.geometry_data, self._full(q))
        return bool(pin.computeCollisions(*args, True))

    def smallest(self, q: np.ndarray) -> tuple[float, int]:
        """The smallest distance over the checked pairs at ``q`` [m], and its pair's index."""
        pin.computeDistances(
            self.model, self.data, self.geometry, self.geometry_data, self._full(q)
        )
        distances = [r.min_distance for r in self.geometry_data.distanceResults]
        index = int(np.argmin(distances))
        return float(distances[index]), index

    def pair(self, index: int) -> tuple[str, str]:
        """The shapes of pair ``index``."""
        p = self.geometry.collisionPairs[index]
        return self.names[p.first], self.names[p.second]

    def judge(self, path: np.ndarray, step: float = RESAMPLE, stop: bool = False) -> Verdict:
        """Every configuration of ``path`` resampled at ``step`` [rad]: contact, smallest distance.

        ``stop``: return at the first contact (its smallest distance then that sample's).
        """
        samples = resample(np.asarray(path, dtype=float), step)
        smallest, first = math.inf, None
        for k, q in enumerate(samples):
            distance, index = self.smallest(q)
            smallest = min(smallest, distance)
            if first is None and distance <= 0.0:  # coal's signed distance: contact
                contact = self._contact(q)
                first = (k, [round(float(v), 9) for v in q], contact)
                if stop:
                    break
        return Verdict(first is None, len(samples), smallest, first)

    def _contact(self, q: np.ndarray) -> tuple[str, str]:
        pin.computeCollisions(
            self.model, self.data, self.geometry, self.geometry_data, self._full(q), False
        )
        for index, result in enumerate(self.geometry_data.collisionResults):
            if result.isCollision():
                return self.pair(index)
        return self.pair(self.smallest(q)[1])
