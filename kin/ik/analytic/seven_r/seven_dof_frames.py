"""The frames of :class:`~.seven_dof.SevenDofIK`: its targets in DH frame 0 and its twin's parameters.

A full pose is read as the wrist centre and two axes of frame 7 in DH frame 0
(:meth:`SevenDofFrames.pose_frame`), a point in DH frame 0 (:meth:`SevenDofFrames.frame0`); the
compiled twin (``kin/_native/ik/analytic/seven_r/_closed7.c``) reads the same through :meth:`SevenDofFrames.prepare`,
:meth:`SevenDofFrames.many_targets`, its parameters :meth:`SevenDofFrames.c_fields` and the
frames of its seeded call :meth:`SevenDofFrames.seed_frames`. Mixed into
:class:`~.seven_dof.SevenDofIK`, which sets the constants. ``t_i`` are DH angles, ``q_i`` joint
values [rad]; lengths in [m].
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..structure import SevenDof
from .subproblems import limit_arcs
from .twin_form import TwinForm

_TWO_PI = 2.0 * math.pi


class SevenDofFrames(TwinForm):
    """Targets and twin parameters of a :class:`~kin.ik.analytic.structure.SevenDof` arm (mixed in)."""

    structure: SevenDof
    _a: tuple[float, ...]
    _d: tuple[float, ...]
    _base_r: np.ndarray
    _base_t: np.ndarray
    _tool_r: np.ndarray
    _tool_t: np.ndarray
    _plain: bool
    _shoulder3: tuple[float, float, float]
    _shoulder3_2: float
    _wrist_u: tuple[float, float, float]
    _wrist7: tuple[float, float, float]
    _axis7: tuple[float, float, float]
    _g: tuple[float, float, float]

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (its ``CLOSED7_PARAMS``; lengths [m])."""
        return {
            "off": self._offsets,
            "sin": self._sin,
            "cos": self._cos,
            "a": self._a,
            "d": self._d,
            "lo": self.lower,
            "hi": self.upper,
            "s3": self._shoulder3,
            "s3_2": (self._shoulder3_2,),
            "wu": self._wrist_u,
            "g": self._g,
            "tool": tuple(self._tool_t.tolist()),
            "w7": self._wrist7,
            "ax7": self._axis7,
            "edge4": self._edge4(),
            "arc": limit_arcs(self.lower, self.upper, self._offsets, range(1, 7)),
        }

    def _edge4(self) -> tuple[float, ...]:
        """Joint 4's limits as the twin's elbow window reads them (``edge4`` in ``_closed7.c``).

        ``cos t4, sin t4`` at the lower and at the upper limit (``t4 = q4 + offset``), then 1 when
        the limits span a whole turn (every ``t4``), else 0. The Python module does not use it: the
        twin skips, without solving, the joint-1 values whose elbow has no root in these limits.
        """
        low = self.lower[3] + self._offsets[3]
        high = self.upper[3] + self._offsets[3]
        turn = float(not high - low < _TWO_PI)
        return (math.cos(low), math.sin(low), math.cos(high), math.sin(high), turn)

    def seed_frames(self) -> dict[str, tuple[float, ...]]:
        """The frames :meth:`prepare` goes through, as the twin's ``seeded`` reads them.

        ``frame_r``, ``frame_t``: ``T_world_base`` of the structure (rotation row-major, origin
        [m]); ``end_r``, ``end_t``: its ``T_last_tool``; ``point``: unused here (zeros).
        """
        return {
            "frame_r": tuple(self._base_r.ravel().tolist()),
            "frame_t": tuple(self._base_t.tolist()),
            "end_r": tuple(self._tool_r.ravel().tolist()),
            "end_t": tuple(self._tool_t.tolist()),
            "point": (0.0, 0.0, 0.0),
        }

    def prepare(self, position: np.ndarray, rotation: np.ndarray | None) -> tuple[int, np.ndarray]:
        """A target for :meth:`first`: ``(mode, values)`` in DH frame 0.

        Args:
            position: Tool position in the world frame [m].
            rotation: Tool rotation ``R_world_tool``, or None for a position target.

        Returns:
            ``(1, tool point [m])`` for a position; ``(0, frame-7 origin [m] and R_0_7 row-major)``
            for a full pose.
        """
        if rotation is None:
            if self._plain:
                return 1, np.ascontiguousarray(position, dtype=float)
            return 1, np.array(self.frame0(position))
        if self._plain:
            r0, p0 = rotation, position
        else:
            r0 = self._base_r.T @ rotation @ self._tool_r.T
            p0 = self._base_r.T @ (position - self._base_t) - r0 @ self._tool_t
        return 0, np.concatenate((p0, r0.ravel()), dtype=float)

    def many_targets(
        self, positions: np.ndarray, rotations: np.ndarray | None
    ) -> tuple[tuple[Any, ...], np.ndarray | None]:
        """N world targets as the twin's ``first_many`` reads them: ``((mode,), targets)``.

        Mode 0: the frame-7 origin [m] and ``R_0_7`` row-major of each pose, (N, 12); mode 1:
        each point in DH frame 0 [m], (N, 3) (as :meth:`prepare`).
        """
        if self._plain:
            points, frames = positions, rotations
        else:  # DH frame 0 and frame 7 (as prepare)
            points = (positions - self._base_t) @ self._base_r
            frames = None if rotations is None else self._base_r.T @ rotations @ self._tool_r.T
        if frames is None:
            return (1,), points
        n = positions.shape[0]
        return (0,), np.concatenate((points - frames @ self._tool_t, frames.reshape(n, 9)), 1)

    def _elbow_vector(self, x: float, y: float, z: float) -> tuple[float, float, float]:
        """``u`` with ``A4(t4) (x, y, z) = Rz(t4) u`` for a point fixed in frame 4."""
        s, c = self._sin[3], self._cos[3]
        return self._a[3] + x, c * y - s * z, self._d[3] + s * y + c * z

    def tool_point4(self, q5: float, q6: float, q7: float) -> tuple[float, float, float]:
        """The tool origin in frame 4 for wrist joint values ``q5, q6, q7`` [rad] -> [m]."""
        x, y, z = self._tool_t.tolist()
        for i in (6, 5, 4):
            t = (q7, q6, q5)[6 - i] + self._offsets[i]
            s, c = self._sin[i], self._cos[i]
            x, y, z = self._a[i] + x, c * y - s * z, self._d[i] + s * y + c * z
            ct, st = math.cos(t), math.sin(t)
            x, y = ct * x - st * y, st * x + ct * y
        return x, y, z

    def elbow_vector(self, q5: float, q6: float, q7: float) -> tuple[float, float, float]:
        """``u`` of the tool origin for wrist values ``q5, q6, q7`` [rad] (see :meth:`position`)."""
        return self._elbow_vector(*self.tool_point4(q5, q6, q7))

    def frame0(self, position: np.ndarray) -> list[float]:
        """A world point [m] in DH frame 0."""
        if self._plain:
            return position.tolist()
        return (self._base_r.T @ (position - self._base_t)).tolist()

    def pose_frame(
        self, position: np.ndarray, rotation: np.ndarray
    ) -> tuple[tuple[float, ...], ...]:
        """Per-target constants of a full pose (``T_world_tool``): wrist centre, two frame-7 axes.

        Returns ``(W, X, Z)`` in frame 0: the wrist centre [m], the x axis of frame 7 and the
        direction ``R07 (0, sin alpha7, cos alpha7)`` (the joint-7 axis of ``M``).
        """
        if self._plain:  # DH frame 0 is the world frame, frame 7 the tool frame (no NumPy)
            return self._frame_of(position.tolist(), rotation.tolist())
        r0 = self._base_r.T @ rotation @ self._tool_r.T  # R_0_7
        p0 = self._base_r.T @ (position - self._base_t) - r0 @ self._tool_t
        return self._frame_of(p0.tolist(), r0.tolist())

    def _frame_of(self, p0: list[float], r0: list[list[float]]) -> tuple[tuple[float, ...], ...]:
        """:meth:`pose_frame` from frame 7's origin ``p0`` [m] and rotation ``R_0_7`` in frame 0."""
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = r0
        px, py, pz = p0
        wx, wy, wz = self._wrist7
        _, ay, az = self._axis7
        return (
            (
                px + r00 * wx + r01 * wy + r02 * wz,
                py + r10 * wx + r11 * wy + r12 * wz,
                pz + r20 * wx + r21 * wy + r22 * wz,
            ),
            (r00, r10, r20),
            (r01 * ay + r02 * az, r11 * ay + r12 * az, r21 * ay + r22 * az),
        )
