"""Closed-form IK of a 6R arm with a spherical wrist and any first three joints (Pieper's case).

Structure, read from the table brought to the standard chain (:mod:`._six_r`, either convention):

- joints 4, 5, 6: a spherical wrist, as in :mod:`.spherical_wrist` (``a4 = a5 = d5 = 0``,
  ``sin alpha4 != 0``, ``sin alpha5 != 0``; ``d6``, ``a6``, ``alpha6`` free);
- joints 1, 2, 3: any lengths and twists for which the wrist-centre problem has finitely many
  solutions: a forearm ``(a3, sin(alpha3) d4) != 0`` (the wrist centre is off axis 3), axes 2 and
  3 not the same line, and one of three families (Craig, *Introduction to Robotics*, sec. 4.6;
  the IK-Geo families "spherical wrist and two intersecting / two parallel axes / general"):

  * ``intersecting``: ``a1 = 0``, ``sin alpha1 != 0`` (axes 1 and 2 meet), axis 3 not through
    that point (``(a2, sin(alpha2) d2) != 0``);
  * ``parallel``: ``sin alpha1 = 0``, ``a1 != 0`` (axes 1 and 2 parallel), axis 3 not parallel
    to them (``sin alpha2 != 0``);
  * ``general``: ``a1 != 0`` and ``sin alpha1 != 0``.

Solution (``t_i`` DH angles, ``q_i = t_i - theta_i`` [rad], lengths [m]; standard DH,
``T_i = Rz(t_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``, ``s``/``c`` of a twist written ``sa_i``/``ca_i``):

1. Wrist centre ``W = p_0_6 - d6 z_6 = T_1 T_2 T_3 (0, 0, d4)``. In frame 2 it is
   ``f(t3) = Rz(t3) (a3, -sa3 d4, d3 + ca3 d4)``; in frame 1 before ``Rz(t2)`` it is
   ``g(t3) = (a2, 0, d2) + Rx(alpha2) f``, each component ``g_k = g_k0 + g_kc cos t3 + g_ks sin t3``;
   in frame 1 ``h = Rz(t2) g``; and ``W = Rz(t1) (a1 + h1, ca1 h2 - sa1 h3, d1 + sa1 h2 + ca1 h3)``.
2. With ``Z = Wz - d1`` and ``R = Wx^2 + Wy^2 + Z^2`` (both free of ``t1``) and ``|h| = |g|``:

   ``R - a1^2 - |g|^2 = 2 a1 h1`` (A) and ``Z - ca1 g3 = sa1 h2`` (B), where
   ``(h1, h2) = Rz(t2) (g1, g2)``.

   - intersecting (``a1 = 0``): (A) is ``|g(t3)|^2 = R``, linear in ``(cos t3, sin t3)``: two
     ``t3 = psi -+ acos(.)`` (elbow up / down); (B) gives ``h2``, the base radius
     ``a1 + h1 = +-sqrt(Wx^2 + Wy^2 - (ca1 h2 - sa1 h3)^2)`` (shoulder right / left);
   - parallel (``sa1 = 0``): (B) is ``g3(t3) = ca1 Z``: two ``t3`` (elbow up / down); (A) gives
     ``h1``, and ``h2 = +-sqrt(g1^2 + g2^2 - h1^2)``: the arm of axes 1-2 bends counter-clockwise
     or clockwise about ``z_0`` (``a1 ca1 h2 >= 0``: ccw);
   - general: ``u = (R - a1^2 - |g|^2) / (2 a1)`` and ``w = (Z - ca1 g3) / sa1`` are ``(h1, h2)``,
     so ``E(t3) = u^2 + w^2 - g1^2 - g2^2 = 0``: a trigonometric polynomial of degree 2, that is a
     quartic in ``x = tan((t3 - tau) / 2)``. The shift ``tau`` (a multiple of 45 deg) makes
     ``|E(tau + pi)|``, the leading coefficient, the largest of eight, so no root runs off to
     infinity. The real roots of its companion matrix, polished by Newton steps on ``E`` itself
     (not on the expanded polynomial), are kept when ``|E|`` is below :data:`~.pieper_quartic.REACH_TOL`; they
     are ordered by ``q3`` (``arm 1 .. 4``). Then ``(cos t2, sin t2) ~ (g1 u + g2 w, g1 w - g2 u)``.

   Then ``t2 = atan2(h2, h1) - atan2(g2, g1)`` and
   ``t1 = atan2(Wy, Wx) - atan2(ca1 h2 - sa1 h3, a1 + h1)`` with ``h = Rz(t2) g``.
3. ``N = R_0_3^T R_0_6 = Rz(t4) Rx(alpha4) Rz(t5) Rx(alpha5) Rz(t6)`` as in
   :mod:`.spherical_wrist`: ``cos t5`` from its third column, two signs of ``sin t5`` (wrist no flip:
   ``sin t5 >= 0``, flip: ``< 0``), ``t4``, then ``t6`` from the first column; at ``sin t5 = 0``
   (axes 4 and 6 aligned) ``q4`` takes the value ``free``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ...exceptions import TargetError
from ...target import PoseTarget
from ._six_r import (
    ANGLE_TOL,
    LENGTH_TOL,
    NAN_ROW,
    SINGULAR,
    SLACK,
    SixRChecker,
    TargetFrame,
    clip_unit,
    wrap,
)
from .pieper_batch import PieperBatch

_ARM_LABELS = {
    "intersecting": tuple(
        f"shoulder {s}, elbow {e}" for s in ("right", "left") for e in ("up", "down")
    ),
    "parallel": tuple(f"arm {s}, elbow {e}" for s in ("ccw", "cw") for e in ("up", "down")),
    "general": tuple(f"arm {k} (q3 ascending)" for k in range(1, 5)),
}


@dataclass(frozen=True)
class Pieper6R(PieperBatch):
    """A 6R arm with a spherical wrist and a general 3R arm: parameters in SI, closed form (8 branches).

    Attributes:
        robot: Robot name.
        family: ``"intersecting"`` (axes 1, 2 meet), ``"parallel"`` (axes 1, 2 parallel) or
            ``"general"`` (see the module).
        a1: Length of the common normal of axes 1 and 2 [m].
        d1: Height of that normal along axis 1 [m].
        alpha1: Twist between axes 1 and 2 [rad] (0 or pi exactly in the parallel family).
        a2, alpha2, d2: Common normal, twist and offset of joint 2 [m], [rad].
        a3, alpha3, d3: The same of joint 3 [m], [rad].
        d4: Offset along axis 4 from the normal of axes 3 and 4 to the wrist centre [m].
        alpha4: Twist between axes 4 and 5 [rad].
        alpha5: Twist between axes 5 and 6 [rad].
        d6: Distance from the wrist centre to standard frame 6 along axis 6 [m].
        offsets: Joint offsets ``theta1 .. theta6`` [rad] (DH angle = q + offset).
        T_base: World -> standard DH frame 0 (4x4) [m].
        T_tool: Standard frame 6 (``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
    """

    name: ClassVar[str] = "pieper"
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)

    robot: str
    family: str
    a1: float
    d1: float
    alpha1: float
    a2: float
    alpha2: float
    d2: float
    a3: float
    alpha3: float
    d3: float
    d4: float
    alpha4: float
    alpha5: float
    d6: float
    offsets: tuple[float, ...]
    T_base: np.ndarray = field(repr=False)
    T_tool: np.ndarray = field(repr=False)
    _frame: TargetFrame = field(init=False, repr=False, compare=False)
    _g: tuple[tuple[float, float, float], ...] = field(init=False, repr=False, compare=False)
    _k: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _e: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _wrist: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _classic: bool = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        setattr_ = object.__setattr__
        setattr_(self, "_frame", TargetFrame(self.T_base, self.T_tool))
        sa2, ca2 = math.sin(self.alpha2), math.cos(self.alpha2)
        sa3, ca3 = math.sin(self.alpha3), math.cos(self.alpha3)
        f3 = self.d3 + ca3 * self.d4
        ly = sa3 * self.d4  # f = Rz(t3) (a3, -ly, f3)
        g = (
            (self.a2, self.a3, ly),
            (-sa2 * f3, -ca2 * ly, ca2 * self.a3),
            (self.d2 + ca2 * f3, -sa2 * ly, sa2 * self.a3),
        )
        setattr_(self, "_g", g)
        sa1, ca1 = math.sin(self.alpha1), math.cos(self.alpha1)
        # |g|^2 = G0 + Gc cos t3 + Gs sin t3
        g0 = sum(gk[0] * gk[0] + 0.5 * (gk[1] * gk[1] + gk[2] * gk[2]) for gk in g)
        gc = sum(2.0 * gk[0] * gk[1] for gk in g)
        gs = sum(2.0 * gk[0] * gk[2] for gk in g)
        setattr_(self, "_k", (self.a1, self.d1, sa1, ca1, g0, gc, gs))
        e: tuple[float, ...] = ()
        if self.family == "intersecting":
            e = (math.hypot(gc, gs), math.atan2(gs, gc))
        elif self.family == "parallel":
            e = (math.hypot(g[2][1], g[2][2]), math.atan2(g[2][2], g[2][1]))
        else:
            # E = u^2 + w^2 - P: the t3-parts of u, w (uc, us, wc, ws) and the harmonics of the
            # fixed terms; the target adds u0, w0 (see _harmonics).
            two_a1 = 2.0 * self.a1
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
        setattr_(self, "_e", e)
        wrist: tuple[float, ...] = ()
        for angle in (self.alpha1, self.alpha2, self.alpha3, self.alpha4, self.alpha5):
            wrist += (math.sin(angle), math.cos(angle))
        setattr_(self, "_wrist", wrist)
        # Both wrist twists +-90 deg: |sin t5| is then read without cancellation.
        setattr_(self, "_classic", abs(wrist[7]) < 1e-15 and abs(wrist[9]) < 1e-15)

    @property
    def branch_labels(self) -> tuple[str, ...]:
        """The meaning of the 8 rows of :meth:`solve`: the family's arm, then the wrist."""
        return tuple(
            f"{arm}, wrist {w}" for arm in _ARM_LABELS[self.family] for w in ("no flip", "flip")
        )

    @classmethod
    def recognise(cls, table: DHTable) -> Pieper6R:
        """The parameters of ``table``'s arm.

        Raises:
            StructureError: The table is not a 6R arm with a spherical wrist and a 3R arm of
                finitely many solutions; the message names the row and the parameter.
        """
        check = SixRChecker(table, "6R Pieper")
        check.zero(3, "a", "the wrist axes 4, 5 and 6 must meet")
        check.zero(4, "a", "the wrist axes 4, 5 and 6 must meet")
        check.zero(4, "d", "the wrist axes 4, 5 and 6 must meet")
        alpha4 = check.skew(3, "wrist axes 4 and 5 must not be parallel")
        alpha5 = check.skew(4, "wrist axes 5 and 6 must not be parallel")
        a, alpha, d = check.a, check.alpha, check.d
        if math.hypot(a[2], math.sin(alpha[2]) * d[3]) <= LENGTH_TOL:
            raise check.fail(
                f"{check.where(2, 'a')} and {check.where(3, 'd')}: the wrist centre is on axis 3 "
                "(zero forearm), expected a forearm of non-zero length"
            )
        if abs(a[1]) <= LENGTH_TOL and abs(math.sin(alpha[1])) <= ANGLE_TOL:
            raise check.fail(
                f"{check.where(1, 'a')} = 0 m and {check.where(1, 'alpha')} = "
                f"{math.degrees(alpha[1]):.6g} deg: axes 2 and 3 are one line, expected them to "
                "meet at an angle, be parallel at a distance, or be skew"
            )
        alpha1 = float(alpha[0])
        if abs(math.sin(alpha1)) <= ANGLE_TOL:
            check.nonzero(0, "a", "axes 1 and 2 are parallel: they must be apart")
            check.skew(1, "axes 1 and 2 are parallel: axis 3 must not be parallel to them")
            family = "parallel"
            alpha1 = check.twist(0, (0.0, math.pi, -math.pi), "")
        elif abs(a[0]) <= LENGTH_TOL:
            family = "intersecting"
            if math.hypot(a[1], math.sin(alpha[1]) * d[1]) <= LENGTH_TOL:
                raise check.fail(
                    f"{check.where(0, 'a')} = 0 m, {check.where(1, 'a')} = 0 m and "
                    f"{check.where(1, 'd')} = {d[1]:g} m: axes 1, 2 and 3 meet in one point "
                    "(a spherical shoulder), expected axis 3 away from where axes 1 and 2 meet"
                )
        else:
            family = "general"
        return cls(
            robot=table.name,
            family=family,
            a1=0.0 if family == "intersecting" else float(a[0]),
            d1=float(d[0]),
            alpha1=alpha1,
            a2=float(a[1]),
            alpha2=float(alpha[1]),
            d2=float(d[1]),
            a3=float(a[2]),
            alpha3=float(alpha[2]),
            d3=float(d[2]),
            d4=float(d[3]),
            alpha4=float(alpha4),
            alpha5=float(alpha5),
            d6=float(d[5]),
            offsets=tuple(float(v) for v in check.theta),
            T_base=check.T_base,
            T_tool=check.T_tool,
        )

    # -----------------------------------------------------------------------------------------
    # One target

    def solve(
        self, position: npt.ArrayLike, rotation: npt.ArrayLike | None, free: float = 0.0
    ) -> np.ndarray:
        """The 8 branches reaching a tool pose.

        Args:
            position: Tool position in the world frame [m], (3,).
            rotation: Tool rotation ``R_world_tool``, (3, 3).
            free: Value of ``q4`` [rad] where the wrist is singular (axes 4 and 6 aligned).

        Returns:
            Joint vectors [rad] in (-pi, pi], (8, 6), one row per :attr:`branch_labels`; a row of
            NaN where that branch does not reach the target. Not verified, not wrapped into limits.
        """
        if rotation is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs a full pose")
        p, r = self._frame.scalar(position, rotation)  # type: ignore[arg-type]
        d6 = self.d6
        arms = self._arms(p[0] - d6 * r[0][2], p[1] - d6 * r[1][2], p[2] - d6 * r[2][2])
        out: list[tuple[float, ...]] = [NAN_ROW] * 8
        for index, arm in enumerate(arms):
            if arm is not None:
                out[2 * index], out[2 * index + 1] = self._wrist_scalar(arm, r, free)
        return np.array(out)

    def _arms(self, wx: float, wy: float, wz: float) -> list[tuple[float, float, float] | None]:
        """``(t1, t2, t3)`` [rad] of the four arm slots reaching the wrist centre ``W`` [m]."""
        a1, d1, sa1, ca1, g0, _, _ = self._k
        (g10, g1c, g1s), (g20, g2c, g2s), (g30, g3c, g3s) = self._g
        z = wz - d1
        rho2 = wx * wx + wy * wy
        big_r = rho2 + z * z
        heading = math.atan2(wy, wx)
        out: list[tuple[float, float, float] | None] = [None] * 4
        if self.family == "general":
            roots = self._general_t3(big_r - a1 * a1, z)
        else:
            size, psi = self._e
            if self.family == "intersecting":
                cos3 = (big_r - g0) / size
            else:
                cos3 = (ca1 * z - g30) / size
            if (clipped := clip_unit(cos3)) is None:
                return out
            cos3 = clipped
            delta = math.acos(cos3)
            roots = [psi - delta, psi + delta]
        for elbow, t3 in enumerate(roots):
            c3, s3 = math.cos(t3), math.sin(t3)
            g1 = g10 + g1c * c3 + g1s * s3
            g2 = g20 + g2c * c3 + g2s * s3
            g3 = g30 + g3c * c3 + g3s * s3
            if self.family == "general":
                u = (big_r - a1 * a1 - (g1 * g1 + g2 * g2 + g3 * g3)) / (2.0 * a1)
                w = (z - ca1 * g3) / sa1
                t2 = math.atan2(g1 * w - g2 * u, g1 * u + g2 * w)
                c2, s2 = math.cos(t2), math.sin(t2)
                h1, h2 = c2 * g1 - s2 * g2, s2 * g1 + c2 * g2
                t1 = heading - math.atan2(ca1 * h2 - sa1 * g3, a1 + h1)
                out[elbow] = (t1, t2, t3)
                continue
            pairs = []
            if self.family == "intersecting":
                h2 = (z - ca1 * g3) / sa1
                b = ca1 * h2 - sa1 * g3
                a_sq = rho2 - b * b
                if a_sq < 0.0:
                    if a_sq < -SLACK * (rho2 + b * b + 1.0):
                        continue
                    a_sq = 0.0
                radius = math.sqrt(a_sq)
                pairs = [(radius - a1, h2), (-radius - a1, h2)]
            else:
                h1 = (big_r - a1 * a1 - (g1 * g1 + g2 * g2 + g3 * g3)) / (2.0 * a1)
                p_sq = g1 * g1 + g2 * g2
                h2_sq = p_sq - h1 * h1
                if h2_sq < 0.0:
                    if h2_sq < -SLACK * (p_sq + h1 * h1 + 1.0):
                        continue
                    h2_sq = 0.0
                h2 = math.copysign(math.sqrt(h2_sq), a1 * ca1)
                pairs = [(h1, h2), (h1, -h2)]
            for side, (h1, h2) in enumerate(pairs):
                t2 = math.atan2(h2, h1) - math.atan2(g2, g1)
                t1 = heading - math.atan2(ca1 * h2 - sa1 * g3, a1 + h1)
                out[2 * side + elbow] = (t1, t2, t3)
        return out

    def _wrist_scalar(
        self, arm: tuple[float, float, float], r: list[list[float]], free: float
    ) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The rows (no flip, flip) of one arm solution: ``q`` [rad] wrapped, NaN if unreached."""
        t1, t2, t3 = arm
        s1, c1, s2, c2, s3, c3, s4, c4, s5, c5 = self._wrist
        o1, o2, o3, o4, o5, o6 = self.offsets
        # N = R_0_3^T R_0_6, columns 0 (v) and 2 (n): Rx(a3)^T Rz(t3)^T ... Rx(a1)^T Rz(t1)^T
        v = (r[0][0], r[1][0], r[2][0])
        n = (r[0][2], r[1][2], r[2][2])
        for angle, sa, ca in ((t1, s1, c1), (t2, s2, c2), (t3, s3, c3)):
            ct, st = math.cos(angle), math.sin(angle)
            vx, vy = ct * v[0] + st * v[1], -st * v[0] + ct * v[1]
            nx, ny = ct * n[0] + st * n[1], -st * n[0] + ct * n[1]
            v = (vx, ca * vy + sa * v[2], -sa * vy + ca * v[2])
            n = (nx, ca * ny + sa * n[2], -sa * ny + ca * n[2])
        vx, vy, vz = v
        wvx, wvy, mz = n
        cos5 = (c4 * c5 - mz) / (s4 * s5)
        if self._classic:
            sin5 = math.hypot(wvx, wvy)
        else:
            if (clipped := clip_unit(cos5)) is None:
                return NAN_ROW, NAN_ROW
            cos5 = clipped
            sin5 = math.sqrt(max(0.0, 1.0 - cos5 * cos5))
        q123 = (wrap(t1 - o1), wrap(t2 - o2), wrap(t3 - o3))
        rows = []
        for st5 in (sin5, -sin5):
            t5 = math.atan2(st5, cos5)
            mx = s5 * st5
            my = -(c4 * s5 * cos5 + s4 * c5)
            if math.hypot(mx, my) <= SINGULAR:
                t4 = free + o4
            else:
                t4 = math.atan2(wvy, wvx) - math.atan2(my, mx)
            ct4, st4 = math.cos(t4), math.sin(t4)
            ex, ey = ct4 * vx + st4 * vy, -st4 * vx + ct4 * vy
            ey, ez = c4 * ey + s4 * vz, -s4 * ey + c4 * vz
            ct5 = math.cos(t5)
            fx, fy = ct5 * ex + st5 * ey, -st5 * ex + ct5 * ey
            fy = c5 * fy + s5 * ez
            t6 = math.atan2(fy, fx)
            rows.append((*q123, wrap(t4 - o4), wrap(t5 - o5), wrap(t6 - o6)))
        return rows[0], rows[1]

    # -----------------------------------------------------------------------------------------
    # N targets
