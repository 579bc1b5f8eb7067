"""The frames of :class:`~.spherical_shoulder7.SphericalShoulder7RIK`: its targets and its twin's parameters.

A full pose is read as ``R_K_J7`` and the shoulder point ``S`` seen from ``J_7``
(:meth:`Shoulder7Frames.prepare`); the compiled twin (``kin/_native/ik/analytic/seven_r/_shoulder7.c``) reads the
same, its parameters :meth:`Shoulder7Frames.c_fields` (with the range of ``|S - W|^2`` over
joint 4's limits, :meth:`Shoulder7Frames.elbow_range`) and the frames of its seeded call
:meth:`Shoulder7Frames.seed_frames`. Mixed into
:class:`~.spherical_shoulder7.SphericalShoulder7RIK`, which sets the constants. Angles in [rad],
lengths in [m].
"""

from __future__ import annotations

import math

import numpy as np

from .shoulder7_structure import Vec
from .subproblems import limit_arcs
from .twin_form import TwinForm

_TWO_PI = 2.0 * math.pi


class Shoulder7Frames(TwinForm):
    """Targets and twin parameters of a spherical-shoulder 7R arm (mixed in)."""

    _c7: Vec
    _u: Vec
    _w4: Vec
    _p4: float
    _q4: float
    _k4: float
    _reach2: tuple[float, float]
    _m7_rot: tuple[tuple[float, ...], ...]
    _k_flat: tuple[float, ...]
    _k_t: tuple[float, ...]
    _tool_flat: tuple[float, ...]
    _tool_t: tuple[float, ...]
    _shoulder_z: float

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (its ``SHOULDER7_PARAMS``; lengths [m])."""
        return {
            "off": self._offsets,
            "sin": self._sin,
            "cos": self._cos,
            "lo": self.lower,
            "hi": self.upper,
            "c7": self._c7,
            "u": self._u,
            "w4": self._w4,
            "elbow": (self._p4, self._q4, self._k4),
            "reach2": self._reach2,
            "m7": tuple(v for row in self._m7_rot for v in row),
            "arc": limit_arcs(self.lower, self.upper, self._offsets, range(6)),
        }

    def elbow_range(self) -> tuple[float, float]:
        """``|S - W|^2`` [m^2] over joint 4's limits: ``(min, max)``, widened by rounding slack.

        ``|S - W|^2 = 2 (k - p cos t4 - q sin t4)``; :meth:`first` skips the joint-7 values whose
        distance is outside this range (no branch inside joint 4's limits) before solving.
        """
        p, q, k = self._p4, self._q4, self._k4
        low = self.lower[3] + self._offsets[3]
        high = self.upper[3] + self._offsets[3]
        values = [p * math.cos(t) + q * math.sin(t) for t in (low, high)]
        rho, phi = math.hypot(p, q), math.atan2(q, p)
        for peak, value in ((phi, rho), (phi + math.pi, -rho)):
            if high - low >= _TWO_PI or low <= low + (peak - low) % _TWO_PI <= high:
                values.append(value)
        slack = 1e-9 * (1.0 + abs(k) + rho)
        return 2.0 * (k - max(values)) - slack, 2.0 * (k - min(values)) + slack

    def seed_frames(self) -> dict[str, tuple[float, ...]]:
        """The frames :meth:`prepare` goes through, as the twin's ``seeded`` reads them.

        ``frame_r``, ``frame_t``: the base frame ``K`` (rotation row-major, origin [m]);
        ``end_r``, ``end_t``: the tool ``M_8`` in joint 7's frame; ``point``: the shoulder point
        ``S`` in ``K`` [m].
        """
        return {
            "frame_r": self._k_flat,
            "frame_t": self._k_t,
            "end_r": self._tool_flat,
            "end_t": self._tool_t,
            "point": (0.0, 0.0, float(self._shoulder_z)),
        }

    def prepare(
        self, position: np.ndarray, rotation: np.ndarray | None
    ) -> tuple[float, ...] | None:
        """A target for :meth:`first` and :meth:`branches`, or None for a position (not handled).

        Args:
            position: Tool position in the world frame [m].
            rotation: Tool rotation ``R_world_tool``, or None.

        Returns:
            ``R_K_J7`` (9 values, row-major) and ``S`` seen from ``J_7`` (3 values, [m]).
        """
        if rotation is None:
            return None
        # Plain floats, unrolled (NumPy on 3 x 3, or loops, cost microseconds here).
        k00, k01, k02, k10, k11, k12, k20, k21, k22 = self._k_flat
        m00, m01, m02, m10, m11, m12, m20, m21, m22 = self._tool_flat
        (w00, w01, w02), (w10, w11, w12), (w20, w21, w22) = rotation.tolist()
        # R_K_J7 = K^T R_world_tool M_8^T; p_K_J7 = K^T (p - k) - R_K_J7 t_8. First A = K^T R.
        a00 = k00 * w00 + k10 * w10 + k20 * w20
        a01 = k00 * w01 + k10 * w11 + k20 * w21
        a02 = k00 * w02 + k10 * w12 + k20 * w22
        a10 = k01 * w00 + k11 * w10 + k21 * w20
        a11 = k01 * w01 + k11 * w11 + k21 * w21
        a12 = k01 * w02 + k11 * w12 + k21 * w22
        a20 = k02 * w00 + k12 * w10 + k22 * w20
        a21 = k02 * w01 + k12 * w11 + k22 * w21
        a22 = k02 * w02 + k12 * w12 + k22 * w22
        r00 = a00 * m00 + a01 * m01 + a02 * m02
        r01 = a00 * m10 + a01 * m11 + a02 * m12
        r02 = a00 * m20 + a01 * m21 + a02 * m22
        r10 = a10 * m00 + a11 * m01 + a12 * m02
        r11 = a10 * m10 + a11 * m11 + a12 * m12
        r12 = a10 * m20 + a11 * m21 + a12 * m22
        r20 = a20 * m00 + a21 * m01 + a22 * m02
        r21 = a20 * m10 + a21 * m11 + a22 * m12
        r22 = a20 * m20 + a21 * m21 + a22 * m22
        kx, ky, kz = self._k_t
        px, py, pz = position.tolist()
        x, y, z = px - kx, py - ky, pz - kz
        # S seen from J_7: R_K_J7^T (S - p_K_J7) = R_K_J7^T (S - K^T (p - k)) + t_8.
        gx = -(k00 * x + k10 * y + k20 * z)
        gy = -(k01 * x + k11 * y + k21 * z)
        gz = self._shoulder_z - (k02 * x + k12 * y + k22 * z)
        tx, ty, tz = self._tool_t
        return (
            r00, r01, r02, r10, r11, r12, r20, r21, r22,
            r00 * gx + r10 * gy + r20 * gz + tx,
            r01 * gx + r11 * gy + r21 * gz + ty,
            r02 * gx + r12 * gy + r22 * gz + tz,
        )  # fmt: skip
