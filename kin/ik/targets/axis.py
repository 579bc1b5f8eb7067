"""A tool position and the world direction of one tool axis, the roll about it free."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..exceptions import TargetError
from .values import checked_vector

__all__ = ["TOOL_AXES", "AxisTarget", "axis_turn"]


#: The tool axis an :class:`AxisTarget` may name, as a column of ``R_world_tool``.
TOOL_AXES = {"x": 0, "y": 1, "z": 2}


def axis_turn(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation vector [rad] turning unit vector ``a`` onto unit vector ``b``, about their normal.

    The shortest turn (on their great circle); opposite vectors get a half turn about an axis
    normal to ``a`` (one chosen), equal ones none. The rotation error of an
    :class:`AxisTarget` and the interpolation of its axis along a path.
    """
    cross = np.cross(a, b)
    sine = float(np.linalg.norm(cross))
    cosine = float(a @ b)
    angle = math.atan2(sine, cosine)
    if sine > 1e-12:
        return cross * (angle / sine)
    if cosine > 0.0:
        return np.zeros(3)
    normal = np.cross(a, (1.0, 0.0, 0.0) if abs(a[0]) < 0.9 else (0.0, 1.0, 0.0))
    return normal * (math.pi / float(np.linalg.norm(normal)))


@dataclass(frozen=True, eq=False)
class AxisTarget:
    """A tool position and the world direction of one tool axis; the roll about it is free.

    The task of a drill, a welding torch, a spray gun or a suction cup (five constraints). A
    joint vector's errors are the position error [m] and the angle between its tool axis and
    :attr:`axis` [rad].

    Attributes:
        position: Tool point in the world frame [m], shape (3,).
        axis: Unit vector in the world frame the tool axis must point along, shape (3,).
        tool_axis: Which tool axis: ``"x"``, ``"y"`` or ``"z"`` (the default, the approach axis of
            most flanges).
    """

    position: np.ndarray
    axis: np.ndarray
    tool_axis: str = "z"

    def __init__(self, position: npt.ArrayLike, axis: npt.ArrayLike, tool_axis: str = "z"):
        object.__setattr__(self, "position", checked_vector(position, 3, "position"))
        direction = checked_vector(axis, 3, "axis")
        scale = float(np.abs(direction).max())
        norm = float(np.linalg.norm(direction / scale)) * scale if scale > 0.0 else 0.0
        if not (norm > 1e-12 and math.isfinite(norm)):
            raise TargetError(f"axis must be a nonzero direction, got {direction.tolist()}")
        object.__setattr__(self, "axis", direction / norm)
        if tool_axis not in TOOL_AXES:
            raise TargetError(f"tool_axis must be 'x', 'y' or 'z', got {tool_axis!r}")
        object.__setattr__(self, "tool_axis", tool_axis)

    @property
    def free(self) -> tuple[str, ...]:
        """The free component: the roll about the tool axis."""
        return (f"roll about tool {self.tool_axis}",)

    @property
    def finite(self) -> bool:
        """Whether every value is finite."""
        isfinite = math.isfinite
        return all(map(isfinite, self.position.tolist())) and all(map(isfinite, self.axis.tolist()))
