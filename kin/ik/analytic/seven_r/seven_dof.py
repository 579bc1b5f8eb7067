"""Closed-form IK of the seven-joint arm (:class:`~kin.ik.analytic.structure.SevenDof`) for chosen joint-1 angles.

The arm is redundant: joint 1 is left free. For a given ``q1`` the elbow, the shoulder and the
wrist follow in closed form (:mod:`.seven_dof_steps`, its frames :mod:`.seven_dof_frames`;
both held by :class:`SevenDofIK`): up to 8 joint vectors for a full pose, up
to 4 for a position (the wrist angles ``q5, q6, q7`` chosen too). This module chooses ``q1``:
:meth:`SevenDofIK.first` from starts (their joint 1, scanned outward when asked),
:meth:`SevenDofIK.branches_at` at stated values (limits ignored).

The numeric solver (:mod:`ik.numeric`) picks ``q1`` (and the wrist) from its seed table and has
Pinocchio judge every answer. :meth:`SevenDofIK.first` runs the compiled twin of these steps
(``kin/_native/ik/analytic/seven_r/_closed7.c``, an optional extension built at install when a C compiler is there)
and their Python code otherwise; the tests compare the two. ``t_i`` are DH angles,
``q_i = t_i - theta_i`` joint values [rad]; lengths in [m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np

from kin._native import twin

from ..structure import SevenDof
from .seven_dof_frames import SevenDofFrames
from .seven_dof_steps import SevenDofSteps
from .subproblems import scan
from .twin_form import TwinForm

_closed7 = twin("_closed7")

#: Whether the compiled twin (``kin/_native/ik/analytic/seven_r/_closed7.c``) is built.
COMPILED = _closed7 is not None


class SevenDofIK(TwinForm):
    """Closed-form branches of a :class:`~kin.ik.analytic.structure.SevenDof` arm for chosen free joints.

    Holds its constants and targets' frames (:attr:`frames`,
    :class:`~.seven_dof_frames.SevenDofFrames`) and its steps at one joint-1 value (:attr:`steps`,
    :class:`~.seven_dof_steps.SevenDofSteps`), and hands on their methods as its own
    (:meth:`~.SevenDofFrames.prepare`, :meth:`~.SevenDofFrames.pose_frame`,
    :meth:`~.SevenDofFrames.frame0`, :meth:`~.SevenDofFrames.tool_point4`,
    :meth:`~.SevenDofFrames.elbow_vector`, :meth:`~.SevenDofFrames.seed_frames`,
    :meth:`~.SevenDofSteps.pose`, :meth:`~.SevenDofSteps.position`): bound, not forwarded, so a
    call costs no more than before.

    Args:
        structure: The arm's parameters.
        lower: Lower joint limits [rad] (7).
        upper: Upper joint limits [rad] (7).
    """

    twin_module = _closed7  # its :meth:`first`'s (``compiled_twin``: whether it is built)
    #: The free joint (0-based): joint 1.
    free: ClassVar[int] = 0

    def __init__(self, structure: SevenDof, lower: Sequence[float], upper: Sequence[float]):
        self.structure = structure
        frames = SevenDofFrames(structure, lower, upper)
        steps = SevenDofSteps(frames)
        self.frames, self.steps = frames, steps
        self.lower, self.upper = frames.lower, frames.upper
        self._sin, self._cos, self._offsets = frames.sin, frames.cos, frames.offsets
        self._plain = frames.plain
        self._c_params = None
        self._unlimited: SevenDofIK | None = None
        # their methods, handed on as this solver's own: bound, so no forwarding call
        self.prepare = frames.prepare
        self.pose_frame = frames.pose_frame
        self.frame0 = frames.frame0
        self.tool_point4 = frames.tool_point4
        self.elbow_vector = frames.elbow_vector
        self.seed_frames = frames.seed_frames
        self.pose = steps.pose
        self.position = steps.position

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (:meth:`~.SevenDofFrames.c_fields`)."""
        return self.frames.c_fields()

    def many_targets(
        self, positions: np.ndarray, rotations: np.ndarray | None
    ) -> tuple[tuple[Any, ...], np.ndarray | None]:
        """N world targets as the twin's ``first_many`` reads them.

        :meth:`~.SevenDofFrames.many_targets`: ``((mode,), targets)``, positions [m].
        """
        return self.frames.many_targets(positions, rotations)

    def branches_at(
        self,
        position: np.ndarray,
        rotation: np.ndarray | None,
        values: np.ndarray,
        folds: np.ndarray | None = None,
    ) -> np.ndarray | None:
        """Every branch (G, 8, 7) [rad] of a tool pose at joint-1 values (G,), limits ignored.

        :meth:`pose` at each value, of the same arm without limits (joints 2-7 in [-pi, pi]),
        NaN rows where there is none; None for a position (its wrist is free too). ``folds``
        (G,): receives each value's :meth:`pose` folds' least (inf: no equation).
        """
        if rotation is None:
            return None
        if self._unlimited is None:
            turn = [-math.pi] * 7, [math.pi] * 7
            self._unlimited = SevenDofIK(self.structure, *turn)
        frame = self.pose_frame(position, rotation)
        out = np.full((values.shape[0], 8, 7), np.nan)
        for k, q1 in enumerate(values.tolist()):
            seen: list[float] | None = None if folds is None else []
            found = self._unlimited.pose(q1, frame, seen)
            if seen is not None and folds is not None:
                folds[k] = min(seen, default=math.inf)
            if found:
                out[k, : len(found)] = found
        return out

    def first(
        self,
        target: tuple[int, np.ndarray],
        starts: np.ndarray,
        out: np.ndarray,
        step: float = 0.0,
        compiled: bool = True,
    ) -> int:
        """The first start from which a branch inside the limits reaches the target.

        For a full pose the branches depend on joint 1 alone (the start only picks one); for a
        position on joints 1 and 5-7. A start whose joint 1 gives no branch inside the limits
        scans joint 1 outward from there when ``step > 0``: ``q1 +- step``, ``q1 +- 2 step``, ...
        inside its limits; the first joint-1 value with a branch is taken (the nearest to the
        start's, at that resolution).

        Args:
            target: :meth:`prepare` of the target.
            starts: Start joint vectors [rad], shape (k, 7); clipped into the limits, a row with a
                value that is not finite skipped. Joint 1 (and for a position joints 5-7) are
                kept, the others solved.
            out: Receives the branch nearest that start [rad], shape (7,).
            step: Joint-1 scan step [rad] (0: no scan).
            compiled: Use the compiled twin when it is built (False: this module's Python).

        Returns:
            The index of that start, or -1 (``out`` untouched).
        """
        mode, values = target
        if compiled and _closed7 is not None:
            if not values.flags.c_contiguous:
                values = np.ascontiguousarray(values)
            if not starts.flags.c_contiguous or starts.dtype != np.float64:
                starts = np.ascontiguousarray(starts, dtype=float)
            return _closed7.first(self.c_params, mode, values, starts, out, step)
        lows, highs = self.lower, self.upper
        if mode == 0:
            frame = self.frames.frame_of(values[:3].tolist(), values[3:].reshape(3, 3).tolist())
        else:
            point = values.tolist()
        if starts.ndim != 2 or starts.shape[1] != 7:
            raise ValueError(f"starts: not k x 7, got shape {starts.shape}")
        for index, start in enumerate(starts.tolist()):
            if not all(map(math.isfinite, start)):
                continue  # no joint 1 to keep
            clipped = [min(max(v, lo), hi) for v, lo, hi in zip(start, lows, highs)]
            u = None if mode == 0 else self.elbow_vector(*clipped[4:])
            found = []
            for q1 in scan(clipped[0], step, lows[0], highs[0]):
                if mode == 0:
                    found = self.pose(q1, frame)
                else:
                    found = self.position(q1, clipped[4:], point, u)
                if found:
                    break
            if found:
                found.sort(key=lambda q: sum((a - b) ** 2 for a, b in zip(q, clipped)))
                out[:] = found[0]
                return index
        return -1
