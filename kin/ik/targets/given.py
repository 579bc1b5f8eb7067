"""A target from the values a user gives, in the user's units: the kind chosen by what is given.

The position, and at most one of a URDF roll-pitch-yaw, a quaternion, a tool-axis direction or a
five-joint arm's pitch (with its roll): the one place that tells the kinds apart by the values
given and turns lengths and angles written in a unit into meters and radians. An angle is reduced
modulo a turn in its own unit before it is converted (:func:`dh2urdf.units.angle_to_radians`),
so an angle of any size keeps its digits. The command line words its own errors in its options
first (:func:`kin.commands.targets.build_target`) and then builds the target here.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from dh2urdf.units import angle_to_radians

from .. import angles
from ..exceptions import TargetError
from .axis import AxisTarget
from .pitch import PitchTarget
from .target import PoseTarget, PositionTarget, Target
from .values import checked_angle, checked_floats

__all__ = ["ZERO_QUATERNION", "target_from_values"]

#: A quaternion whose norm is below this is refused as zero (it names no rotation).
ZERO_QUATERNION = 1e-9


def target_from_values(
    position: Sequence[float],
    *,
    rpy: Sequence[float] | None = None,
    quaternion: Sequence[float] | None = None,
    axis: Sequence[float] | None = None,
    tool_axis: str = "z",
    pitch: float | None = None,
    roll: float | None = None,
    mask: Sequence[float] | None = None,
    length: float = 1.0,
    angle: float = 1.0,
) -> Target:
    """The target of ``position`` and the orientation given, in SI units.

    Args:
        position: Tool position in the world frame [length unit].
        rpy: URDF roll, pitch, yaw [angle unit], or None.
        quaternion: Quaternion ``w, x, y, z`` (normalised here; not zero), or None.
        axis: World direction of the tool axis ``tool_axis`` (the roll about it free), or None.
        tool_axis: With ``axis``: the tool axis, ``"x"``, ``"y"`` or ``"z"``.
        pitch: Approach angle below the horizontal [angle unit] (:class:`PitchTarget`), or None.
        roll: With ``pitch``: the wrist-roll joint value [angle unit], or None (the seed's).
        mask: With ``rpy`` or ``quaternion``: six flags 0/1 (x y z rx ry rz), or None.
        length: Meters per length unit.
        angle: Radians per angle unit.

    Returns:
        A :class:`PositionTarget` when no orientation is given, else the target of the one given.

    Raises:
        TargetError: More than one orientation, ``roll`` without ``pitch``, ``mask`` without a
            full orientation, a zero quaternion, or a value the target refuses (it names it).
    """
    given = [
        name
        for name, value in (
            ("rpy", rpy),
            ("quaternion", quaternion),
            ("axis", axis),
            ("pitch", pitch),
        )
        if value is not None
    ]
    if len(given) > 1:
        raise TargetError(f"give one orientation of rpy, quaternion, axis, pitch; got {given}")
    if roll is not None and pitch is None:
        raise TargetError("roll needs pitch (the wrist roll of a five-joint arm's pitch target)")
    if mask is not None and rpy is None and quaternion is None:
        raise TargetError("mask needs rpy or quaternion (the pose whose components it keeps)")
    p = [v * length for v in checked_floats(position, 3, "position")[1]]
    if axis is not None:
        return AxisTarget(p, axis, tool_axis)
    if quaternion is not None:
        w, x, y, z = checked_floats(quaternion, 4, "quaternion")[1]
        if math.sqrt(w * w + x * x + y * y + z * z) < ZERO_QUATERNION:
            raise TargetError(f"quaternion must not be zero, got {[w, x, y, z]}")
        return PoseTarget(p, angles.quaternion_matrix(w, x, y, z), mask)
    if rpy is not None:
        rpy_si = [angle_to_radians(v, angle) for v in checked_floats(rpy, 3, "rpy")[1]]
        return PoseTarget.from_rpy(p, rpy_si, mask)
    if pitch is not None:
        roll_si = None if roll is None else checked_angle(roll, "roll") * angle
        return PitchTarget(p, angle_to_radians(checked_angle(pitch, "pitch"), angle), roll_si)
    return PositionTarget(p)
