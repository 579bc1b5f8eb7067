"""Cartesian paths: tool poses along lines and polylines, IK along them, time-optimal timing."""

from .cartesian import CartesianPath, line, polyline
from .exceptions import PathError
from .follow import follow_path, path_solver
from .result import PathResult
from .timing import DEFAULT_ACCELERATION, TimedPath, table_limits, time_optimal

__all__ = [
    "CartesianPath",
    "DEFAULT_ACCELERATION",
    "PathError",
    "PathResult",
    "TimedPath",
    "follow_path",
    "line",
    "path_solver",
    "polyline",
    "table_limits",
    "time_optimal",
]
