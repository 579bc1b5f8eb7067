"""Closed-form IK of the seven-joint arm (:class:`~kin.ik.analytic.structure.SevenDof`) for a chosen joint-1 angle.

The arm is redundant: joint 1 is left free. For a given ``q1``:

1. the shoulder point ``S`` (where axes 2 and 3 meet) is fixed, and the wrist centre ``W`` (where
   axes 5, 6 and 7 meet) follows from the tool pose; ``|SW|`` depends on the elbow angle only:
   ``P cos t4 + Q sin t4 = K`` gives ``t4`` (two branches);
2. ``Rz(t2) Rx(alpha2) Rz(t3) v = SW`` (``v`` the shoulder-to-wrist vector in frame 3 rotated by
   ``Rx(alpha3)``) gives ``t2, t3`` (two branches, :func:`~.subproblems.rotation_pair`);
3. the wrist: ``Rz(t5) Rx(alpha5) Rz(t6) Rx(alpha6) e_z`` must equal the tool's joint-7 axis seen
   in frame 4 (``t5, t6``: two branches, the same sub-problem), ``t7`` is what remains.

Up to 8 joint vectors per ``q1``. For a position-only target the wrist angles are chosen too
(``q5, q6, q7``): the tool point is then fixed in frame 4 and steps 1-2 place it (up to 4 vectors).

All of it is scalar arithmetic; the numeric solver (:mod:`ik.numeric`) picks ``q1`` (and the
wrist) from its seed table and has Pinocchio judge every answer. :meth:`SevenDofIK.first` runs the
compiled twin of this module (``kin/_native/_closed7.c``, an optional extension built at install when a C
compiler is there) and this Python code otherwise; the tests compare the two. ``t_i`` are DH
angles, ``q_i = t_i - theta_i`` joint values [rad]; lengths in [m].
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np

from kin._native import twin

from ..structure import SevenDof
from .seven_dof_frames import SevenDofFrames
from .subproblems import fold_distance, harmonic_roots, rotation_pair, scan

_closed7 = twin("_closed7")

#: Whether the compiled twin (``kin/_native/_closed7.c``) is built.
COMPILED = _closed7 is not None

_TWO_PI = 2.0 * math.pi


class SevenDofIK(SevenDofFrames):
    """Closed-form branches of a :class:`~kin.ik.analytic.structure.SevenDof` arm for chosen free joints.

    Its targets' frames and its twin's parameters: :class:`~.seven_dof_frames.SevenDofFrames`.

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
        self.lower = tuple(float(v) for v in lower)
        self.upper = tuple(float(v) for v in upper)
        a, alpha, d = structure.a, structure.alpha, structure.d
        self._a, self._d, self._offsets = a, d, structure.offsets
        self._sin = tuple(math.sin(v) for v in alpha)
        self._cos = tuple(math.cos(v) for v in alpha)
        base = structure.T_world_base
        self._base_r = np.array(base[:3, :3], dtype=float)
        self._base_t = np.array(base[:3, 3], dtype=float)
        tool = structure.T_last_tool
        self._tool_r = np.array(tool[:3, :3], dtype=float)
        self._tool_t = np.array(tool[:3, 3], dtype=float)
        self._c_params = None
        self._plain = bool(np.array_equal(base, np.eye(4)) and np.array_equal(tool, np.eye(4)))
        s, c = self._sin, self._cos
        # Shoulder point in frame 3: o2 = -Rx(alpha3)^T (a3, 0, d3), whatever t3.
        self._shoulder3 = (-a[2], -s[2] * d[2], -c[2] * d[2])
        self._shoulder3_2 = sum(v * v for v in self._shoulder3)
        # Wrist centre in frame 3: Rz(t4) u.
        self._wrist_u = self._elbow_vector(0.0, 0.0, d[4])
        # Wrist centre in frame 7: o6 = -Rx(alpha7)^T (a7, 0, d7).
        self._wrist7 = (-a[6], -s[6] * d[6], -c[6] * d[6])
        # Joint-7 axis direction (frame 7 z of M = R47 Rx(alpha7)^T) seen in frame 7.
        self._axis7 = (0.0, s[6], c[6])
        self._g = (0.0, -s[5], c[5])  # Rx(alpha6) e_z
        self._unlimited: SevenDofIK | None = None

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
            frame = self._frame_of(values[:3].tolist(), values[3:].reshape(3, 3).tolist())
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
            frame: :meth:`pose_frame` of the target.
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
            point0: Target point in DH frame 0 [m] (:meth:`frame0`).
            u: :meth:`elbow_vector` of ``wrist`` [m] when the caller has it (it depends on the
                wrist only: A4(t4) maps the tool origin of frame 4 to ``Rz(t4) u``).
        """
        q5, q6, q7 = wrist
        if u is None:
            u = self.elbow_vector(q5, q6, q7)
        return [[q1, q2, q3, q4, q5, q6, q7] for _, q2, q3, q4, *_ in self._arm(q1, point0, u)]
