"""Forward kinematics and frame Jacobians of DH robots, through Pinocchio (meters, radians)."""

from typing import TYPE_CHECKING

from .batch_fk import batch_forward_kinematics, batch_tool_positions
from .configuration import Configuration, as_joint_vector, limit_violations
from .exceptions import (
    FrameError,
    JointVectorError,
    KinError,
    ModelLoadError,
    NotWithinLimitsError,
    RunFaultError,
)
from .robot_model import RobotModel, load_robot, robot_from_table

if TYPE_CHECKING:
    from .mimic.arm import MimicArm, load_arm

__version__ = "0.3.0"

#: Names imported on first use: a URDF chain with mimic joints and its loader (the one ``kin fk``
#: and ``kin ik`` use), whose module pulls in ``kin.ik``; ``import kin`` stays light.
_LAZY = {"MimicArm": "mimic.arm", "load_arm": "mimic.arm"}


def __getattr__(name: str) -> object:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "Configuration",
    "FrameError",
    "JointVectorError",
    "KinError",
    "MimicArm",
    "ModelLoadError",
    "NotWithinLimitsError",
    "RobotModel",
    "RunFaultError",
    "as_joint_vector",
    "batch_forward_kinematics",
    "batch_tool_positions",
    "limit_violations",
    "load_arm",
    "load_robot",
    "robot_from_table",
]
