"""Cartesian paths: tool poses along lines and polylines, IK along them, time-optimal timing."""

from .cartesian import CartesianPath, line, polyline
from .exceptions import PathError
from .follow import follow_path
from .result import PathResult
from .timing import DEFAULT_ACCELERATION, TimedPath, table_limits, time_optimal

__all__ = [
    "DEFAULT_ACCELERATION",
    "CartesianPath",
    "PathError",
    "PathResult",
    "TimedPath",
    "follow_path",
    "line",
    "polyline",
    "table_limits",
    "time_optimal",
]
