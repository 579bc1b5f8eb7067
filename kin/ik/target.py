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

from . import angles
from .exceptions import TargetError

_twin = twin("_pose_check")  # the pose check on the short way in C (optional: same verdict, faster)
_exact_pack = _twin.exact_pack if _twin is not None else None

#: Largest ``max |R^T R - I|`` of a target rotation replaced by its nearest rotation matrix; a
#: farther matrix is refused.
ROTATION_SNAP = 1e-3
#: Largest ``max |R^T R - I|`` taken as it is (the rounding of a product of rotations).
_ROTATION_EXACT = 1e-12
#: NumPy's float64, compared by identity on the short way of :func:`_checked`.
_FLOAT64 = np.dtype(float)


def _vector(values: npt.ArrayLike, size: int, what: str) -> np.ndarray:
    """``values`` as a new float array of ``size`` finite numbers (a TargetError names the field)."""
    return _checked(values, size, what)[0]


def _checked(values: npt.ArrayLike, size: int, what: str) -> tuple[np.ndarray, list[float]]:
    """:func:`_vector`, and its values as Python floats (row-major).

    A float64 array of the right size (what a solve loop hands in) takes the short way: one
    copy, one sum of Python floats for the finiteness check (about 0.6 us; the general way,
    through ``np.array`` and a reshape, about 1.3 us).
    """
    if type(values) is np.ndarray and values.dtype is _FLOAT64 and values.size == size:
        array = values.flatten()  # a copy, one-dimensional
    else:
        try:
            array = np.array(values, dtype=float).reshape(-1)
        except (TypeError, ValueError, OverflowError) as err:
            raise TargetError(f"{what} must be {size} numbers, got {values!r}") from err
        if array.size != size:
            raise TargetError(f"{what} must be {size} numbers, got {array.size}")
    floats = array.tolist()
    # A finite sum means every value is finite (a NaN or an infinity makes it NaN or infinite);
    # a sum that overflows is looked at value by value.
    if not math.isfinite(sum(floats)) and not all(map(math.isfinite, floats)):
        i = int(np.flatnonzero(~np.isfinite(array))[0])
        where = f"{what}[{i}]" if size <= 3 else f"{what}[{i // 3}][{i % 3}]"
        raise TargetError(f"{where} is {array[i]}: every target value must be a finite number")
    array.setflags(write=False)  # checked once: it cannot change after (a copy of the input)
    return array, floats


def orthonormality(*entries: float) -> tuple[float, float]:
    """``max |R^T R - I|`` and ``det R`` of a 3x3 matrix given row-major (9 finite floats).

    A matrix whose entry's square overflows has deviation ``inf`` and determinant NaN.
    """
    a, b, c, d, e, f, g, h, i = entries
    # The entries of R^T R - I (symmetric: six of them), the diagonal first: an entry whose
    # square overflows makes a diagonal one infinite, and a NaN after it (inf - inf off the
    # diagonal) does not replace that maximum.
    deviation = max(
        abs(a * a + d * d + g * g - 1.0),
        abs(b * b + e * e + h * h - 1.0),
        abs(c * c + f * f + i * i - 1.0),
        abs(a * b + d * e + g * h),
        abs(a * c + d * f + g * i),
        abs(b * c + e * f + h * i),
    )
    if deviation == math.inf:
        return deviation, math.nan
    return deviation, a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)


def _rotation(values: npt.ArrayLike) -> np.ndarray:
    """A rotation matrix from 9 numbers (row-major): checked, snapped to SO(3) when nearly one.

    The check runs on Python floats (a few microseconds): a target is built once per solve.
    """
    if type(values) is np.ndarray and values.dtype is _FLOAT64 and values.shape == (3, 3):
        matrix = values.copy()  # the short way of a solve loop's float64 3x3 (about 1 us less)
        (a, b, c), (d, e, f), (g, h, i) = matrix.tolist()
        if not math.isfinite(a + b + c + d + e + f + g + h + i):
            matrix = _checked(values, 9, "rotation")[0].reshape(3, 3)  # names the entry
    else:
        flat, floats = _checked(values, 9, "rotation")
        matrix = flat.reshape(3, 3)
        a, b, c, d, e, f, g, h, i = floats
    deviation, determinant = orthonormality(a, b, c, d, e, f, g, h, i)
    if deviation <= _ROTATION_EXACT and determinant > 0.0:
        matrix.setflags(write=False)
        return matrix
    if deviation <= ROTATION_SNAP and determinant > 0.0:
        u, _, vt = np.linalg.svd(matrix)
        snapped = u @ vt
        snapped.setflags(write=False)
        return snapped
    raise TargetError(
        f"rotation is not a rotation matrix (max |R^T R - I| = {deviation:.3g}, "
        f"det = {determinant:.3g}): give orthonormal axes with det +1 "
        f"(a matrix off by at most {ROTATION_SNAP:g} is rounded to the nearest rotation)"
    )


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
        self.__dict__["position"] = _vector(position, 3, "position")  # frozen: set once here

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
            fields["position"] = _vector(position, 3, "position")
            fields["rotation"] = _rotation(rotation)
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
    return angles.rpy_matrix(*_vector(rpy, 3, "rpy"))


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
        object.__setattr__(self, "position", _vector(position, 3, "position"))
        direction = _vector(axis, 3, "axis")
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


@dataclass(frozen=True, eq=False)
class PitchTarget:
    """A tool position with the tool pitch, and optionally the wrist roll, of a five-joint arm.

    ``pitch`` is the angle of the tool's approach axis (the wrist-roll axis, pointing from the
    wrist to the tool) *below the horizontal*, measured in the vertical plane through the base
    axis and the target, from the horizontal direction pointing away from the base axis:
    ``approach = cos(pitch) h - sin(pitch) z0`` with ``h`` the horizontal unit vector from the base
    axis to the target. So 0 is "pointing straight out", +pi/2 "pointing straight down", -pi/2
    "pointing straight up". It does not depend on the branch (shoulder front or back). For the
    Abaas et al. arm (``lab5``, 002) with the shoulder in front, ``pitch = pi/2 - (q2 + q3 + q4)``:
    the paper's eq. (9) ``90 - theta234 = +phi``.

    Attributes:
        position: Tool point in the world frame [m], shape (3,).
        pitch: Approach angle below the horizontal [rad].
        roll: Wrist-roll joint value ``q5`` [rad] (as the papers pose it), or None to keep the
            seed's.
    """

    position: np.ndarray
    pitch: float
    roll: float | None = None

    def __init__(self, position: npt.ArrayLike, pitch: float, roll: float | None = None):
        object.__setattr__(self, "position", _vector(position, 3, "position"))
        object.__setattr__(self, "pitch", _angle(pitch, "pitch"))
        object.__setattr__(self, "roll", None if roll is None else _angle(roll, "roll"))

    @property
    def finite(self) -> bool:
        """Whether every value is finite."""
        isfinite = math.isfinite
        return (
            all(map(isfinite, self.position.tolist()))
            and isfinite(self.pitch)
            and (self.roll is None or isfinite(self.roll))
        )


def _angle(value: object, what: str) -> float:
    """``value`` as a finite float [rad] (a TargetError names the field)."""
    try:
        angle = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError) as err:
        raise TargetError(f"{what} must be a number [rad], got {value!r}") from err
    if not math.isfinite(angle):
        raise TargetError(f"{what} is {angle}: every target value must be a finite number")
    return angle


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
