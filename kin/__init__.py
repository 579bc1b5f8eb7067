"""Forward kinematics and frame Jacobians of DH robots, through Pinocchio (meters, radians)."""

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

__version__ = "0.3.0"

__all__ = [
    "Configuration",
    "FrameError",
    "JointVectorError",
    "KinError",
    "ModelLoadError",
    "NotWithinLimitsError",
    "RobotModel",
    "RunFaultError",
    "as_joint_vector",
    "batch_forward_kinematics",
    "batch_tool_positions",
    "limit_violations",
    "load_robot",
    "robot_from_table",
]
