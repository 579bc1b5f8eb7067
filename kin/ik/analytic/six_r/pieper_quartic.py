"""The general family's equation of :class:`~.pieper.Pieper6R`: ``E(t3) = 0`` and its roots.

For a wrist centre ``W`` with ``rt = R - a1^2`` and ``z = Wz - d1`` (see :mod:`.pieper`),
``E(t3) = u^2 + w^2 - g1^2 - g2^2`` with ``u = (rt - |g|^2) / (2 a1)``, ``w = (z - ca1 g3) / sa1``:
a trigonometric polynomial of degree 2 in ``t3`` [rad], in harmonics
(:meth:`PieperQuartic.harmonics`), whose candidate roots (:mod:`._trig_quartic`) are polished
by Newton steps on ``E`` itself (:meth:`PieperQuartic.residual`) and kept when ``|E|`` is
within its bound; for N wrist centres at once. Held by the family's algorithm
(:class:`~.pieper_batch.PieperBatch`) of a general-family arm. Lengths in [m].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ._six_r import wrap_array
from ._trig_quartic import EPS, candidates_batch, polish_batch

#: A general-family root is kept when, after polishing, ``|E(t3)| <= 2 sqrt(g1^2 + g2^2)
#: REACH_TOL`` (plus the rounding of ``E``): the arm then reaches the wrist centre within about
#: ``REACH_TOL`` [m] (``E / (2 sqrt(g1^2 + g2^2))`` is the error of ``|(h1, h2)|``).
REACH_TOL = 1e-10


@dataclass(frozen=True)
class PieperQuartic:
    """The roots ``t3`` of ``E(t3)`` of a general-family :class:`~.pieper.Pieper6R`.

    Attributes:
        a1: Length of the common normal of axes 1 and 2 [m] (not 0).
        offset3: Joint 3's offset ``theta3`` [rad] (the roots are ordered by ``q3``).
        k: ``(a1, d1, sin alpha1, cos alpha1, G0, Gc, Gs)``: the arm's constants, ``|g|^2 = G0
            + Gc cos t3 + Gs sin t3`` [m], [-], [m^2].
        g: The harmonics ``(g_k0, g_kc, g_ks)`` of the components of ``g(t3)`` [m].
        e: The harmonics of ``E``'s fixed terms (see :meth:`harmonics`) [m^2].
    """

    a1: float
    offset3: float
    k: tuple[float, ...]
    g: tuple[tuple[float, float, float], ...]
    e: tuple[float, ...]

    def harmonics(self, rt: Any, z: Any) -> tuple[Any, Any, Any, float, float]:
        """``E(t3) = h0 + hc cos + hs sin + hc2 cos 2t3 + hs2 sin 2t3`` for a wrist centre.

        Floats, or arrays of N wrist centres (``h0``, ``hc``, ``hs`` then arrays too).
        """
        uc, us, wc, ws, e0, pc, ps, hc2, hs2 = self.e
        _, _, sa1, ca1, g0, _, _ = self.k
        u0 = (rt - g0) / (2.0 * self.a1)
        w0 = (z - ca1 * self.g[2][0]) / sa1
        h0 = u0 * u0 + w0 * w0 + e0
        hc = 2.0 * (u0 * uc + w0 * wc) - pc
        hs = 2.0 * (u0 * us + w0 * ws) - ps
        return h0, hc, hs, hc2, hs2

    def residual(self, t3: Any, rt: Any, z: Any) -> tuple[Any, Any, Any]:
        """``E(t3)`` [m^2], ``dE/dt3`` [m^2] and the bound on ``|E|`` of a kept root [m^2].

        Arrays; ``rt = R - a1^2`` [m^2], ``z = Wz - d1`` [m].
        """
        a1, _, sa1, ca1, _, _, _ = self.k
        (g10, g1c, g1s), (g20, g2c, g2s), (g30, g3c, g3s) = self.g
        c3, s3 = np.cos(t3), np.sin(t3)
        g1, g2, g3 = g10 + g1c * c3 + g1s * s3, g20 + g2c * c3 + g2s * s3, g30 + g3c * c3 + g3s * s3
        p_sq = g1 * g1 + g2 * g2
        g_sq = p_sq + g3 * g3
        u = (rt - g_sq) / (2.0 * a1)
        w = (z - ca1 * g3) / sa1
        e = u * u + w * w - p_sq
        d1, d2, d3 = g1s * c3 - g1c * s3, g2s * c3 - g2c * s3, g3s * c3 - g3c * s3
        dp = 2.0 * (g1 * d1 + g2 * d2)
        du = -(dp + 2.0 * g3 * d3) / (2.0 * a1)
        dw = -ca1 * d3 / sa1
        de = 2.0 * (u * du + w * dw) - dp
        rounding = abs(u) * (abs(rt) + g_sq) / abs(a1) + abs(w) * (abs(z) + abs(g3)) / abs(sa1)
        bound = 2.0 * REACH_TOL * p_sq**0.5 + 16.0 * EPS * (rounding + p_sq)
        return e, de, bound

    def roots(self, rt: np.ndarray, z: np.ndarray) -> np.ndarray:
        """The real roots ``t3`` of ``E(t3) = 0`` of N wrist centres, ascending ``q3``, then NaN.

        (N, 4) [rad].
        """
        t3 = candidates_batch(*self.harmonics(rt, z))
        t3 = self._polish_batch(t3, rt[:, None], z[:, None])
        key = np.where(np.isnan(t3), np.inf, wrap_array(t3 - self.offset3))
        return np.take_along_axis(t3, np.argsort(key, axis=1), axis=1)

    def _polish_batch(self, t3: np.ndarray, rt: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Newton steps on ``E`` from (N, 4) starts [rad]; NaN where no root."""
        t3, _, ok = polish_batch(lambda t: self.residual(t, rt, z), t3)
        return np.where(ok, t3, np.nan)
