"""Forward kinematics and frame Jacobians of DH robots, through Pinocchio (meters, radians)."""

from typing import TYPE_CHECKING

if TYPE_CHECKING:
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
    from .mimic.arm import MimicArm, load_arm
    from .robot_model import RobotModel, load_robot, robot_from_table

__version__ = "0.3.0"

#: Every name is imported on first use (module under ``kin``): ``import kin`` loads neither
#: Pinocchio nor the IK solvers, so a program above ``kin`` that needs one corner of it (the
#: ``dh2urdf`` program's export, ``kin robots``) starts without them.
_LAZY = {
    "batch_forward_kinematics": "batch_fk",
    "batch_tool_positions": "batch_fk",
    "Configuration": "configuration",
    "as_joint_vector": "configuration",
    "limit_violations": "configuration",
    "FrameError": "exceptions",
    "JointVectorError": "exceptions",
    "KinError": "exceptions",
    "ModelLoadError": "exceptions",
    "NotWithinLimitsError": "exceptions",
    "RunFaultError": "exceptions",
    "MimicArm": "mimic.arm",
    "load_arm": "mimic.arm",
    "RobotModel": "robot_model",
    "load_robot": "robot_model",
    "robot_from_table": "robot_model",
}


def __getattr__(name: str) -> object:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *_LAZY])


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
