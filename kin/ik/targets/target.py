"""IK targets: a position, a pose (full or masked), a position with a tool axis, or with a pitch.

All targets are expressed in the world frame (the URDF root), in meters and radians. They are
checked once, when built, and their arrays are read-only copies, so that a solve never checks
them again: a NaN or infinite value is a
:class:`~kin.ik.TargetError` that names the field (``position[1]``, ``rotation[2][0]``,
``pitch``). A rotation must be a rotation matrix: one that is off by at most
:data:`ROTATION_SNAP` (``max |R^T R - I|``, e.g. a matrix printed with six decimals) is replaced by
the nearest rotation matrix (SVD); a farther one, or one with ``det(R) < 0``, is a ``TargetError``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from kin._native import twin

from .. import angles
from ..exceptions import TargetError
from .axis import TOOL_AXES, AxisTarget, axis_turn
from .pitch import PitchTarget
from .values import FLOAT64 as _FLOAT64
from .values import ROTATION_EXACT as _ROTATION_EXACT
from .values import (
    ROTATION_SNAP,
    checked_rotation,
    checked_vector,
    orthonormality,
)

# The value checks, the axis and the pitch targets live in .values, .axis and .pitch; their
# names stay importable from here.
__all__ = [
    "KIND_NAMES",
    "MASK_COMPONENTS",
    "ROTATION_SNAP",
    "TOOL_AXES",
    "AxisTarget",
    "PitchTarget",
    "PoseTarget",
    "PositionTarget",
    "Target",
    "axis_turn",
    "describe_kinds",
    "is_partial",
    "kind_error",
    "orthonormality",
    "rpy_matrix",
]

_twin = twin("_pose_check")  # the pose check on the short way in C (optional: same verdict, faster)
_exact_pack = _twin.exact_pack if _twin is not None else None


_EYE = np.eye(3)


@dataclass(frozen=True, eq=False)
class PositionTarget:
    """A tool position; the orientation is free.

    Attributes:
        position: Tool point in the world frame [m], shape (3,).
    """

    position: np.ndarray
    #: No orientation, no posture preference (what the numeric stages read of a target).
    rotation = None
    posture = None
    position_only = True
    #: No packed values: the compiled solvers read ``position`` (see :class:`PoseTarget`).
    _packed = None

    def __init__(self, position: npt.ArrayLike):
        self.__dict__["position"] = checked_vector(position, 3, "position")  # frozen: set once here

    @property
    def finite(self) -> bool:
        """Whether every value is finite (always, unless its array was made writeable again)."""
        position = self.position
        return not position.flags.writeable or all(map(math.isfinite, position.tolist()))


#: The components of a pose error, in the order of a mask (the Robotics Toolbox's): the
#: position along the world axes, then the rotation about the world axes.
MASK_COMPONENTS = ("x", "y", "z", "rx", "ry", "rz")


def _mask(values: object) -> tuple[bool, ...] | None:
    """A mask of 6 flags (1 = constrained) or None when every component is constrained."""
    if values is None:
        return None
    try:
        flags = [float(v) for v in values]  # type: ignore[attr-defined]
    except (TypeError, ValueError) as err:
        raise TargetError(f"mask must be 6 flags 0 or 1 (x y z rx ry rz), got {values!r}") from err
    if len(flags) != 6 or any(f not in (0.0, 1.0) for f in flags):
        raise TargetError(
            f"mask must be 6 flags 0 or 1 (x y z rx ry rz: 1 = constrained), got {values!r}"
        )
    if not any(flags):
        raise TargetError("mask constrains nothing: give at least one 1 (x y z rx ry rz)")
    mask = tuple(f == 1.0 for f in flags)
    return None if all(mask) else mask


@dataclass(frozen=True, eq=False)
class PoseTarget:
    """A tool pose ``T_world_tool``, whole or with some components left free (a mask).

    The error of a joint vector is ``e = (p_target - p, log3(R_target R^T))``: the position along
    the world axes [m] and the rotation vector about the world axes [rad] (the Robotics
    Toolbox's ``ik_LM`` error). A mask keeps the components flagged 1, in the order
    :data:`MASK_COMPONENTS` ``(x, y, z, rx, ry, rz)``; a solution is verified on those only. A
    SCARA's task is ``mask=(1, 1, 1, 0, 0, 1)``: the position and the yaw.

    Attributes:
        position: Tool point in the world frame [m], shape (3,).
        rotation: Tool axes in the world frame, shape (3, 3).
        mask: Six flags, True where the component is constrained, or None: all are (the default;
            a mask of six 1 is None too).
    """

    position: np.ndarray
    rotation: np.ndarray
    mask: tuple[bool, ...] | None = None
    #: No posture preference (what the numeric stages read of a target).
    posture = None
    position_only = False

    def __init__(
        self, position: npt.ArrayLike, rotation: npt.ArrayLike, mask: object | None = None
    ):
        fields = self.__dict__  # frozen: set once here (cheaper than object.__setattr__)
        # The short way of a solve loop's float64 arrays: the 12 values checked by the compiled
        # twin (all finite, max |R^T R - I| <= _ROTATION_EXACT, det R > 0) and kept packed in
        # bytes, which the compiled solvers read as they are; ``position`` and ``rotation`` are
        # views of them made on first read (_PackedArray). None sends anything else the long
        # way, which says what is wrong and keeps read-only copies.
        short = _exact_pack
        packed = None if short is None else short(position, rotation, _ROTATION_EXACT)
        if packed is None:
            fields["position"] = checked_vector(position, 3, "position")
            fields["rotation"] = checked_rotation(rotation)
        fields["_packed"] = packed
        fields["mask"] = None if mask is None else _mask(mask)

    def __getstate__(self) -> dict[str, object]:
        """The fields to pickle or copy: the packed values, not the views made of them."""
        state = dict(self.__dict__)
        if state["_packed"] is not None:
            state.pop("position", None)
            state.pop("rotation", None)
        return state

    @property
    def free(self) -> tuple[str, ...]:
        """The names of the free components (of :data:`MASK_COMPONENTS`), ``()`` without a mask."""
        if self.mask is None:
            return ()
        return tuple(name for name, kept in zip(MASK_COMPONENTS, self.mask) if not kept)

    @classmethod
    def from_matrix(cls, T_world_tool: npt.ArrayLike, mask: object | None = None) -> PoseTarget:
        """From a 4x4 homogeneous matrix (or a ``pin.SE3``)."""
        homogeneous = getattr(T_world_tool, "homogeneous", T_world_tool)
        matrix = np.asarray(homogeneous, dtype=float)
        if matrix.shape != (4, 4):
            raise TargetError(f"a pose must be a 4x4 matrix, got shape {matrix.shape}")
        return cls(matrix[:3, 3], matrix[:3, :3], mask)

    @classmethod
    def from_rpy(
        cls, position: npt.ArrayLike, rpy: npt.ArrayLike, mask: object | None = None
    ) -> PoseTarget:
        """From a position [m] and URDF roll-pitch-yaw [rad]: ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
        return cls(position, rpy_matrix(rpy), mask)

    @property
    def finite(self) -> bool:
        """Whether every value is finite (always, unless an array was made writeable again)."""
        if self.__dict__["_packed"] is not None:  # immutable: as checked
            return True
        position, rotation = self.position, self.rotation
        if not (position.flags.writeable or rotation.flags.writeable):
            return True
        isfinite = math.isfinite
        return all(map(isfinite, position.tolist())) and all(
            map(isfinite, rotation.ravel().tolist())
        )


class _PackedArray:
    """A :class:`PoseTarget` array read from its packed values, made on first read and kept.

    A view of the bytes the compiled check packed (immutable, so the array is read-only for
    good), stored in the instance's dict, which shadows this descriptor from then on: later
    reads cost what an attribute costs. A target built the long way has its arrays in its dict
    from the start.
    """

    def __init__(self, name: str, offset: int, shape: tuple[int, ...]):
        self._name = name
        self._offset = offset  # [bytes]
        self._shape = shape

    def __get__(self, target: object, owner: type | None = None) -> np.ndarray:
        if target is None:  # the class attribute (dataclasses look it up)
            return self  # type: ignore[return-value]
        fields = target.__dict__
        array = np.ndarray(self._shape, _FLOAT64, fields["_packed"], self._offset)
        fields[self._name] = array
        return array


# After the dataclass is made (its fields have no defaults): views of the packed values.
PoseTarget.position = _PackedArray("position", 0, (3,))  # type: ignore[assignment]
PoseTarget.rotation = _PackedArray("rotation", 24, (3, 3))  # type: ignore[assignment]


def rpy_matrix(rpy: npt.ArrayLike) -> list[list[float]]:
    """URDF roll-pitch-yaw [rad] as a rotation matrix ``Rz(yaw) Ry(pitch) Rx(roll)`` (rows).

    :func:`kin.ik.angles.rpy_matrix` of three checked numbers.

    Raises:
        TargetError: ``rpy`` is not three finite numbers.
    """
    return angles.rpy_matrix(*checked_vector(rpy, 3, "rpy"))


Target = PositionTarget | PoseTarget | PitchTarget | AxisTarget


def is_partial(target: object, nq: int) -> bool:
    """Whether ``target`` is solved here: an axis target, a masked pose, or a pose on < 6 joints."""
    cls = target.__class__
    if cls is AxisTarget:
        return True
    return cls is PoseTarget and (target.mask is not None or nq < 6)  # type: ignore[attr-defined]


#: Target kinds in user terms, as error messages name them.
KIND_NAMES: dict[type, str] = {
    PositionTarget: "position",
    PitchTarget: "position with pitch (and roll)",
    AxisTarget: "position with a tool axis",
    PoseTarget: "full pose",
}


def describe_kinds(kinds: tuple[type, ...]) -> str:
    """``"position or full pose"``: the user terms of ``kinds`` (in :data:`KIND_NAMES` order)."""
    names = [name for kind, name in KIND_NAMES.items() if kind in kinds]
    if len(names) > 2:
        return ", ".join(names[:-1]) + " or " + names[-1]
    return " or ".join(names) if names else "no target"


def kind_error(robot: str, kinds: tuple[type, ...], target: object) -> TargetError:
    """The error for a target of a kind ``robot`` cannot take (``kinds`` are those it can)."""
    given = KIND_NAMES.get(type(target), type(target).__name__)
    return TargetError(f"'{robot}' takes a {describe_kinds(kinds)} target, not a {given} target")
