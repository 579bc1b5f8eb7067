"""The independent reference of the idealised-table tests: a NumPy FK of the table, targets of each
kind, the arm files with rounded constants, and which configurations lie outside the limits.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pinocchio as pin

import kin
from kin import load_robot
from kin.ik import PoseTarget, PositionTarget
from support import DATA
from support.dh_reference import load_reference

#: pi and pi/2 as the corpus AL5D writes them (its branches miss by less than the tolerance:
#: rejected as they are), and to 4 decimals (they miss by up to 1e-5: rejected with a reason).
ROUNDINGS = [("3.141592653", "1.570796325"), ("3.1416", "1.5708")]
PUMA = Path(kin.__file__).parent.parent / "dh2urdf" / "tables" / "puma560.toml"
AL5D = DATA / "toolbox" / "al5d.toml"
LIMIT = 1.2  # [rad]


class Reference:
    """Pinocchio's FK of the rounded arm's URDF (a model of its own) and the table's limits."""

    def __init__(self, path: Path):
        robot = load_robot(path)
        self.model = pin.buildModelFromXML(robot.urdf)
        self.data = self.model.createData()
        self.frame = self.model.getFrameId(robot.tool_frame)
        table = load_reference(path)
        self.names, self.lower, self.upper = table.names, table.lower, table.upper

    def pose(self, q: np.ndarray) -> pin.SE3:
        """``T_world_tool`` at ``q`` [rad] (a copy)."""
        pin.framesForwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        return self.data.oMf[self.frame].copy()

    def errors(self, q: np.ndarray, target: PositionTarget | PoseTarget) -> tuple[float, float]:
        """Position [m] and rotation [rad] errors of ``q`` (rotation 0 for a position)."""
        pose = self.pose(q)
        position = float(np.linalg.norm(pose.translation - target.position))
        if isinstance(target, PositionTarget):
            return position, 0.0
        return position, float(np.linalg.norm(pin.log3(pose.rotation.T @ target.rotation)))

    def beyond(self, q: np.ndarray) -> np.ndarray:
        """Per joint, how far the nearest copy ``q + 2 pi k`` is outside the limits [rad]."""
        copies = np.asarray(q)[:, None] + 2 * np.pi * np.arange(-3, 4)
        outside = np.maximum(self.lower[:, None] - copies, copies - self.upper[:, None])
        return np.maximum(outside, 0.0).min(axis=1)

    def refine(self, q: np.ndarray, target: PositionTarget | PoseTarget) -> np.ndarray:
        """``q`` moved onto the target by Gauss-Newton steps (SVD least squares), no limits."""
        q = np.array(q, dtype=float)
        world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        for _ in range(20):
            pose = self.pose(q)
            jacobian = pin.computeFrameJacobian(self.model, self.data, q, self.frame, world)
            error = target.position - pose.translation
            if isinstance(target, PoseTarget):
                error = np.concatenate((error, pin.log3(target.rotation @ pose.rotation.T)))
            else:
                jacobian = jacobian[:3]
            q = q + np.linalg.lstsq(jacobian, error, rcond=None)[0]
        return q


def targets_of(reference: Reference, kind: str, qs: np.ndarray) -> list:
    """Position or pose targets at Pinocchio's FK of ``qs``."""
    out = []
    for q in qs:
        pose = reference.pose(q)
        position = pose.translation.copy()
        out.append(
            PositionTarget(position) if kind == "position" else PoseTarget(position, pose.rotation)
        )
    return out


def arm_file(name: str, folder: Path) -> Path:
    """A rounded arm's table file: the AL5D (+-1.2 rad) or the PUMA 560 (+-100 deg) one.

    The PUMA's wrist has ``a5`` = 3 um, which breaks the spherical wrist until idealised.
    """
    path = folder / f"{name}.toml"
    if name.startswith("al5d"):
        path.write_text(rounded_text(*ROUNDINGS[name.endswith("4_decimals")]), encoding="utf-8")
        return path
    text = PUMA.read_text(encoding="utf-8")  # twists of +-pi/2 written as +-1.5708 rad
    wrist = 'name = "joint5"\ntype = "revolute"\na = 0.0\n'
    assert text.count(wrist) == 1
    text = text.replace(wrist, wrist.replace("0.0", "3e-06"))  # the wrist axes miss by 3 um
    text = text.replace("alpha = 90.0", f"alpha = {math.degrees(1.5708)!r}")
    text = text.replace("alpha = -90.0", f"alpha = {math.degrees(-1.5708)!r}")
    text = re.sub(r"limits = \[.*\]", "limits = [-100.0, 100.0]", text)
    path.write_text(text, encoding="utf-8")
    return path


def reference_outside(reference: Reference, qs: np.ndarray) -> np.ndarray:
    """Which joint vectors have a joint 0.2 rad or more outside the limits in every copy."""
    return np.array([reference.beyond(q).max() >= 0.2 for q in qs])


def rounded_text(pi: str, half_pi: str, limit: float | None = LIMIT) -> str:
    """The AL5D table with pi and pi/2 written as given, its limits +-``limit`` [rad]."""
    text = AL5D.read_text(encoding="utf-8")
    text = text.replace("alpha = 3.141592653589793", f"alpha = {pi}")
    text = text.replace("alpha = 1.5707963267948966", f"alpha = {half_pi}")
    assert text.count(f"alpha = {pi}\n") == 3 and text.count(f"alpha = {half_pi}\n") == 1
    if limit is not None:
        old = "limits = [-1.5707963267948966, 1.5707963267948966]"
        assert text.count(old) == 4
        text = text.replace(old, f"limits = [{-limit}, {limit}]")
    return text
