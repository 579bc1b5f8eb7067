"""Cartesian paths: tool poses along lines and polylines, IK along them, time-optimal timing."""

from .avoid import follow_path_avoiding
from .avoid_result import AvoidedPath, AvoidFailure
from .cartesian import CartesianPath, line, polyline
from .collision_check import MotionCheck, PathCollision, PathCollisionCheck, check_path_collisions
from .exceptions import PathError
from .follow import follow_path, path_solver
from .joint_path_file import JointPath, animation_frames, read_joint_path
from .result import PathResult
from .timing import DEFAULT_ACCELERATION, TimedPath, table_limits, time_optimal

__all__ = [
    "AvoidFailure",
    "AvoidedPath",
    "CartesianPath",
    "DEFAULT_ACCELERATION",
    "JointPath",
    "MotionCheck",
    "PathCollision",
    "PathCollisionCheck",
    "PathError",
    "PathResult",
    "TimedPath",
    "animation_frames",
    "check_path_collisions",
    "follow_path",
    "follow_path_avoiding",
    "line",
    "path_solver",
    "polyline",
    "read_joint_path",
    "table_limits",
    "time_optimal",
]
