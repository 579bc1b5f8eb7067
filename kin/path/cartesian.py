"""Tool poses along a straight line or a polyline of waypoints, sampled in N steps.

Frames and units: every pose is ``T_world_tool`` (world = the URDF root), positions in meters.
Between two waypoints the position moves on the straight segment at a constant rate and the
orientation turns at a constant rate about one axis (quaternion slerp, Pinocchio's
``Quaternion.slerp``); a five-joint arm's pitch (and wrist roll) moves linearly. Every waypoint is
a sample, so consecutive samples always lie on one segment.

The waypoints are :mod:`kin.ik` targets, all of one kind: :class:`~kin.ik.PositionTarget`
(position-only arms), :class:`~kin.ik.PoseTarget` (full pose, or all with one mask),
:class:`~kin.ik.AxisTarget` (a tool axis, roll free: the axis turns at a constant rate on the
great circle between two waypoints' axes) or :class:`~kin.ik.PitchTarget` (five-joint arms).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..ik.targets.target import (
    AxisTarget,
    PitchTarget,
    PoseTarget,
    PositionTarget,
    Target,
    axis_turn,
)
from .exceptions import PathError

#: Length that one radian of tool rotation (or pitch) counts for when steps are shared out among
#: the segments of a polyline [m/rad].
ROTATION_LENGTH = 0.1


@dataclass(frozen=True, eq=False)
class CartesianPath:
    """Samples of a tool path, waypoints included.

    Attributes:
        kind: Class of the targets (``PositionTarget``, ``PoseTarget`` or ``PitchTarget``).
        positions: Tool points in the world frame [m], shape (M, 3).
        rotations: ``R_world_tool`` per sample, shape (M, 3, 3), for pose paths; else None.
        pitches: Approach angle below the horizontal per sample [rad], for pitch paths; else None.
        rolls: Wrist-roll joint value per sample [rad] for pitch paths that give one; else None.
        waypoint_indices: Sample index of each waypoint, first 0 and last M - 1.
        axes: World direction of the tool axis per sample, shape (M, 3), for axis paths; else
            None.
        tool_axis: The tool axis of an axis path (``"x"``, ``"y"``, ``"z"``).
        mask: The mask of a masked pose path (every waypoint's), else None.
    """

    kind: type
    positions: np.ndarray
    rotations: np.ndarray | None
    pitches: np.ndarray | None
    rolls: np.ndarray | None
    waypoint_indices: tuple[int, ...]
    axes: np.ndarray | None = None
    tool_axis: str = "z"
    mask: tuple[bool, ...] | None = None

    def __len__(self) -> int:
        return int(self.positions.shape[0])

    @property
    def length(self) -> float:
        """Length of the tool point's path [m]."""
        return float(np.linalg.norm(np.diff(self.positions, axis=0), axis=1).sum())

    def target(self, index: int) -> Target:
        """The IK target of sample ``index`` (world frame, SI)."""
        position = self.positions[index]
        if self.axes is not None:
            return AxisTarget(position, self.axes[index], self.tool_axis)
        if self.rotations is not None:
            return PoseTarget(position, self.rotations[index], self.mask)
        if self.pitches is not None:
            roll = None if self.rolls is None else float(self.rolls[index])
            return PitchTarget(position, float(self.pitches[index]), roll)
        return PositionTarget(position)


def line(start: Target, end: Target, steps: int) -> CartesianPath:
    """The straight path from ``start`` to ``end`` in ``steps`` equal steps (``steps + 1`` samples)."""
    return polyline([start, end], steps)


def polyline(waypoints: Sequence[Target], steps: int) -> CartesianPath:
    """The path through ``waypoints`` in ``steps`` steps in all.

    The steps are shared out among the segments in proportion to their length (position change
    [m] plus :data:`ROTATION_LENGTH` times the rotation or pitch change [rad]), at least one each;
    within a segment they are equal.

    Args:
        waypoints: Two or more targets of one kind, world frame, SI.
        steps: Number of steps (samples minus one), at least the number of segments.

    Raises:
        PathError: Fewer than two waypoints, mixed kinds, non-finite values, or too few steps.
    """
    if len(waypoints) < 2:
        raise PathError(f"a path needs at least 2 waypoints, got {len(waypoints)}", "waypoints")
    kind = type(waypoints[0])
    for number, waypoint in enumerate(waypoints, start=1):
        if type(waypoint) is not kind:
            raise PathError(
                f"every waypoint must be of one kind: waypoint 1 is a {kind.__name__}, "
                f"waypoint {number} a {type(waypoint).__name__}",
                f"waypoint {number}",
            )
        if not waypoint.finite:
            raise PathError(f"waypoint {number} is not finite", f"waypoint {number}")
    if kind is PoseTarget and len({getattr(w, "mask", None) for w in waypoints}) > 1:
        raise PathError("give every waypoint the same mask (or none)", "mask")
    if kind is AxisTarget and len({getattr(w, "tool_axis", "z") for w in waypoints}) > 1:
        raise PathError("give every waypoint the same tool axis", "tool_axis")
    rolls_given = [getattr(w, "roll", None) is not None for w in waypoints]
    if kind is PitchTarget and any(rolls_given) and not all(rolls_given):
        raise PathError("give the wrist roll at every waypoint or at none", "roll")
    segments = len(waypoints) - 1
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < segments:
        raise PathError(
            f"steps must be an integer of at least {segments} (one per segment), got {steps!r}",
            "steps",
        )
    lengths = [_segment_length(a, b) for a, b in zip(waypoints, waypoints[1:])]
    for number, length in enumerate(lengths, start=1):
        if not math.isfinite(length):  # e.g. a waypoint 1e308 m away
            raise PathError(
                f"segment {number} (waypoints {number} and {number + 1}) is too long to sample "
                f"({length:g} m): give waypoints the arm can reach",
                f"waypoint {number + 1}",
            )
    counts = _share_steps(lengths, steps)
    positions, rotations, pitches, rolls, axes = [], [], [], [], []
    indices = [0]
    for k, (a, b) in enumerate(zip(waypoints, waypoints[1:])):
        fractions = np.arange(0 if k == 0 else 1, counts[k] + 1) / counts[k]
        positions.append(a.position + np.outer(fractions, b.position - a.position))
        if isinstance(a, PoseTarget) and isinstance(b, PoseTarget):
            qa, qb = pin.Quaternion(a.rotation), pin.Quaternion(b.rotation)
            rotations += [qa.slerp(float(f), qb).toRotationMatrix() for f in fractions]
        elif isinstance(a, AxisTarget) and isinstance(b, AxisTarget):
            turn = axis_turn(a.axis, b.axis)
            axes += [pin.exp3(turn * float(f)) @ a.axis for f in fractions]
        elif isinstance(a, PitchTarget) and isinstance(b, PitchTarget):
            pitches.append(a.pitch + fractions * (b.pitch - a.pitch))
            if a.roll is not None and b.roll is not None:
                rolls.append(a.roll + fractions * (b.roll - a.roll))
        indices.append(indices[-1] + counts[k])
    return CartesianPath(
        kind=kind,
        positions=np.concatenate(positions),
        rotations=np.array(rotations) if rotations else None,
        pitches=np.concatenate(pitches) if pitches else None,
        rolls=np.concatenate(rolls) if rolls else None,
        waypoint_indices=tuple(indices),
        axes=np.array(axes) if axes else None,
        tool_axis=getattr(waypoints[0], "tool_axis", "z"),
        mask=getattr(waypoints[0], "mask", None),
    )


def _segment_length(a: Target, b: Target) -> float:
    """Position change [m] plus :data:`ROTATION_LENGTH` times the angle change [rad]."""
    length = math.hypot(*(b.position - a.position).tolist())  # inf, not an overflow, when huge
    if isinstance(a, PoseTarget) and isinstance(b, PoseTarget):
        turn = pin.log3(a.rotation.T @ b.rotation)
        length += ROTATION_LENGTH * math.sqrt(float(turn @ turn))
    elif isinstance(a, AxisTarget) and isinstance(b, AxisTarget):
        length += ROTATION_LENGTH * float(np.linalg.norm(axis_turn(a.axis, b.axis)))
    elif isinstance(a, PitchTarget) and isinstance(b, PitchTarget):
        length += ROTATION_LENGTH * abs(b.pitch - a.pitch)
        if a.roll is not None and b.roll is not None:
            length += ROTATION_LENGTH * abs(b.roll - a.roll)
    return length


def _share_steps(lengths: list[float], steps: int) -> list[int]:
    """``steps`` split in proportion to ``lengths``, at least 1 each (largest remainders)."""
    total = sum(lengths)
    n = len(lengths)
    if total <= 0.0:
        weights = [1.0 / n] * n
    else:
        weights = [length / total for length in lengths]
    spare = steps - n  # one step per segment is given first
    shares = [w * spare for w in weights]
    counts = [1 + int(math.floor(s)) for s in shares]
    order = sorted(range(n), key=lambda k: shares[k] - math.floor(shares[k]), reverse=True)
    for k in order[: steps - sum(counts)]:
        counts[k] += 1
    return counts


def segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each point to the segment from ``a`` to ``b`` (row-wise) [m].

    Args:
        points: Points, shape (K, 3) [m].
        a: Segment starts, shape (K, 3) [m].
        b: Segment ends, shape (K, 3) [m].
    """
    ab = b - a
    ap = points - a
    squared = np.einsum("ij,ij->i", ab, ab)
    safe = np.where(squared > 0.0, squared, 1.0)
    fraction = np.clip(np.einsum("ij,ij->i", ap, ab) / safe, 0.0, 1.0)
    fraction = np.where(squared > 0.0, fraction, 0.0)
    return np.linalg.norm(points - (a + fraction[:, None] * ab), axis=1)
