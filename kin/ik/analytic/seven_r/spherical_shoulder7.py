"""Closed-form IK of 7R arms with a spherical shoulder, for a chosen joint-7 angle (Panda, xArm7).

The structure (:class:`SphericalShoulder7R`): axes 1, 2 and 3 meet in one point ``S`` (the
shoulder), joint 4 is an elbow, axes 5 and 6 meet in one point ``W``; joint 7 is general and left
free. Either DH convention, any base and tool: joint ``i`` is ``L_i Rz(t_i) R_i`` (modified:
``L = Rx(alpha) Tx(a) Tz(d)``, ``R = I``; standard: ``L = Tz(d)``, ``R = Tx(a) Rx(alpha)``), and the
chain is rewritten ``M_1 Rz(t_1) M_2 ... M_7 Rz(t_7) M_8`` with ``M_1 = T_world_base L_1``,
``M_i = R_(i-1) L_i`` (a rotation ``Rx(alpha_i')`` and a translation) and ``M_8 = R_7
T_last_tool``. Frame ``J_i`` follows ``Rz(t_i)``; frame ``K`` (``M_1``) is fixed, axis 1 its z.

For a full tool pose and a chosen ``q7`` the pose of ``J_6`` is known, and:

1. elbow: ``|S - W|^2`` depends on ``t4`` alone: ``p cos t4 + q sin t4 = k`` (two ``t4``);
2. wrist: the vector ``S - W`` is known in ``J_6`` (from the target) and in ``J_4`` (from ``t4``);
   ``Rz(t5) Rx(alpha_6') Rz(t6)`` maps one onto the other (Paden-Kahan 2: two ``(t5, t6)``);
3. shoulder: ``R_K_J3`` follows; ``Rz(t1) Rx(alpha_2') Rz(t2) Rx(alpha_3') Rz(t3) = R_K_J3`` is a
   generalised Euler decomposition (two ``(t1, t2)``, then ``t3``).

Up to 8 joint vectors per ``q7``. ``t_i`` are DH angles, ``q_i = t_i - theta_i`` joint values
[rad]; lengths in [m]. A position-only target is not handled (:meth:`SphericalShoulder7RIK.prepare`
returns None): the numeric stages answer it. The sub-problems are those of :mod:`.seven_dof`
(:mod:`.subproblems`), the joint-7 scan its
:func:`~.subproblems.scan`. :meth:`SphericalShoulder7RIK.first` runs the compiled twin of this
module (``kin/_native/ik/analytic/seven_r/_shoulder7.c``, an optional extension built at install when a C compiler
is there) and this Python code otherwise; ``tests/native/test_shoulder7_parity.py`` compares the two.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from kin._native import twin

from ...angles import wrap
from ...limit_rule import nearest_inside
from .shoulder7_batch import BRANCHES, Shoulder7Batch
from .shoulder7_frames import Shoulder7Frames
from .shoulder7_structure import SphericalShoulder7R
from .subproblems import (
    harmonic_roots,
    rotation_pair,
    scan,
)
from .twin_form import TwinForm

_shoulder7 = twin("_shoulder7")

#: Whether the compiled twin (``kin/_native/ik/analytic/seven_r/_shoulder7.c``) is built.
COMPILED = _shoulder7 is not None


_TWO_PI = 2.0 * math.pi


class SphericalShoulder7RIK(TwinForm):
    """Closed-form branches of a :class:`SphericalShoulder7R` arm for chosen joint-7 values.

    Holds its constants and targets' frames (:attr:`frames`,
    :class:`~.shoulder7_frames.Shoulder7Frames`) and its batched steps (:attr:`batch`,
    :class:`~.shoulder7_batch.Shoulder7Batch`), and hands on their methods as its own
    (:meth:`~.Shoulder7Frames.prepare`, :meth:`~.Shoulder7Frames.seed_frames`,
    :meth:`~.Shoulder7Frames.elbow_range`, :meth:`~.Shoulder7Batch.solve_batch`): bound, not
    forwarded, so a call costs no more than before.

    Args:
        structure: The arm's parameters (:func:`spherical_shoulder7`).
        lower: Lower joint limits [rad] (7).
        upper: Upper joint limits [rad] (7).
    """

    twin_module = _shoulder7  # its :meth:`first`'s (``compiled_twin``: whether it is built)
    #: The free joint (0-based): joint 7.
    free: ClassVar[int] = 6

    def __init__(
        self, structure: SphericalShoulder7R, lower: Sequence[float], upper: Sequence[float]
    ):
        self.structure = structure
        frames = Shoulder7Frames(structure, lower, upper)
        batch = Shoulder7Batch(frames)
        self.frames, self.batch = frames, batch
        self.lower, self.upper = frames.lower, frames.upper
        self._sin, self._cos, self._offsets = frames.sin, frames.cos, frames.offsets
        self._c_params = None
        # their methods, handed on as this solver's own: bound, so no forwarding call
        self.prepare = frames.prepare
        self.seed_frames = frames.seed_frames
        self.elbow_range = frames.elbow_range
        self.solve_batch = batch.solve_batch

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (:meth:`~.Shoulder7Frames.c_fields`)."""
        return self.frames.c_fields()

    def many_targets(
        self, positions: np.ndarray, rotations: np.ndarray | None
    ) -> tuple[tuple[()], np.ndarray | None]:
        """N world poses as the twin's ``first_many`` reads them.

        :meth:`~.Shoulder7Frames.many_targets`: ``R_K_J7`` and ``S`` (N, 12), None for positions.
        """
        return self.frames.many_targets(positions, rotations)

    def branches(
        self, target: tuple[float, ...], q7: float, fit: Callable[[int, float], float | None]
    ) -> list[tuple[int, list[float]]]:
        """Joint vectors [rad] reaching a :meth:`prepare` d target with joint 7 at ``q7``.

        Args:
            target: :meth:`prepare` of the target.
            q7: Joint-7 value [rad] (kept as given).
            fit: ``fit(joint, q)``: joint ``joint``'s (0-based) value for the solved ``q`` [rad],
                or None to drop the branch (outside a limit); asked joint by joint, a branch
                leaves at its first None.

        Returns:
            ``(slot, q)`` per branch: slot ``4 e + 2 w + s`` for the elbow root ``e``, the wrist
            pair ``w`` and the shoulder pair ``s``.
        """
        r00, r01, r02, r10, r11, r12, r20, r21, r22, ex, ey, ez = target
        s, c, off = self._sin, self._cos, self._offsets
        frames = self.frames
        cos, sin, atan2 = math.cos, math.sin, math.atan2
        t7 = q7 + off[6]
        c7, s7 = cos(t7), sin(t7)
        wx, wy, wz = frames.c7
        # S - W before Rz(t7): Rz(t7) e - c7; in J_6: M_7's rotation of it.
        rx, ry, rz = c7 * ex - s7 * ey - wx, s7 * ex + c7 * ey - wy, ez - wz
        ux, uy, uz = frames.u
        w4x, w4y, w4z = frames.w4
        distance2 = rx * rx + ry * ry + rz * rz
        elbows = harmonic_roots(frames.p4, frames.q4, frames.k4 - 0.5 * distance2)
        if not elbows:
            return []
        (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = frames.m7_rot
        v6x = a00 * rx + a01 * ry + a02 * rz
        v6y = a10 * rx + a11 * ry + a12 * rz
        v6z = a20 * rx + a21 * ry + a22 * rz
        # R_K_J6 = R_K_J7 Rz(-t7) M_7^T (rows).
        b00, b01 = r00 * c7 - r01 * s7, r00 * s7 + r01 * c7
        b10, b11 = r10 * c7 - r11 * s7, r10 * s7 + r11 * c7
        b20, b21 = r20 * c7 - r21 * s7, r20 * s7 + r21 * c7
        k6 = (
            (b00 * a00 + b01 * a01 + r02 * a02, b00 * a10 + b01 * a11 + r02 * a12,
             b00 * a20 + b01 * a21 + r02 * a22),
            (b10 * a00 + b11 * a01 + r12 * a02, b10 * a10 + b11 * a11 + r12 * a12,
             b10 * a20 + b11 * a21 + r12 * a22),
            (b20 * a00 + b21 * a01 + r22 * a02, b20 * a10 + b21 * a11 + r22 * a12,
             b20 * a20 + b21 * a21 + r22 * a22),
        )  # fmt: skip
        out: list[tuple[int, list[float]]] = []
        for e, t4 in enumerate(elbows):
            q4 = fit(3, t4 - off[3])
            if q4 is None:
                continue
            c4, s4 = cos(t4), sin(t4)
            # S - W in J_4 (Rz(-t4) u - w4), then through Rx(alpha_5')^T.
            vx, vy, vz = c4 * ux + s4 * uy - w4x, c4 * uy - s4 * ux - w4y, uz - w4z
            dy, dz = c[5] * vy + s[5] * vz, c[5] * vz - s[5] * vy
            # z and x of J_3 in K: R_K_J6 Rz(-t6) Rx6^T Rz(-t5) Rx5^T Rz(-t4) Rx4^T (e_z, e_x);
            # here the part up to Rx5^T (t4 only).
            zy, zz = c4 * s[4], c[4]
            z4 = (s4 * s[4], c[5] * zy + s[5] * zz, c[5] * zz - s[5] * zy)
            x4 = (c4, -c[5] * s4, s[5] * s4)
            for w, (t5, t6) in enumerate(rotation_pair(s[6], c[6], v6x, v6y, v6z, vx, dy, dz)):
                q5, q6 = fit(4, t5 - off[4]), fit(5, t6 - off[5])
                if q5 is None or q6 is None:
                    continue
                turn = (cos(t5), sin(t5), s[6], c[6], cos(t6), sin(t6))
                z = _back(k6, turn, *z4)
                x = _back(k6, turn, *x4)
                for h, (t1, t2) in enumerate(rotation_pair(s[2], c[2], 0.0, -s[3], c[3], *z)):
                    q1, q2 = fit(0, t1 - off[0]), fit(1, t2 - off[1])
                    if q1 is None or q2 is None:
                        continue
                    # t3: Rx3^T Rz(-t2) Rx2^T Rz(-t1) x_3 = (cos t3, sin t3, 0).
                    ct, st = cos(t1), sin(t1)
                    nx, ny, nz = ct * x[0] + st * x[1], ct * x[1] - st * x[0], x[2]
                    ny, nz = c[2] * ny + s[2] * nz, c[2] * nz - s[2] * ny
                    ct, st = cos(t2), sin(t2)
                    nx, ny = ct * nx + st * ny, ct * ny - st * nx
                    ny = c[3] * ny + s[3] * nz
                    q3 = fit(2, atan2(ny, nx) - off[2])
                    if q3 is not None:
                        out.append((4 * e + 2 * w + h, [q1, q2, q3, q4, q5, q6, q7]))
        return out

    def solve(self, position: npt.ArrayLike, rotation: npt.ArrayLike, q7: float) -> np.ndarray:
        """Every branch reaching a tool pose with joint 7 at ``q7``, limits ignored.

        Args:
            position: Tool position in the world frame [m] (3,).
            rotation: Tool rotation ``R_world_tool`` (3, 3).
            q7: Joint-7 value [rad].

        Returns:
            (8, 7) joint vectors [rad], joints 1-6 in (-pi, pi], joint 7 ``q7``; row
            ``4 e + 2 w + s`` holds elbow root ``e``, wrist pair ``w`` and shoulder pair ``s``
            (:meth:`branches`); NaN rows where there is none.
        """
        p = np.asarray(position, dtype=float).reshape(3)
        r = np.asarray(rotation, dtype=float).reshape(3, 3)
        target = self.prepare(p, r)
        assert target is not None
        out = np.full((BRANCHES, 7), np.nan)
        for slot, q in self.branches(target, float(q7), _wrap_joint):
            out[slot] = q
        return out

    def branches_at(
        self, position: np.ndarray, rotation: np.ndarray | None, values: np.ndarray
    ) -> np.ndarray | None:
        """Every branch (G, 8, 7) [rad] of a tool pose at joint-7 values (G,), limits ignored.

        :meth:`solve_batch` of the pose repeated (NaN rows where there is none); None for a
        position (not handled).
        """
        if rotation is None:
            return None
        n = values.shape[0]
        return self.solve_batch(
            np.broadcast_to(position, (n, 3)), np.broadcast_to(rotation, (n, 3, 3)), values
        )

    def first(
        self,
        target: tuple[float, ...] | None,
        starts: np.ndarray,
        out: np.ndarray,
        step: float = 0.0,
        compiled: bool = True,
    ) -> int:
        """The first start from which a branch inside the limits reaches the target.

        The branches depend on joint 7 alone (a start only picks one). A start whose joint 7
        gives no branch inside the limits scans joint 7 outward from there when ``step > 0``
        (:func:`~.subproblems.scan`); the first joint-7 value with a branch is taken, and its
        branch nearest the start (each joint shifted by ``2 pi`` into its limits, nearest the
        start's value).

        Args:
            target: :meth:`prepare` of the target (None, a position: no start reaches it).
            starts: Start joint vectors [rad], shape (k, 7); clipped into the limits, a row with a
                value that is not finite skipped.
            out: Receives that branch [rad], shape (7,).
            step: Joint-7 scan step [rad] (0: no scan).
            compiled: Use the compiled twin when it is built (False: this module's Python).

        Returns:
            The index of that start, or -1 (``out`` untouched).
        """
        if target is None:
            return -1
        if compiled and _shoulder7 is not None:
            if not starts.flags.c_contiguous or starts.dtype != np.float64:
                starts = np.ascontiguousarray(starts, dtype=float)
            return _shoulder7.first(self.c_params, target, starts, out, step)
        if starts.ndim != 2 or starts.shape[1] != 7:
            raise ValueError(f"starts: not k x 7, got shape {starts.shape}")
        lows, highs = self.lower, self.upper
        frames = self.frames
        # |S - W|^2 at t7 is |e|^2 + |c7|^2 - 2 c7 . Rz(t7) e: skip values outside the elbow's range.
        ex, ey, ez = target[9:]
        wx, wy, wz = frames.c7
        base2 = ex * ex + ey * ey + ez * ez + wx * wx + wy * wy + wz * wz - 2.0 * wz * ez
        cx, cy = 2.0 * (wx * ex + wy * ey), 2.0 * (wy * ex - wx * ey)
        low2, high2 = frames.reach2
        off7 = self._offsets[6]
        cos, sin = math.cos, math.sin
        for index, start in enumerate(starts.tolist()):
            if not all(map(math.isfinite, start)):
                continue
            clipped = [min(max(v, lo), hi) for v, lo, hi in zip(start, lows, highs)]

            def fit(joint: int, q: float, near: list[float] = clipped) -> float | None:
                return nearest_inside(q, near[joint], lows[joint], highs[joint])

            for q7 in scan(clipped[6], step, lows[6], highs[6]):
                t7 = q7 + off7
                distance2 = base2 - cx * cos(t7) - cy * sin(t7)
                if not low2 <= distance2 <= high2:
                    continue
                found = self.branches(target, q7, fit)
                if found:
                    best = min(
                        (q for _, q in found),
                        key=lambda q: sum((a - b) ** 2 for a, b in zip(q, clipped)),
                    )
                    out[:] = best
                    return index
        return -1


def _wrap_joint(_joint: int, q: float) -> float:
    """:func:`~._six_r.wrap` as the ``fit`` of :meth:`SphericalShoulder7RIK.solve`."""
    return wrap(q)


def _back(
    k6: tuple[tuple[float, ...], ...],
    turn: tuple[float, float, float, float, float, float],
    x: float,
    y: float,
    z: float,
) -> tuple[float, float, float]:
    """``R_K_J6 Rz(-t6) Rx(alpha)^T Rz(-t5) v``.

    ``turn``: ``(cos t5, sin t5, sin alpha, cos alpha, cos t6, sin t6)``; ``k6``: ``R_K_J6`` rows.
    """
    c5, s5, sa, ca, c6, s6 = turn
    x, y = c5 * x + s5 * y, c5 * y - s5 * x
    y, z = ca * y + sa * z, ca * z - sa * y
    x, y = c6 * x + s6 * y, c6 * y - s6 * x
    return (
        k6[0][0] * x + k6[0][1] * y + k6[0][2] * z,
        k6[1][0] * x + k6[1][1] * y + k6[1][2] * z,
        k6[2][0] * x + k6[2][1] * y + k6[2][2] * z,
    )
