"""The closed-form steps of humanoid7's seven-joint arm at one joint-1 value: elbow, shoulder, wrist.

For a given ``q1`` (:class:`SevenDofSteps`, held by :class:`~.seven_dof.SevenDofIK`):

1. the shoulder point ``S`` (where axes 2 and 3 meet) is fixed, and the wrist centre ``W`` (where
   axes 5, 6 and 7 meet) follows from the tool pose; ``|SW|`` depends on the elbow angle only:
   ``P cos t4 + Q sin t4 = K`` gives ``t4`` (two branches);
2. ``Rz(t2) Rx(alpha2) Rz(t3) v = SW`` (``v`` the shoulder-to-wrist vector in frame 3 rotated by
   ``Rx(alpha3)``) gives ``t2, t3`` (two branches, :func:`~.subproblems.rotation_pair`);
3. the wrist: ``Rz(t5) Rx(alpha5) Rz(t6) Rx(alpha6) e_z`` must equal the tool's joint-7 axis seen
   in frame 4 (``t5, t6``: two branches, the same sub-problem), ``t7`` is what remains.

Up to 8 joint vectors per ``q1`` (:meth:`SevenDofSteps.pose`). For a position-only target the
wrist angles are chosen too (``q5, q6, q7``): the tool point is then fixed in frame 4 and steps 1-2
place it (up to 4 vectors, :meth:`SevenDofSteps.position`). All of it is scalar arithmetic; the
compiled twin (``kin/_native/ik/analytic/seven_r/_closed7.c``) runs the same steps. ``t_i`` are DH angles,
``q_i = t_i - theta_i`` joint values [rad]; lengths in [m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from .seven_dof_frames import SevenDofFrames
from .subproblems import fold_distance, harmonic_roots, rotation_pair

_TWO_PI = 2.0 * math.pi


class SevenDofSteps:
    """The branches of a :class:`~kin.ik.analytic.structure.SevenDof` arm at one joint-1 value.

    Held by :class:`~.seven_dof.SevenDofIK`; it reads the arm's constants from the arm's
    :class:`~.seven_dof_frames.SevenDofFrames` (and asks it :meth:`~.SevenDofFrames.elbow_vector`).

    Args:
        frames: The arm's constants and frames.
    """

    def __init__(self, frames: SevenDofFrames):
        self.frames = frames
        self.lower, self.upper = frames.lower, frames.upper
        self._sin, self._cos, self._offsets = frames.sin, frames.cos, frames.offsets
        self._a, self._d = frames.a, frames.d
        self._shoulder3, self._shoulder3_2 = frames.shoulder3, frames.shoulder3_2
        self._wrist_u, self._g = frames.wrist_u, frames.g

    def _arm(
        self,
        q1: float,
        point0: Sequence[float],
        u: tuple[float, float, float],
        folds: list[float] | None = None,
    ) -> list[tuple[float, ...]]:
        """Branches putting the point ``Rz(t4) u`` of frame 3 on ``point0`` (frame 0), joint 1 at ``q1``.

        Returns ``(t1, q2, q3, q4, t2, t3, t4)`` (DH angles ``t``, joint values ``q`` inside the
        limits [rad]) of each branch. ``folds``: receives the :func:`~.subproblems.fold_distance`
        of the elbow's equation and of each elbow's shoulder equation.
        """
        s, c, off, lo, hi = self._sin, self._cos, self._offsets, self.lower, self.upper
        # The point seen from the shoulder point, in frame 1: R01^T (P - o1) - (0, 0, d2).
        t1 = q1 + off[0]
        c1, s1 = math.cos(t1), math.sin(t1)
        x, y, z = point0
        a1 = self._a[0]
        x -= a1 * c1
        y -= a1 * s1
        z -= self._d[0]
        x, y = c1 * x + s1 * y, c1 * y - s1 * x
        ca, sa = c[0], s[0]
        dx, dy, dz = x, ca * y + sa * z, ca * z - sa * y - self._d[1]
        # Elbow: |S P|^2 = |u|^2 + |s3|^2 - 2 s3 . Rz(t4) u  ->  p cos t4 + q sin t4 = k.
        ux, uy, uz = u
        sx, sy, sz = self._shoulder3
        k = 0.5 * (ux * ux + uy * uy + uz * uz + self._shoulder3_2 - dx * dx - dy * dy - dz * dz)
        elbows = harmonic_roots(sx * ux + sy * uy, sy * ux - sx * uy, k - sz * uz)
        if folds is not None:
            folds.append(fold_distance(sx * ux + sy * uy, sy * ux - sx * uy, k - sz * uz))
        s2, c2, s3, c3 = s[1], c[1], s[2], c[2]
        remainder = math.remainder
        out: list[tuple[float, ...]] = []
        for t4 in elbows:
            q4 = remainder(t4 - off[3], _TWO_PI)
            if not lo[3] <= q4 <= hi[3]:
                continue
            c4, s4 = math.cos(t4), math.sin(t4)
            vx = ux * c4 - uy * s4 - sx
            vy = ux * s4 + uy * c4 - sy
            vz = uz - sz
            vy, vz = c3 * vy - s3 * vz, s3 * vy + c3 * vz  # Rx(alpha3) v
            # Rz(t2) Rx(alpha2) Rz(t3) v = d.
            if folds is not None:
                folds.append(fold_distance(s2 * vy, s2 * vx, dz - c2 * vz))
            for t2, t3 in rotation_pair(s2, c2, vx, vy, vz, dx, dy, dz):
                q3 = remainder(t3 - off[2], _TWO_PI)
                if not lo[2] <= q3 <= hi[2]:
                    continue
                q2 = remainder(t2 - off[1], _TWO_PI)
                if lo[1] <= q2 <= hi[1]:
                    out.append((t1, q2, q3, q4, t2, t3, t4))
        return out

    def pose(
        self, q1: float, frame: tuple[tuple[float, ...], ...], folds: list[float] | None = None
    ) -> list[list[float]]:
        """Joint vectors [rad] inside the limits (up to 8) reaching a full pose with joint 1 at ``q1``.

        Branches leave as soon as one of their joints is outside its limits.

        Args:
            q1: Joint-1 value [rad].
            frame: :meth:`~.SevenDofFrames.pose_frame` of the target.
            folds: Receives the :func:`~.subproblems.fold_distance` of each equation solved
                (the elbow's, each elbow's shoulder equation, each arm's wrist equation).
        """
        wrist, x7, z7 = frame
        arms = self._arm(q1, wrist, self._wrist_u, folds)
        if not arms:
            return []
        s, c, off, lo, hi = self._sin, self._cos, self._offsets, self.lower, self.upper
        remainder, cos, sin, atan2 = math.remainder, math.cos, math.sin, math.atan2
        s5, c5, s6, c6 = s[4], c[4], s[5], c[5]
        gx, gy, gz = self._g
        out = []
        for t1, q2, q3, q4, t2, t3, t4 in arms:
            # x7 and z7 in frame 4: (R01 R12 R23 R34)^T, one (Rz(t) Rx(alpha))^T at a time.
            (xx, xy, xz), (zx, zy, zz) = x7, z7
            for t, sa, ca in (
                (t1, s[0], c[0]),
                (t2, s[1], c[1]),
                (t3, s[2], c[2]),
                (t4, s[3], c[3]),
            ):
                ct, st = cos(t), sin(t)
                xx, xy = ct * xx + st * xy, ct * xy - st * xx
                xy, xz = ca * xy + sa * xz, ca * xz - sa * xy
                zx, zy = ct * zx + st * zy, ct * zy - st * zx
                zy, zz = ca * zy + sa * zz, ca * zz - sa * zy
            if folds is not None:
                folds.append(fold_distance(s5 * gy, s5 * gx, zz - c5 * gz))
            for t5, t6 in rotation_pair(s5, c5, gx, gy, gz, zx, zy, zz):
                q5 = remainder(t5 - off[4], _TWO_PI)
                q6 = remainder(t6 - off[5], _TWO_PI)
                if not (lo[4] <= q5 <= hi[4] and lo[5] <= q6 <= hi[5]):
                    continue
                # t7: (R45 R56)^T x4 = (cos t7, sin t7, 0).
                ct, st = cos(t5), sin(t5)
                nx, ny = ct * xx + st * xy, ct * xy - st * xx
                ny, nz = c5 * ny + s5 * xz, c5 * xz - s5 * ny
                ct, st = cos(t6), sin(t6)
                nx, ny = ct * nx + st * ny, ct * ny - st * nx
                ny = c6 * ny + s6 * nz
                q7 = remainder(atan2(ny, nx) - off[6], _TWO_PI)
                if lo[6] <= q7 <= hi[6]:
                    out.append([q1, q2, q3, q4, q5, q6, q7])
        return out

    def position(
        self,
        q1: float,
        wrist: Sequence[float],
        point0: Sequence[float],
        u: tuple[float, float, float] | None = None,
    ) -> list[list[float]]:
        """Joint vectors [rad] inside the limits (up to 4) putting the tool origin on a point.

        Joints 1 and 5-7 are given (their limits are the caller's business).

        Args:
            q1: Joint-1 value [rad].
            wrist: Joint values ``q5, q6, q7`` [rad].
            point0: Target point in DH frame 0 [m] (:meth:`~.SevenDofFrames.frame0`).
            u: :meth:`~.SevenDofFrames.elbow_vector` of ``wrist`` [m] when the caller has it
                (it depends on the wrist only: A4(t4) maps the tool origin of frame 4 to
                ``Rz(t4) u``).
        """
        q5, q6, q7 = wrist
        if u is None:
            u = self.frames.elbow_vector(q5, q6, q7)
        return [[q1, q2, q3, q4, q5, q6, q7] for _, q2, q3, q4, *_ in self._arm(q1, point0, u)]
