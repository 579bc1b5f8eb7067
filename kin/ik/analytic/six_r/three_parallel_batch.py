"""The algorithm of :class:`~.three_parallel.ThreeParallel6R`: N tool poses at once, in NumPy.

The one form of the family (one target is N = 1; the compiled twin ``_three_parallel.c`` repeats
it, both cases): joint 1 from the wrist centre, in closed form when axes 5 and 6
meet, else a quartic polished (:mod:`._trig_quartic`); the three parallel axes as a planar 2R;
the wrist. The steps are those of :mod:`.three_parallel`'s docstring; :class:`ThreeParallelBatch`
holds the arm's constants and is held by the arm it solves. Angles in [rad], lengths in [m].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._six_r import SINGULAR, TargetFrame, clip_cosines, sin_cos, wrap_array
from ._trig_quartic import EPS, candidates_batch, polish_batch

#: A general-family root is kept when, after polishing, ``|E(t1)| max(|sa4 a5| [m], |sa4 sa5|)
#: <= 2 REACH_TOL`` (plus the rounding of ``E``): ``(sin t5, cos t5)`` then meets ``A`` within
#: about ``REACH_TOL`` [m] and ``B`` within about ``REACH_TOL`` [-].
REACH_TOL = 1e-10


@dataclass(frozen=True)
class ThreeParallelBatch:
    """The NumPy algorithm of a :class:`~.three_parallel.ThreeParallel6R` and what it reads.

    Held by the arm (:meth:`of` reads its parameters once).

    Attributes:
        family: ``"intersecting"`` (``a5 = 0``) or ``"general"`` (see :mod:`.three_parallel`).
        offsets: Joint offsets ``theta1 .. theta6`` [rad].
        a1, d1, a2, a3, lateral, a4, d5, a5, d6: The arm's lengths of those names [m].
        k: ``sin``, ``cos`` of ``alpha1``, ``alpha4`` and ``alpha5`` in turn [-].
        classic: Both wrist twists +-90 deg (``|sin t5|`` is then read without cancellation).
        frame: World tool pose -> pose of standard frame 6 in frame 0.
    """

    family: str
    offsets: tuple[float, ...]
    a1: float
    d1: float
    a2: float
    a3: float
    lateral: float
    a4: float
    d5: float
    a5: float
    d6: float
    k: tuple[float, ...]
    classic: bool
    frame: TargetFrame = field(repr=False, compare=False)

    @classmethod
    def of(
        cls,
        family: str,
        offsets: tuple[float, ...],
        frame: TargetFrame,
        lengths: tuple[float, ...],
        twists: tuple[float, float, float],
    ) -> ThreeParallelBatch:
        """The algorithm of an arm from its parameters (:class:`~.three_parallel.ThreeParallel6R`).

        Args:
            family: The arm's family.
            offsets: Joint offsets ``theta1 .. theta6`` [rad].
            frame: World tool pose -> pose of standard frame 6 in frame 0.
            lengths: ``(a1, d1, a2, a3, lateral, a4, d5, a5, d6)`` [m].
            twists: ``(alpha1, alpha4, alpha5)`` [rad].
        """
        s1, c1 = sin_cos(twists[0])
        s4, c4 = sin_cos(twists[1])
        s5, c5 = sin_cos(twists[2])
        # Both wrist twists +-90 deg: |sin t5| is then read without cancellation.
        classic = c4 == 0.0 and c5 == 0.0
        a1, d1, a2, a3, lateral, a4, d5, a5, d6 = lengths
        k = (s1, c1, s4, c4, s5, c5)
        return cls(family, offsets, a1, d1, a2, a3, lateral, a4, d5, a5, d6, k, classic, frame)

    def solve_block(self, positions: np.ndarray, rotations: np.ndarray, free: float) -> np.ndarray:
        """The 8 branches (N, 8, 6) [rad] of N world tool poses, NaN where a branch is missing."""
        p, r = self.frame.batch(positions, rotations)
        with np.errstate(invalid="ignore", divide="ignore"):
            n = r[:, :, 2]
            w = p - self.d6 * n
            if self.family == "general":
                slots = self._general_slots_batch(w, n)
            else:
                slots = self._intersecting_slots_batch(w, n)
            out = self._arm_batch(slots, w, r, free)
        out[np.isnan(out).any(axis=2)] = np.nan
        return out

    def _intersecting_slots_batch(self, w: np.ndarray, n: np.ndarray) -> np.ndarray:
        """``(t1, cos t5, sin t5)`` of the four slots (shoulder, wrist) when ``a5 = 0``.

        (N, 4, 3) [rad], [-], NaN: no slot.
        """
        s1, c1, s4, c4, s5, c5 = self.k
        wx, wy, wz = w.T
        rho = np.hypot(wx, wy)
        k = (c1 * (wz - self.d1) - self.lateral) / (s1 * rho)
        k = np.where(rho == 0.0, np.nan, clip_cosines(k))
        beta = np.arctan2(wy, wx)
        asin_k = np.arcsin(k)
        out = np.empty((w.shape[0], 4, 3))
        for shoulder in (0, 1):
            t1 = beta - asin_k if shoulder == 0 else beta - math.pi + asin_k
            z1 = (s1 * np.sin(t1), -s1 * np.cos(t1), c1)
            cos5 = (c4 * c5 - (n[:, 0] * z1[0] + n[:, 1] * z1[1] + n[:, 2] * z1[2])) / (s4 * s5)
            if self.classic:
                sin5 = np.sqrt(
                    (n[:, 1] * z1[2] - n[:, 2] * z1[1]) ** 2
                    + (n[:, 2] * z1[0] - n[:, 0] * z1[2]) ** 2
                    + (n[:, 0] * z1[1] - n[:, 1] * z1[0]) ** 2
                )
            else:
                cos5 = clip_cosines(cos5)
                sin5 = np.sqrt(1.0 - cos5 * cos5)
            for wrist, sign in ((0, 1.0), (1, -1.0)):
                out[:, 2 * shoulder + wrist] = np.stack((t1, cos5, sign * sin5), axis=-1)
        return out

    def _general_slots_batch(self, w: np.ndarray, n: np.ndarray) -> np.ndarray:
        """``(t1, cos t5, sin t5)`` of the real roots of ``E(t1)``, ascending ``q1``, then NaN.

        (N, 4, 3) [rad], [-].
        """
        uv = self._uv(*w.T, *n.T)
        t1 = candidates_batch(*harmonics(uv))
        slots = self._polish_batch(t1, tuple(np.asarray(k)[:, None] for k in uv))
        key = np.where(
            np.isnan(slots[:, :, 0]), np.inf, wrap_array(slots[:, :, 0] - self.offsets[0])
        )
        return np.take_along_axis(slots, np.argsort(key, axis=1)[:, :, None], axis=1)

    def _uv(self, wx: Any, wy: Any, wz: Any, nx: Any, ny: Any, nz: Any) -> tuple[Any, ...]:
        """``u = u0 + uc c1 + us s1``, ``v = v0 + vc c1 + vs s1`` and their rounding scales.

        Arrays of N targets: ``(u0, uc, us, v0, vc, vs, su, sv)``, ``su``, ``sv`` the sums of the
        magnitudes that make up ``u``, ``v`` [-].
        """
        s1, c1, s4, c4, s5, c5 = self.k
        ka, kb = s4 * self.a5, s4 * s5
        u0 = (c1 * (wz - self.d1) - self.lateral) / ka
        v0 = (c4 * c5 - c1 * nz) / kb
        su = abs(s1) * (abs(wx) + abs(wy)) + abs(c1) * (abs(wz) + abs(self.d1)) + abs(self.lateral)
        sv = abs(s1) * (abs(nx) + abs(ny)) + abs(c1 * nz) + abs(c4 * c5)
        return (u0, -s1 * wy / ka, s1 * wx / ka, v0, s1 * ny / kb, -s1 * nx / kb,
                su / abs(ka), sv / abs(kb))  # fmt: skip

    def _residual(self, t1: Any, uv: tuple[Any, ...]) -> tuple[Any, Any, Any, Any, Any]:
        """``E(t1)`` [-], ``dE/dt1`` [-], the bound on ``|E|`` of a kept root, ``u`` and ``v``."""
        u0, uc, us, v0, vc, vs, su, sv = uv
        c, s = np.cos(t1), np.sin(t1)
        u = u0 + uc * c + us * s
        v = v0 + vc * c + vs * s
        e = u * u + v * v - 1.0
        de = 2.0 * (u * (us * c - uc * s) + v * (vs * c - vc * s))
        _, _, s4, _, s5, _ = self.k
        reach = 2.0 * REACH_TOL / max(abs(s4 * self.a5), abs(s4 * s5))
        bound = reach + 16.0 * EPS * (abs(u) * su + abs(v) * sv + 1.0)
        return e, de, bound, u, v

    def _polish_batch(self, t1: np.ndarray, uv: tuple[np.ndarray, ...]) -> np.ndarray:
        """Newton steps on ``E`` from (N, 4) starts: (N, 4, 3), NaN where no root."""
        t1, (u, v), ok = polish_batch(lambda t: self._residual(t, uv), t1)
        size = np.hypot(u, v)
        out = np.stack((t1, v / size, u / size), axis=-1)
        out[~ok] = np.nan
        return out

    def _arm_batch(
        self, slots: np.ndarray, w: np.ndarray, r: np.ndarray, free: float
    ) -> np.ndarray:
        """The 8 rows (N, 8, 6) [rad] of N targets from their slots ``(t1, cos t5, sin t5)``."""
        s1, c1, s4, c4, s5a, c5a = self.k
        a2, a3, a5 = self.a2, self.a3, self.a5
        o1, o2, o3, o4, o5, o6 = self.offsets
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = (
            (r[:, i, 0, None], r[:, i, 1, None], r[:, i, 2, None]) for i in range(3)
        )
        t1, cos5, st5 = slots[:, :, 0], slots[:, :, 1], slots[:, :, 2]
        ct, st = np.cos(t1), np.sin(t1)
        y1 = (-c1 * st, c1 * ct, s1)
        z1 = (s1 * st, -s1 * ct, c1)
        x6 = r00 * z1[0] + r10 * z1[1] + r20 * z1[2]
        y6 = r01 * z1[0] + r11 * z1[1] + r21 * z1[2]
        t5 = np.arctan2(st5, cos5)
        vx, vy = s4 * st5, c5a * s4 * cos5 + s5a * c4
        t6 = np.where(
            np.hypot(x6, y6) <= SINGULAR, free + o6, np.arctan2(vy, vx) - np.arctan2(y6, x6)
        )
        ct6, st6 = np.cos(t6), np.sin(t6)
        xi0 = cos5 * ct6 - st5 * c5a * st6
        xi1 = -cos5 * st6 - st5 * c5a * ct6
        xi2 = s5a * st5
        rx = r00 * xi0 + r01 * xi1 + r02 * xi2
        ry = r10 * xi0 + r11 * xi1 + r12 * xi2
        rz = r20 * xi0 + r21 * xi1 + r22 * xi2
        phi = np.arctan2(y1[0] * rx + y1[1] * ry + y1[2] * rz, ct * rx + st * ry)
        cp, sp = np.cos(phi), np.sin(phi)
        qx, qy, qz = (
            w[:, 0, None] - self.a1 * ct,
            w[:, 1, None] - self.a1 * st,
            w[:, 2, None] - self.d1,
        )
        ex, ey = self.a4 + a5 * cos5, c4 * a5 * st5 - s4 * self.d5
        bx = ct * qx + st * qy - (cp * ex - sp * ey)
        by = y1[0] * qx + y1[1] * qy + y1[2] * qz - (sp * ex + cp * ey)
        cos3 = clip_cosines((bx * bx + by * by - (a2 * a2 + a3 * a3)) / (2.0 * a2 * a3))
        sin3 = np.sqrt(1.0 - cos3 * cos3)
        heading = np.arctan2(by, bx)
        out = np.empty((slots.shape[0], 8, 6))
        for elbow, sign in ((0, 1.0), (1, -1.0)):
            st3 = sign * sin3
            t3 = np.arctan2(st3, cos3)
            t2 = heading - np.arctan2(a3 * st3, a2 + a3 * cos3)
            t4 = phi - t2 - t3
            q = np.stack((t1 - o1, t2 - o2, t3 - o3, t4 - o4, t5 - o5, t6 - o6), -1)
            out[:, elbow::2] = wrap_array(q)
        return out


def harmonics(uv: tuple[Any, ...]) -> tuple[Any, Any, Any, Any, Any]:
    """``E = u^2 + v^2 - 1 = h0 + hc cos t1 + hs sin t1 + hc2 cos 2t1 + hs2 sin 2t1``."""
    u0, uc, us, v0, vc, vs = uv[:6]
    h0 = u0 * u0 + v0 * v0 - 1.0 + 0.5 * (uc * uc + us * us + vc * vc + vs * vs)
    hc = 2.0 * (u0 * uc + v0 * vc)
    hs = 2.0 * (u0 * us + v0 * vs)
    hc2 = 0.5 * (uc * uc - us * us + vc * vc - vs * vs)
    hs2 = uc * us + vc * vs
    return h0, hc, hs, hc2, hs2
