"""The frames of :class:`~.spherical_shoulder7.SphericalShoulder7RIK`: its targets and its twin's parameters.

A full pose is read as ``R_K_J7`` and the shoulder point ``S`` seen from ``J_7``
(:meth:`Shoulder7Frames.prepare`); the compiled twin (``kin/_native/ik/analytic/seven_r/_shoulder7.c``) reads the
same, its parameters :meth:`Shoulder7Frames.c_fields` (with the range of ``|S - W|^2`` over
joint 4's limits, :meth:`Shoulder7Frames.elbow_range`) and the frames of its seeded call
:meth:`Shoulder7Frames.seed_frames`. :class:`Shoulder7Frames` reads the arm's constants once;
:class:`~.spherical_shoulder7.SphericalShoulder7RIK` holds it (and its batched steps,
:class:`~.shoulder7_batch.Shoulder7Batch`, read them). Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .shoulder7_structure import SphericalShoulder7R, inverse_point
from .subproblems import limit_arcs

_TWO_PI = 2.0 * math.pi


class Shoulder7Frames:
    """The constants, targets and twin parameters of a spherical-shoulder 7R arm.

    Args:
        structure: The arm's parameters (:func:`~.shoulder7_structure.spherical_shoulder7`).
        lower: Lower joint limits [rad] (7).
        upper: Upper joint limits [rad] (7).

    Attributes:
        structure: The arm's parameters.
        lower, upper: The joint limits [rad] (7 each).
        sin, cos: ``sin``, ``cos`` of the twists ``alpha_i'`` [-]; ``offsets``: the joint
            offsets [rad].
        k_rot, k_pos: The base frame ``K`` (``M_1``): rotation, origin [m] (arrays; ``k_flat``,
            ``k_t``: the same as tuples, the rotation row-major).
        tool_rot, tool_pos: The tool ``M_8`` in joint 7's frame (``tool_flat``, ``tool_t``: as
            tuples).
        m7_rot: The rotation of ``M_7`` (rows).
        c7: ``W`` just before ``Rz(t7)``: ``M_7^-1 W_6`` [m].
        u: ``S`` just before ``Rz(t4)`` [m]; ``w4``: ``W`` in ``J_4`` [m].
        p4, q4, k4: The elbow's ``|S - W|^2 = 2 (k - p cos t4 - q sin t4)`` [m^2].
        reach2: :meth:`elbow_range` [m^2].
        shoulder_z: The height of ``S`` in ``K`` [m].
    """

    def __init__(
        self, structure: SphericalShoulder7R, lower: Sequence[float], upper: Sequence[float]
    ):
        self.structure = structure
        self.lower = tuple(float(v) for v in lower)
        self.upper = tuple(float(v) for v in upper)
        frames, twists = structure.frames, structure.twists
        self.sin = tuple(math.sin(v) for v in twists)
        self.cos = tuple(math.cos(v) for v in twists)
        self.offsets = structure.offsets
        self.k_rot = np.array(frames[0][:3, :3])
        self.k_pos = np.array(frames[0][:3, 3])
        self.tool_rot = np.array(frames[7][:3, :3])
        self.tool_pos = np.array(frames[7][:3, 3])
        self.m7_rot = tuple(tuple(r) for r in frames[6][:3, :3].tolist())
        # W just before Rz(t7): M_7^-1 W_6.
        self.c7 = inverse_point(frames[6], structure.wrist6)
        self.u = inverse_point(frames[3], structure.shoulder3)  # S just before Rz(t4)
        self.w4 = structure.wrist4
        u, w = self.u, self.w4
        self.p4 = u[0] * w[0] + u[1] * w[1]
        self.q4 = u[1] * w[0] - u[0] * w[1]
        self.k4 = 0.5 * (sum(v * v for v in u) + sum(v * v for v in w)) - u[2] * w[2]
        self.reach2 = self.elbow_range()
        self.k_flat = tuple(self.k_rot.ravel().tolist())
        self.k_t = tuple(self.k_pos.tolist())
        self.tool_flat = tuple(self.tool_rot.ravel().tolist())
        self.tool_t = tuple(self.tool_pos.tolist())
        self.shoulder_z = structure.shoulder[2]

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (its ``SHOULDER7_PARAMS``; lengths [m])."""
        return {
            "off": self.offsets,
            "sin": self.sin,
            "cos": self.cos,
            "lo": self.lower,
            "hi": self.upper,
            "c7": self.c7,
            "u": self.u,
            "w4": self.w4,
            "elbow": (self.p4, self.q4, self.k4),
            "reach2": self.reach2,
            "m7": tuple(v for row in self.m7_rot for v in row),
            "arc": limit_arcs(self.lower, self.upper, self.offsets, range(6)),
        }

    def elbow_range(self) -> tuple[float, float]:
        """``|S - W|^2`` [m^2] over joint 4's limits: ``(min, max)``, widened by rounding slack.

        ``|S - W|^2 = 2 (k - p cos t4 - q sin t4)``; :meth:`first` skips the joint-7 values whose
        distance is outside this range (no branch inside joint 4's limits) before solving.
        """
        p, q, k = self.p4, self.q4, self.k4
        low = self.lower[3] + self.offsets[3]
        high = self.upper[3] + self.offsets[3]
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
            "frame_r": self.k_flat,
            "frame_t": self.k_t,
            "end_r": self.tool_flat,
            "end_t": self.tool_t,
            "point": (0.0, 0.0, float(self.shoulder_z)),
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
        k00, k01, k02, k10, k11, k12, k20, k21, k22 = self.k_flat
        m00, m01, m02, m10, m11, m12, m20, m21, m22 = self.tool_flat
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
        kx, ky, kz = self.k_t
        px, py, pz = position.tolist()
        x, y, z = px - kx, py - ky, pz - kz
        # S seen from J_7: R_K_J7^T (S - p_K_J7) = R_K_J7^T (S - K^T (p - k)) + t_8.
        gx = -(k00 * x + k10 * y + k20 * z)
        gy = -(k01 * x + k11 * y + k21 * z)
        gz = self.shoulder_z - (k02 * x + k12 * y + k22 * z)
        tx, ty, tz = self.tool_t
        return (
            r00, r01, r02, r10, r11, r12, r20, r21, r22,
            r00 * gx + r10 * gy + r20 * gz + tx,
            r01 * gx + r11 * gy + r21 * gz + ty,
            r02 * gx + r12 * gy + r22 * gz + tz,
        )  # fmt: skip

    def prepare_array(self, p: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`prepare` of N poses: ``R_K_J7`` (N, 3, 3), ``S`` seen from ``J_7`` (N, 3) [m]."""
        rk = self.k_rot.T @ r @ self.tool_rot.T
        pk = (p - self.k_pos) @ self.k_rot - rk @ self.tool_pos
        return rk, np.einsum("nji,nj->ni", rk, np.asarray(self.structure.shoulder) - pk)

    def many_targets(
        self, positions: np.ndarray, rotations: np.ndarray | None
    ) -> tuple[tuple[()], np.ndarray | None]:
        """N world poses as the twin's ``first_many`` reads them: ``R_K_J7`` and ``S`` (N, 12).

        None for positions (this form takes no point: every row of the answer NaN).
        """
        if rotations is None:
            return (), None
        rk, e = self.prepare_array(positions, rotations)
        return (), np.concatenate((rk.reshape(-1, 9), e), axis=1)
