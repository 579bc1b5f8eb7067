"""Reachable task-shaped targets and their independent judge, for tests and benchmarks.

A robot's targets are the tool poses of random joint vectors inside its limits, made by an
independent forward kinematics: the plain NumPy DH product of ``tests/support/dh_reference.py`` for a
shipped table, Pinocchio on the maker's original URDF (``tests/support/urdf_reference.py``) for an
example-robot-data arm; the same reference judges every answer.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from dh2urdf import get_robot
from dh2urdf.robots import robot_names
from kin import load_robot
from kin.ik import AxisTarget, PoseTarget, get_solver
from kin.ik.targets.target import rpy_matrix
from support.dh_reference import fk_frames, load_reference
from support.urdf_reference import ARMS, UrdfReference, erd

#: example-robot-data's arms of the issue (names of ``tests/support/urdf_reference.py``).
URDF_ARMS = ("panda", "kinova", "ur5", "z1", "xarm7", "tiago", "baxter_left")
ROBOTS = (*robot_names(), *(f"erd:{name}" for name in URDF_ARMS))

#: A target's kind -> how it frees the pose: the roll about the tool's z axis, the rotation about
#: the world's z axis (a yaw-free mask) or about the world's x axis.
KINDS = ("axis", "mask_rz", "mask_rx")
MASKS = {"mask_rz": (1, 1, 1, 1, 1, 0), "mask_rx": (1, 1, 1, 0, 1, 1)}

#: Tolerances of the reference's judgement [m], [rad]: the judge's (kin.ik.judge), which IK promises.
POSITION_TOL, ROTATION_TOL = 1e-5, 1e-4


class Arm:
    """A robot, its solver and its independent forward kinematics (4 x 4 tool pose of q)."""

    def __init__(self, name: str):
        if name.startswith("erd:"):
            relative, base, tip = ARMS[name[4:]]
            self.argv = ["--robot", str(erd(relative))]
            self.argv += ["--base", base] if base else []
            self.argv += ["--tip", tip] if tip else []
            self.robot = load_robot(erd(relative), base, tip)
            path, base, tip = self.robot.urdf_source
            urdf = UrdfReference(path, base, tip, self.robot.joint_names)
            self.pose = urdf.pose
        else:
            self.argv = ["--robot", name]
            self.robot = load_robot(name)
            table = load_reference(get_robot(name).table_path)
            self.pose = lambda q: fk_frames(table, np.asarray(q)[None])[0, -1]
        self.solver = get_solver(self.robot)
        self.lower = np.maximum(self.robot.lower, -math.pi)
        self.upper = np.minimum(self.robot.upper, math.pi)

    def targets(self, kind: str, count: int, seed: int) -> list[tuple[object, dict]]:
        """``count`` reachable targets of ``kind``: (library target, JSON line of ``--stdin``)."""
        rng = np.random.default_rng(seed)
        out = []
        for q in rng.uniform(self.lower, self.upper, (count, self.robot.nq)):
            pose = self.pose(q)
            p = pose[:3, 3]
            if kind == "axis":
                axis = pose[:3, 2]
                out.append((AxisTarget(p, axis), {"target": p.tolist(), "axis": axis.tolist()}))
                continue
            # The free rotation turned by a random angle: still reachable (the mask frees it).
            free = np.eye(3)[2 if kind == "mask_rz" else 0]
            turned = pin.exp3(free * rng.uniform(-math.pi, math.pi)) @ pose[:3, :3]
            rpy = pin.rpy.matrixToRpy(turned)
            target = PoseTarget(p, rpy_matrix(rpy), mask=MASKS[kind])
            line = {"target": p.tolist(), "rpy": rpy.tolist(), "mask": list(MASKS[kind])}
            out.append((target, line))
        return out

    def errors(self, target: object, q: np.ndarray) -> tuple[float, float, bool]:
        """The reference's errors of ``q`` [m], [rad] on the constrained components; inside?"""
        reached = self.pose(q)
        position = float(np.linalg.norm(reached[:3, 3] - target.position))
        if isinstance(target, AxisTarget):
            angle = math.acos(min(1.0, float(reached[:3, 2] @ target.axis)))
        else:
            error = pin.log3(target.rotation @ reached[:3, :3].T)
            angle = float(np.linalg.norm(error[np.array(target.mask[3:], dtype=bool)]))
        inside = bool(np.all(q >= self.robot.lower) and np.all(q <= self.robot.upper))
        return position, angle, inside

    def check(self, target: object, q: np.ndarray) -> None:
        """The reference's judgement: on the constrained components, inside the limits."""
        position, angle, inside = self.errors(target, q)
        assert position < POSITION_TOL and angle < ROTATION_TOL and inside, (
            position,
            angle,
            inside,
        )


_ARMS: dict[str, Arm] = {}


def arm_of(name: str) -> Arm:
    """The :class:`Arm` of ``name`` (a shipped robot, or ``erd:<arm>``), loaded once."""
    if name not in _ARMS:
        _ARMS[name] = Arm(name)
    return _ARMS[name]
