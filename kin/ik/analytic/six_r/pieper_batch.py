"""The algorithm of :class:`~.pieper.Pieper6R`: N tool poses at once, in NumPy.

The one form of the family (one target is N = 1; the compiled twin ``_pieper_arms.c`` repeats it
for every case): the arm by its family's equations (the general family's quartic in ``t3``
polished, :mod:`.pieper_quartic`), then the spherical wrist; the steps are those of
:mod:`.pieper`'s docstring. :class:`PieperBatch` holds the arm's constants (read once from its
parameters, :meth:`PieperBatch.of`) and is held by the :class:`~.pieper.Pieper6R` it solves.
Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ._six_r import SINGULAR, SLACK, TargetFrame, clip_cosines, wrap_array
from .pieper_quartic import PieperQuartic


@dataclass(frozen=True)
class PieperBatch:
    """The NumPy algorithm of a :class:`~.pieper.Pieper6R` and the constants it reads.

    Attributes:
        family: The arm's family (``"intersecting"``, ``"parallel"``, ``"general"``,
            ``"parallel23"``; see :mod:`.pieper`).
        offsets: Joint offsets ``theta1 .. theta6`` [rad].
        a1, d1, a2, d6: The arm's lengths of those names [m].
        k: ``(a1, d1, sin alpha1, cos alpha1, G0, Gc, Gs)`` with ``|g|^2 = G0 + Gc cos t3 + Gs
            sin t3`` [m], [-], [m^2].
        g: The harmonics ``(g_k0, g_kc, g_ks)`` of the components of ``g(t3)`` [m].
        e: The family's own constants: ``(lx, ly, |l|, angle of l, h)`` (parallel23), ``(size,
            psi)`` of the ``t3`` equation (intersecting, parallel), the harmonics of ``E``
            (general) [m], [rad], [m^2].
        wrist: ``sin``, ``cos`` of ``alpha1 .. alpha5`` in turn [-].
        classic: Both wrist twists +-90 deg (``|sin t5|`` is then read without cancellation).
        frame: World tool pose -> pose of standard frame 6 in frame 0.
        quartic: The general family's equation in ``t3`` (None in the other families).
    """

    family: str
    offsets: tuple[float, ...]
    a1: float
    d1: float
    a2: float
    d6: float
    k: tuple[float, ...]
    g: tuple[tuple[float, float, float], ...]
    e: tuple[float, ...]
    wrist: tuple[float, ...]
    classic: bool
    frame: TargetFrame = field(repr=False, compare=False)
    quartic: PieperQuartic | None = field(default=None, repr=False, compare=False)

    @classmethod
    def of(
        cls,
        family: str,
        offsets: tuple[float, ...],
        frame: TargetFrame,
        lengths: tuple[float, ...],
        twists: tuple[float, ...],
    ) -> PieperBatch:
        """The algorithm of an arm from its parameters (those of :class:`~.pieper.Pieper6R`).

        Args:
            family: The arm's family.
            offsets: Joint offsets ``theta1 .. theta6`` [rad].
            frame: World tool pose -> pose of standard frame 6 in frame 0.
            lengths: ``(a1, d1, a2, d2, a3, d3, d4, d6)`` [m].
            twists: ``(alpha1, alpha2, alpha3, alpha4, alpha5)`` [rad].
        """
        a1, d1, a2, d2, a3, d3, d4, d6 = lengths
        alpha1, alpha2, alpha3, _, _ = twists
        sa2, ca2 = math.sin(alpha2), math.cos(alpha2)
        sa3, ca3 = math.sin(alpha3), math.cos(alpha3)
        f3 = d3 + ca3 * d4
        ly = sa3 * d4  # f = Rz(t3) (a3, -ly, f3)
        g = (
            (a2, a3, ly),
            (-sa2 * f3, -ca2 * ly, ca2 * a3),
            (d2 + ca2 * f3, -sa2 * ly, sa2 * a3),
        )
        sa1, ca1 = math.sin(alpha1), math.cos(alpha1)
        # |g|^2 = G0 + Gc cos t3 + Gs sin t3
        g0 = sum(gk[0] * gk[0] + 0.5 * (gk[1] * gk[1] + gk[2] * gk[2]) for gk in g)
        gc = sum(2.0 * gk[0] * gk[1] for gk in g)
        gs = sum(2.0 * gk[0] * gk[2] for gk in g)
        k = (a1, d1, sa1, ca1, g0, gc, gs)
        e: tuple[float, ...] = ()
        if family == "parallel23":
            # the forearm from axis 3 to the wrist centre in the arm plane, and the wrist
            # centre's offset along axis 2: (lx, ly, |l|, angle of l, h)
            lx, ly = a3, -sa3 * d4
            lateral = d2 + d3 + ca3 * d4
            e = (lx, ly, math.hypot(lx, ly), math.atan2(ly, lx), lateral)
        elif family == "intersecting":
            e = (math.hypot(gc, gs), math.atan2(gs, gc))
        elif family == "parallel":
            e = (math.hypot(g[2][1], g[2][2]), math.atan2(g[2][2], g[2][1]))
        else:
            # E = u^2 + w^2 - P: the t3-parts of u, w (uc, us, wc, ws) and the harmonics of the
            # fixed terms; the target adds u0, w0 (see PieperQuartic.harmonics).
            two_a1 = 2.0 * a1
            uc, us = -gc / two_a1, -gs / two_a1
            wc, ws = -ca1 * g[2][1] / sa1, -ca1 * g[2][2] / sa1
            p0 = sum(gk[0] * gk[0] + 0.5 * (gk[1] * gk[1] + gk[2] * gk[2]) for gk in g[:2])
            pc = sum(2.0 * gk[0] * gk[1] for gk in g[:2])
            ps = sum(2.0 * gk[0] * gk[2] for gk in g[:2])
            pc2 = sum(0.5 * (gk[1] * gk[1] - gk[2] * gk[2]) for gk in g[:2])
            ps2 = sum(gk[1] * gk[2] for gk in g[:2])
            e = (
                uc, us, wc, ws,
                0.5 * (uc * uc + us * us + wc * wc + ws * ws) - p0,
                pc, ps,
                0.5 * (uc * uc - us * us + wc * wc - ws * ws) - pc2,
                uc * us + wc * ws - ps2,
            )  # fmt: skip
        wrist: tuple[float, ...] = ()
        for angle in twists:
            wrist += (math.sin(angle), math.cos(angle))
        # Both wrist twists +-90 deg: |sin t5| is then read without cancellation.
        classic = abs(wrist[7]) < 1e-15 and abs(wrist[9]) < 1e-15
        quartic = PieperQuartic(a1, offsets[2], k, g, e) if family == "general" else None
        return cls(family, offsets, a1, d1, a2, d6, k, g, e, wrist, classic, frame, quartic)

    def solve_block(self, positions: np.ndarray, rotations: np.ndarray, free: float) -> np.ndarray:
        """The 8 branches (N, 8, 6) [rad] of N world tool poses, NaN where a branch is missing."""
        p, r = self.frame.batch(positions, rotations)
        with np.errstate(invalid="ignore", divide="ignore"):
            wx, wy, wz = (p - self.d6 * r[:, :, 2]).T
            t = self._arms_batch(wx, wy, wz)  # (N, 4, 3)
            out = self._wrist_batch(t, r, free)
        rows = np.isnan(out).any(axis=2)
        out[rows] = np.nan
        return out

    def _arms_batch(self, wx: np.ndarray, wy: np.ndarray, wz: np.ndarray) -> np.ndarray:
        """``(t1, t2, t3)`` (N, 4, 3) [rad] of the four arm slots reaching N wrist centres [m].

        NaN: no slot.
        """
        if self.family == "parallel23":
            return self._parallel23_arms(wx, wy, wz)
        a1, d1, sa1, ca1, g0, _, _ = self.k
        (g10, g1c, g1s), (g20, g2c, g2s), (g30, g3c, g3s) = self.g
        z = wz - d1
        rho2 = wx * wx + wy * wy
        big_r = rho2 + z * z
        heading = np.arctan2(wy, wx)[:, None]
        n = wx.shape[0]
        if self.quartic is not None:  # the general family
            t3 = self.quartic.roots(big_r - a1 * a1, z)  # (N, 4)
        else:
            size, psi = self.e
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

    def _parallel23_arms(self, wx: np.ndarray, wy: np.ndarray, wz: np.ndarray) -> np.ndarray:
        """:meth:`_arms_batch` of the parallel23 family (axes 2, 3 parallel): (N, 4, 3) [rad]."""
        a1, d1, a2 = self.a1, self.d1, self.a2
        _, _, s1, c1, *_ = self.k
        lx, ly, l3, phi3, h = self.e
        y1 = (wz - d1 - c1 * h) / s1
        b = c1 * y1 - s1 * h
        rho2 = wx * wx + wy * wy
        a_sq = rho2 - b * b
        a_sq = np.where((a_sq < 0.0) & (a_sq >= -SLACK * (rho2 + b * b + 1.0)), 0.0, a_sq)
        radius = np.sqrt(a_sq)  # NaN out of reach
        heading = np.arctan2(wy, wx)
        out = np.empty((wx.shape[0], 4, 3))
        for shoulder in (0, 1):
            big_a = radius if shoulder == 0 else -radius
            t1 = heading - np.arctan2(b, big_a)
            x1 = big_a - a1
            cos3 = clip_cosines((x1 * x1 + y1 * y1 - (a2 * a2 + l3 * l3)) / (2.0 * a2 * l3))
            delta = np.arccos(cos3)
            heading1 = np.arctan2(y1, x1)
            for elbow in (0, 1):
                t3 = -phi3 - delta if elbow == 0 else -phi3 + delta
                ct3, st3 = np.cos(t3), np.sin(t3)
                t2 = heading1 - np.arctan2(lx * st3 + ly * ct3, a2 + lx * ct3 - ly * st3)
                out[:, 2 * shoulder + elbow] = np.stack((t1, t2, t3), axis=-1)
        return out

    def _wrist_batch(self, t: np.ndarray, r: np.ndarray, free: float) -> np.ndarray:
        """The 8 rows of N targets from their arm slots ``t`` (N, 4, 3): ``q`` (N, 8, 6) [rad]."""
        s1, c1, s2, c2, s3, c3, s4, c4, s5, c5 = self.wrist
        o1, o2, o3, o4, o5, o6 = self.offsets
        vx, vy, vz = (r[:, i, 0][:, None] for i in range(3))  # broadcast to (N, 4) below
        nx, ny, nz = (r[:, i, 2][:, None] for i in range(3))
        # N = R_0_3^T R_0_6, columns 0 (v) and 2 (n): Rx(a3)^T Rz(t3)^T ... Rx(a1)^T Rz(t1)^T;
        # with axes 2 and 3 parallel, Rz(t2 + t3) at once (as the compiled twin does)
        stages = [(t[:, :, 0], s1, c1), (t[:, :, 1], s2, c2), (t[:, :, 2], s3, c3)]
        if self.family == "parallel23":
            stages[1:] = [(t[:, :, 1] + t[:, :, 2], s3, c3)]
        for angle, sa, ca in stages:
            ct, st = np.cos(angle), np.sin(angle)
            vx, vy = ct * vx + st * vy, -st * vx + ct * vy
            nx, ny = ct * nx + st * ny, -st * nx + ct * ny
            vy, vz = ca * vy + sa * vz, -sa * vy + ca * vz
            ny, nz = ca * ny + sa * nz, -sa * ny + ca * nz
        cos5 = (c4 * c5 - nz) / (s4 * s5)
        if self.classic:
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
