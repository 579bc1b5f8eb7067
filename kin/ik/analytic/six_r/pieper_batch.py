"""The batched steps of :class:`~.pieper.Pieper6R`: N tool poses at once, in NumPy.

The same arithmetic as the scalar steps of :mod:`.pieper` (the arm by its family's equations,
the general family's quartic in ``t3`` polished, then the spherical wrist), array by array;
:meth:`PieperBatch.solve_batch` of one pose equals :meth:`~.pieper.Pieper6R.solve` (the tests
hold them to it). Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from ...exceptions import TargetError
from ._six_r import SINGULAR, SLACK, TargetFrame, clip_cosines, in_blocks, wrap_array
from .pieper_quartic import PieperQuartic


class PieperBatch(PieperQuartic):
    """:meth:`solve_batch` of a :class:`~.pieper.Pieper6R` (mixed into it: reads its fields)."""

    name: ClassVar[str]
    family: str
    a1: float
    d6: float
    offsets: tuple[float, ...]
    _frame: TargetFrame
    _g: tuple[tuple[float, float, float], ...]
    _k: tuple[float, ...]
    _e: tuple[float, ...]
    _wrist: tuple[float, ...]
    _classic: bool

    def solve_batch(
        self, positions: npt.ArrayLike, rotations: npt.ArrayLike | None, free: float = 0.0
    ) -> np.ndarray:
        """:meth:`solve` of N tool poses at once, in NumPy.

        Args:
            positions: Tool positions in the world frame [m], (N, 3).
            rotations: Tool rotations ``R_world_tool``, (N, 3, 3).
            free: Value of ``q4`` [rad] where the wrist is singular.

        Returns:
            Joint vectors [rad] in (-pi, pi], (N, 8, 6), NaN where a branch does not exist.
        """
        if rotations is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs full poses")
        return in_blocks(self._solve_block, positions, rotations, free)

    def _solve_block(self, positions: np.ndarray, rotations: np.ndarray, free: float) -> np.ndarray:
        p, r = self._frame.batch(positions, rotations)
        with np.errstate(invalid="ignore", divide="ignore"):
            wx, wy, wz = (p - self.d6 * r[:, :, 2]).T
            t = self._arms_batch(wx, wy, wz)  # (N, 4, 3)
            out = self._wrist_batch(t, r, free)
        rows = np.isnan(out).any(axis=2)
        out[rows] = np.nan
        return out

    def _arms_batch(self, wx: np.ndarray, wy: np.ndarray, wz: np.ndarray) -> np.ndarray:
        """:meth:`_arms` of N wrist centres: ``(t1, t2, t3)`` (N, 4, 3) [rad], NaN: no slot."""
        a1, d1, sa1, ca1, g0, _, _ = self._k
        (g10, g1c, g1s), (g20, g2c, g2s), (g30, g3c, g3s) = self._g
        z = wz - d1
        rho2 = wx * wx + wy * wy
        big_r = rho2 + z * z
        heading = np.arctan2(wy, wx)[:, None]
        n = wx.shape[0]
        if self.family == "general":
            t3 = self._general_t3_batch(big_r - a1 * a1, z)  # (N, 4)
        else:
            size, psi = self._e
            cos3 = (big_r - g0) / size if self.family == "intersecting" else (ca1 * z - g30) / size
            delta = np.arccos(clip_cosines(cos3))
            t3 = np.stack((psi - delta, psi + delta), axis=1)  # (N, 2): elbow up, down
        c3, s3 = np.cos(t3), np.sin(t3)
        g1 = g10 + g1c * c3 + g1s * s3
        g2 = g20 + g2c * c3 + g2s * s3
        g3 = g30 + g3c * c3 + g3s * s3
        zc = z[:, None]
        if self.family == "general":
            u = (big_r[:, None] - a1 * a1 - (g1 * g1 + g2 * g2 + g3 * g3)) / (2.0 * a1)
            w = (zc - ca1 * g3) / sa1
            t2 = np.arctan2(g1 * w - g2 * u, g1 * u + g2 * w)
            c2, s2 = np.cos(t2), np.sin(t2)
            h1, h2 = c2 * g1 - s2 * g2, s2 * g1 + c2 * g2
            t1 = heading - np.arctan2(ca1 * h2 - sa1 * g3, a1 + h1)
            return np.stack((t1, t2, t3), axis=-1)
        if self.family == "intersecting":
            h2 = (zc - ca1 * g3) / sa1
            b = ca1 * h2 - sa1 * g3
            rho2c = rho2[:, None]
            a_sq = rho2c - b * b
            a_sq = np.where((a_sq < 0.0) & (a_sq >= -SLACK * (rho2c + b * b + 1.0)), 0.0, a_sq)
            radius = np.sqrt(a_sq)
            h1s, h2s = (radius - a1, -radius - a1), (h2, h2)
        else:
            h1 = (big_r[:, None] - a1 * a1 - (g1 * g1 + g2 * g2 + g3 * g3)) / (2.0 * a1)
            p_sq = g1 * g1 + g2 * g2
            h2_sq = p_sq - h1 * h1
            h2_sq = np.where((h2_sq < 0.0) & (h2_sq >= -SLACK * (p_sq + h1 * h1 + 1.0)), 0.0, h2_sq)
            h2 = math.copysign(1.0, a1 * ca1) * np.sqrt(h2_sq)
            h1s, h2s = (h1, h1), (h2, -h2)
        out = np.empty((n, 4, 3))
        base = np.arctan2(g2, g1)
        for side in (0, 1):
            h1, h2 = h1s[side], h2s[side]
            out[:, 2 * side : 2 * side + 2, 0] = heading - np.arctan2(ca1 * h2 - sa1 * g3, a1 + h1)
            out[:, 2 * side : 2 * side + 2, 1] = np.arctan2(h2, h1) - base
            out[:, 2 * side : 2 * side + 2, 2] = t3
        return out

    def _wrist_batch(self, t: np.ndarray, r: np.ndarray, free: float) -> np.ndarray:
        """The 8 rows of N targets from their arm slots ``t`` (N, 4, 3): ``q`` (N, 8, 6) [rad]."""
        s1, c1, s2, c2, s3, c3, s4, c4, s5, c5 = self._wrist
        o1, o2, o3, o4, o5, o6 = self.offsets
        vx, vy, vz = (r[:, i, 0][:, None] for i in range(3))  # broadcast to (N, 4) below
        nx, ny, nz = (r[:, i, 2][:, None] for i in range(3))
        for joint, sa, ca in ((0, s1, c1), (1, s2, c2), (2, s3, c3)):
            ct, st = np.cos(t[:, :, joint]), np.sin(t[:, :, joint])
            vx, vy = ct * vx + st * vy, -st * vx + ct * vy
            nx, ny = ct * nx + st * ny, -st * nx + ct * ny
            vy, vz = ca * vy + sa * vz, -sa * vy + ca * vz
            ny, nz = ca * ny + sa * nz, -sa * ny + ca * nz
        cos5 = (c4 * c5 - nz) / (s4 * s5)
        if self._classic:
            sin5 = np.sqrt(nx * nx + ny * ny)
        else:
            cos5 = clip_cosines(cos5)
            sin5 = np.sqrt(np.maximum(0.0, 1.0 - cos5 * cos5))
        out = np.empty((t.shape[0], 8, 6))
        arm = wrap_array(t - np.array((o1, o2, o3)))
        out[:, 0::2, :3] = out[:, 1::2, :3] = arm
        t4_regular = np.arctan2(ny, nx)
        for flip in (0, 1):
            st5 = sin5 if flip == 0 else -sin5
            t5 = np.arctan2(st5, cos5)
            mx = s5 * st5
            my = -(c4 * s5 * cos5 + s4 * c5)
            t4 = t4_regular - np.arctan2(my, mx)
            t4 = np.where(np.sqrt(mx * mx + my * my) <= SINGULAR, free + o4, t4)
            ct4, st4 = np.cos(t4), np.sin(t4)
            ex, ey = ct4 * vx + st4 * vy, -st4 * vx + ct4 * vy
            ey, ez = c4 * ey + s4 * vz, -s4 * ey + c4 * vz
            ct5 = np.cos(t5)
            fx, fy = ct5 * ex + st5 * ey, -st5 * ex + ct5 * ey
            fy = c5 * fy + s5 * ez
            t6 = np.arctan2(fy, fx)
            out[:, flip::2, 3:] = wrap_array(np.stack((t4 - o4, t5 - o5, t6 - o6), -1))
        return out
