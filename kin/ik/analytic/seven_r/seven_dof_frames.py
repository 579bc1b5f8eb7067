"""The frames of :class:`~.seven_dof.SevenDofIK`: its targets in DH frame 0 and its twin's parameters.

A full pose is read as the wrist centre and two axes of frame 7 in DH frame 0
(:meth:`SevenDofFrames.pose_frame`), a point in DH frame 0 (:meth:`SevenDofFrames.frame0`); the
compiled twin (``kin/_native/ik/analytic/seven_r/_closed7.c``) reads the same through :meth:`SevenDofFrames.prepare`,
:meth:`SevenDofFrames.many_targets`, its parameters :meth:`SevenDofFrames.c_fields` and the
frames of its seeded call :meth:`SevenDofFrames.seed_frames`. :class:`SevenDofFrames` reads the
arm's constants once; :class:`~.seven_dof.SevenDofIK` holds it (and its steps,
:class:`~.seven_dof_steps.SevenDofSteps`, read them). ``t_i`` are DH angles, ``q_i`` joint values
[rad]; lengths in [m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..structure import SevenDof
from .subproblems import limit_arcs

_TWO_PI = 2.0 * math.pi


class SevenDofFrames:
    """The constants, targets and twin parameters of a seven-joint arm (``SevenDof``).

    Args:
        structure: The arm's parameters.
        lower: Lower joint limits [rad] (7).
        upper: Upper joint limits [rad] (7).

    Attributes:
        structure: The arm's parameters.
        lower, upper: The joint limits [rad] (7 each).
        a, d: The DH lengths ``a_i``, ``d_i`` [m]; ``offsets``: the joint offsets [rad].
        sin, cos: ``sin``, ``cos`` of the twists ``alpha_i`` [-].
        base_r, base_t, tool_r, tool_t: ``T_world_base`` and ``T_last_tool`` (rotation, origin [m]).
        plain: Both of them identities (DH frame 0 is the world frame, frame 7 the tool frame).
        shoulder3: The shoulder point in frame 3 [m]; ``shoulder3_2``: its squared length [m^2].
        wrist_u: ``u`` of the wrist centre: ``Rz(t4) u`` in frame 3 [m].
        wrist7: The wrist centre in frame 7 [m].
        axis7: The joint-7 axis direction (frame 7 z of ``M``) seen in frame 7 [-].
        g: ``Rx(alpha6) e_z`` [-].
    """

    def __init__(self, structure: SevenDof, lower: Sequence[float], upper: Sequence[float]):
        self.structure = structure
        self.lower = tuple(float(v) for v in lower)
        self.upper = tuple(float(v) for v in upper)
        a, alpha, d = structure.a, structure.alpha, structure.d
        self.a, self.d, self.offsets = a, d, structure.offsets
        self.sin = tuple(math.sin(v) for v in alpha)
        self.cos = tuple(math.cos(v) for v in alpha)
        base = structure.T_world_base
        self.base_r = np.array(base[:3, :3], dtype=float)
        self.base_t = np.array(base[:3, 3], dtype=float)
        tool = structure.T_last_tool
        self.tool_r = np.array(tool[:3, :3], dtype=float)
        self.tool_t = np.array(tool[:3, 3], dtype=float)
        self.plain = bool(np.array_equal(base, np.eye(4)) and np.array_equal(tool, np.eye(4)))
        s, c = self.sin, self.cos
        # Shoulder point in frame 3: o2 = -Rx(alpha3)^T (a3, 0, d3), whatever t3.
        self.shoulder3 = (-a[2], -s[2] * d[2], -c[2] * d[2])
        self.shoulder3_2 = sum(v * v for v in self.shoulder3)
        # Wrist centre in frame 3: Rz(t4) u.
        self.wrist_u = self._elbow_vector(0.0, 0.0, d[4])
        # Wrist centre in frame 7: o6 = -Rx(alpha7)^T (a7, 0, d7).
        self.wrist7 = (-a[6], -s[6] * d[6], -c[6] * d[6])
        # Joint-7 axis direction (frame 7 z of M = R47 Rx(alpha7)^T) seen in frame 7.
        self.axis7 = (0.0, s[6], c[6])
        self.g = (0.0, -s[5], c[5])  # Rx(alpha6) e_z

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (its ``CLOSED7_PARAMS``; lengths [m])."""
        return {
            "off": self.offsets,
            "sin": self.sin,
            "cos": self.cos,
            "a": self.a,
            "d": self.d,
            "lo": self.lower,
            "hi": self.upper,
            "s3": self.shoulder3,
            "s3_2": (self.shoulder3_2,),
            "wu": self.wrist_u,
            "g": self.g,
            "tool": tuple(self.tool_t.tolist()),
            "w7": self.wrist7,
            "ax7": self.axis7,
            "edge4": self._edge4(),
            "arc": limit_arcs(self.lower, self.upper, self.offsets, range(1, 7)),
        }

    def _edge4(self) -> tuple[float, ...]:
        """Joint 4's limits as the twin's elbow window reads them (``edge4`` in ``_closed7.c``).

        ``cos t4, sin t4`` at the lower and at the upper limit (``t4 = q4 + offset``), then 1 when
        the limits span a whole turn (every ``t4``), else 0. The Python module does not use it: the
        twin skips, without solving, the joint-1 values whose elbow has no root in these limits.
        """
        low = self.lower[3] + self.offsets[3]
        high = self.upper[3] + self.offsets[3]
        turn = float(not high - low < _TWO_PI)
        return (math.cos(low), math.sin(low), math.cos(high), math.sin(high), turn)

    def seed_frames(self) -> dict[str, tuple[float, ...]]:
        """The frames :meth:`prepare` goes through, as the twin's ``seeded`` reads them.

        ``frame_r``, ``frame_t``: ``T_world_base`` of the structure (rotation row-major, origin
        [m]); ``end_r``, ``end_t``: its ``T_last_tool``; ``point``: unused here (zeros).
        """
        return {
            "frame_r": tuple(self.base_r.ravel().tolist()),
            "frame_t": tuple(self.base_t.tolist()),
            "end_r": tuple(self.tool_r.ravel().tolist()),
            "end_t": tuple(self.tool_t.tolist()),
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
            if self.plain:
                return 1, np.ascontiguousarray(position, dtype=float)
            return 1, np.array(self.frame0(position))
        if self.plain:
            r0, p0 = rotation, position
        else:
            r0 = self.base_r.T @ rotation @ self.tool_r.T
            p0 = self.base_r.T @ (position - self.base_t) - r0 @ self.tool_t
        return 0, np.concatenate((p0, r0.ravel()), dtype=float)

    def many_targets(
        self, positions: np.ndarray, rotations: np.ndarray | None
    ) -> tuple[tuple[Any, ...], np.ndarray | None]:
        """N world targets as the twin's ``first_many`` reads them: ``((mode,), targets)``.

        Mode 0: the frame-7 origin [m] and ``R_0_7`` row-major of each pose, (N, 12); mode 1:
        each point in DH frame 0 [m], (N, 3) (as :meth:`prepare`).
        """
        if self.plain:
            points, frames = positions, rotations
        else:  # DH frame 0 and frame 7 (as prepare)
            points = (positions - self.base_t) @ self.base_r
            frames = None if rotations is None else self.base_r.T @ rotations @ self.tool_r.T
        if frames is None:
            return (1,), points
        n = positions.shape[0]
        return (0,), np.concatenate((points - frames @ self.tool_t, frames.reshape(n, 9)), 1)

    def _elbow_vector(self, x: float, y: float, z: float) -> tuple[float, float, float]:
        """``u`` with ``A4(t4) (x, y, z) = Rz(t4) u`` for a point fixed in frame 4."""
        s, c = self.sin[3], self.cos[3]
        return self.a[3] + x, c * y - s * z, self.d[3] + s * y + c * z

    def tool_point4(self, q5: float, q6: float, q7: float) -> tuple[float, float, float]:
        """The tool origin in frame 4 for wrist joint values ``q5, q6, q7`` [rad] -> [m]."""
        x, y, z = self.tool_t.tolist()
        for i in (6, 5, 4):
            t = (q7, q6, q5)[6 - i] + self.offsets[i]
            s, c = self.sin[i], self.cos[i]
            x, y, z = self.a[i] + x, c * y - s * z, self.d[i] + s * y + c * z
            ct, st = math.cos(t), math.sin(t)
            x, y = ct * x - st * y, st * x + ct * y
        return x, y, z

    def elbow_vector(self, q5: float, q6: float, q7: float) -> tuple[float, float, float]:
        """``u`` of the tool origin for wrist values ``q5, q6, q7`` [rad] (see :meth:`~.SevenDofSteps.position`)."""
        return self._elbow_vector(*self.tool_point4(q5, q6, q7))

    def frame0(self, position: np.ndarray) -> list[float]:
        """A world point [m] in DH frame 0."""
        if self.plain:
            return position.tolist()
        return (self.base_r.T @ (position - self.base_t)).tolist()

    def pose_frame(
        self, position: np.ndarray, rotation: np.ndarray
    ) -> tuple[tuple[float, ...], ...]:
        """Per-target constants of a full pose (``T_world_tool``): wrist centre, two frame-7 axes.

        Returns ``(W, X, Z)`` in frame 0: the wrist centre [m], the x axis of frame 7 and the
        direction ``R07 (0, sin alpha7, cos alpha7)`` (the joint-7 axis of ``M``).
        """
        if self.plain:  # DH frame 0 is the world frame, frame 7 the tool frame (no NumPy)
            return self.frame_of(position.tolist(), rotation.tolist())
        r0 = self.base_r.T @ rotation @ self.tool_r.T  # R_0_7
        p0 = self.base_r.T @ (position - self.base_t) - r0 @ self.tool_t
        return self.frame_of(p0.tolist(), r0.tolist())

    def frame_of(self, p0: list[float], r0: list[list[float]]) -> tuple[tuple[float, ...], ...]:
        """:meth:`pose_frame` from frame 7's origin ``p0`` [m] and rotation ``R_0_7`` in frame 0."""
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = r0
        px, py, pz = p0
        wx, wy, wz = self.wrist7
        _, ay, az = self.axis7
        return (
            (
                px + r00 * wx + r01 * wy + r02 * wz,
                py + r10 * wx + r11 * wy + r12 * wz,
                pz + r20 * wx + r21 * wy + r22 * wz,
            ),
            (r00, r10, r20),
            (r01 * ay + r02 * az, r11 * ay + r12 * az, r21 * ay + r22 * az),
        )
