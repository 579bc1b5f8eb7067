"""IK targets from command-line terms, and target-kind errors worded in those terms.

A target is a tool position (``--target X Y Z``) with, optionally, an orientation: ``--rpy``
(URDF roll-pitch-yaw), ``--quat`` (unit quaternion w x y z), either with ``--mask`` (the
components kept: x y z rx ry rz, 1 = constrained), ``--axis`` (the world direction of the tool's
z axis, roll free) or ``--pitch`` (approach angle of a five-joint arm, with ``--roll``).
``kin ik --stdin`` reads the same fields from JSON lines (``"target"``, ``"rpy"``, ``"quat"``,
``"mask"``, ``"axis"``, ``"pitch"``, ``"roll"``, ``"position_only"``).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from dh2urdf.quoted_input import quoted

from ..cli import finite_float
from ..ik.exceptions import TargetError
from ..ik.targets.given import ZERO_QUATERNION, target_from_values
from ..ik.targets.target import AxisTarget, PitchTarget, PoseTarget, PositionTarget, Target
from .joint_units import beyond_a_turn

#: What each target class is called on the command line.
KIND_TERMS: dict[type, str] = {
    PoseTarget: "--rpy, --quat",
    AxisTarget: "--axis",
    PitchTarget: "--pitch [--roll]",
    PositionTarget: "a position target",
}


def add_orientation_options(parser: argparse.ArgumentParser) -> None:
    """Add ``--rpy``, ``--quat``, ``--mask`` and ``--axis`` (the target's orientation terms)."""
    add = parser.add_argument
    add("--rpy", type=finite_float, nargs=3, metavar=("R", "P", "Y"), help="URDF roll-pitch-yaw")
    add("--quat", type=finite_float, nargs=4, metavar=("W", "X", "Y", "Z"), help="unit quaternion")
    add(
        "--mask",
        type=finite_float,
        nargs=6,
        metavar=("X", "Y", "Z", "RX", "RY", "RZ"),
        help="with --rpy/--quat: the pose components kept (1) or free (0); rotations about the "
        "world axes (a SCARA: 1 1 1 0 0 1)",
    )
    add(
        "--axis",
        type=finite_float,
        nargs=3,
        metavar=("AX", "AY", "AZ"),
        help="world direction of the tool's z axis; the roll about it is free (a drill)",
    )


def _finite(values: object, size: int, what: str) -> list[float]:
    """``values`` as ``size`` finite floats (JSON numbers or argparse floats; no booleans)."""
    items = [values] if size == 1 and not isinstance(values, (list, tuple)) else values
    if not isinstance(items, (list, tuple)) or len(items) != size:
        raise TargetError(f"{what} must be {size} number(s), got {quoted(values)}")
    for value in items:
        if value.__class__ is not float and (
            isinstance(value, bool) or not isinstance(value, (int, float))
        ):
            raise TargetError(f"{what} must be numbers, got {quoted(values)}")
    if not all(map(math.isfinite, items)):
        raise TargetError(f"{what} must be finite, got {quoted(values)}")
    return [float(v) for v in items]  # type: ignore[arg-type]  # checked above


def _refuse_degrees(option: str, values: list[float]) -> None:
    """Refuse a target angle in radians beyond a turn: degrees given without ``--deg``.

    A joint may turn more than once (a warning, :meth:`~.joint_units.JointUnits.unit_slip`);
    an orientation angle of a target never needs to: ``--rpy 180 0 0`` is 180 degrees meant,
    and solving 180 rad (a different pose) would answer another question.

    Raises:
        TargetError: A value beyond 2 pi; the message names the option and the fix.
    """
    value = beyond_a_turn(values)
    if value is not None:
        raise TargetError(
            f"{option} value {value:g} rad is more than a turn: degrees? then add --deg "
            "(in radians it is at most 2 pi)"
        )


def _mask_flags(values: object) -> list[int]:
    """``--mask``: six flags 0 or 1 (x y z rx ry rz)."""
    items = values if isinstance(values, (list, tuple)) else [values]
    if len(items) != 6 or any(
        isinstance(v, bool) or not isinstance(v, (int, float)) or v not in (0, 1) for v in items
    ):
        raise TargetError(
            f"--mask must be 6 flags 0 or 1 (x y z rx ry rz; 1 = constrained), got {quoted(values)}"
        )
    return [int(v) for v in items]  # type: ignore[call-overload, arg-type]


@dataclass(frozen=True)
class Takes:
    """The target kinds a solver takes, refused by :func:`build_target` before it builds one.

    Attributes:
        robot: Robot name (for the message).
        nq: Number of joints.
        kinds: Target classes the solver accepts.
    """

    robot: str
    nq: int
    kinds: tuple[type, ...]


#: The target class each orientation option chooses.
_OPTION_KINDS: dict[str, type] = {
    "--rpy": PoseTarget,
    "--quat": PoseTarget,
    "--axis": AxisTarget,
    "--pitch": PitchTarget,
}


def build_target(
    position: Sequence[float],
    *,
    rpy: Sequence[float] | None = None,
    quat: Sequence[float] | None = None,
    pitch: float | None = None,
    roll: float | None = None,
    position_only: bool = False,
    length: float = 1.0,
    angle: float = 1.0,
    mask: Sequence[float] | None = None,
    axis: Sequence[float] | None = None,
    tool_axis: str | None = None,
    takes: Takes | None = None,
) -> tuple[Target, str]:
    """The target of the command-line values, and the option that chose its kind.

    Args:
        position: Tool position in the world frame [--unit].
        rpy: URDF roll, pitch, yaw [rad or deg], or None.
        quat: Unit quaternion ``w, x, y, z``, or None.
        pitch: Approach angle below the horizontal [rad or deg], or None.
        roll: Wrist-roll joint value with ``pitch`` [rad or deg], or None.
        position_only: Ignore the orientation (no ``rpy``, ``quat`` or ``pitch`` allowed).
        length: Meters per ``--unit``.
        angle: Radians per input angle unit.
        mask: Six flags 0/1 (x y z rx ry rz) with ``rpy`` or ``quat``, or None.
        axis: World direction of the tool's z axis (the roll about it free), or None.
        tool_axis: With ``axis``: the tool axis ``"x"``, ``"y"`` or ``"z"`` (None: z).
        takes: The kinds the solver takes (a kind it does not take is refused before the target
            is built, as :func:`check_kind` words it), or None.

    Returns:
        The target in SI units, and ``"--rpy"``, ``"--quat"``, ``"--axis"``, ``"--pitch"`` or
        ``"a position target"``.

    Raises:
        TargetError: Contradictory options or malformed values.
    """
    p = _finite(position, 3, "the target position")
    if mask is not None and rpy is None and quat is None:
        raise TargetError("--mask needs --rpy or --quat (the pose whose components it keeps)")
    given = [
        name
        for name, v in (("--rpy", rpy), ("--quat", quat), ("--axis", axis), ("--pitch", pitch))
        if v is not None
    ]
    if position_only and given:
        raise TargetError(f"--position-only excludes {', '.join(given)}")
    if len(given) > 1:
        raise TargetError(f"give one of --rpy, --quat, --axis, --pitch; got {' and '.join(given)}")
    if roll is not None and pitch is None:
        raise TargetError("--roll needs --pitch")
    if tool_axis is not None and axis is None:
        raise TargetError("--tool-axis needs --axis (the world direction it points along)")
    if tool_axis is not None and tool_axis not in ("x", "y", "z"):
        raise TargetError(f"--tool-axis must be x, y or z, got {quoted(tool_axis)}")
    # Every value checked in the command line's words first; the library builds the target.
    values = _checked_values(rpy, quat, axis, pitch, roll, mask, angle)
    option = given[0] if given else "a position target"
    if takes is not None:
        _refuse_kind(takes, _OPTION_KINDS.get(option, PositionTarget), option)
    target = target_from_values(p, tool_axis=tool_axis or "z", length=length, angle=angle, **values)
    return target, option


def _checked_values(
    rpy: object, quat: object, axis: object, pitch: object, roll: object, mask: object, angle: float
) -> dict[str, Any]:
    """The orientation values of :func:`build_target`, checked and named as the library's."""
    values: dict[str, Any] = {}
    if mask is not None:
        values["mask"] = _mask_flags(mask)
    if axis is not None:
        values["axis"] = _finite(axis, 3, "--axis")
    if quat is not None:
        w, x, y, z = values["quaternion"] = _finite(quat, 4, "--quat")
        if math.sqrt(w * w + x * x + y * y + z * z) < ZERO_QUATERNION:
            raise TargetError(f"--quat must not be zero, got {[w, x, y, z]}")
    for option, given, size in (("--rpy", rpy, 3), ("--pitch", pitch, 1)):
        if given is not None:
            checked = _finite(given, size, option)
            if angle == 1.0:
                _refuse_degrees(option, checked)
            values[option[2:]] = checked if size == 3 else checked[0]
    if roll is not None:
        values["roll"] = _finite(roll, 1, "--roll")[0]
    return values


def check_kind(robot: str, nq: int, kinds: tuple[type, ...], target: Target, given: str) -> None:
    """Raise when the solver cannot take ``target``, naming the kinds it can, in CLI terms.

    Args:
        robot: Robot name.
        nq: Number of joints.
        kinds: Target classes the solver accepts.
        target: The target.
        given: The option that chose the target's kind (see :func:`build_target`).

    Raises:
        TargetError: ``target`` is not of one of ``kinds``.
    """
    _refuse_kind(Takes(robot, nq, kinds), type(target), given)


def _refuse_kind(takes: Takes, kind: type, given: str) -> None:
    """Raise when a target of class ``kind`` is not one ``takes`` accepts (:func:`check_kind`)."""
    kinds = takes.kinds
    if issubclass(kind, kinds):
        return
    terms = [term for k, term in KIND_TERMS.items() if k in kinds]
    takes_terms = ", ".join(terms[:-1]) + ", or " + terms[-1] if len(terms) > 1 else "".join(terms)
    if issubclass(kind, PoseTarget) and takes.nq < 6:
        raise TargetError(
            f"a full pose needs at least 6 joints; '{takes.robot}' ({takes.nq} joints) takes "
            f"{takes_terms}: drop --rpy/--quat"
        )
    raise TargetError(f"'{takes.robot}' ({takes.nq} joints) takes: {takes_terms}; got {given}")
