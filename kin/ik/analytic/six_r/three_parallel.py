"""Closed-form IK of a 6R arm with three parallel axes 2-4 and any joints 1, 5, 6 (IK-Geo).

Structure, read from the table brought to the standard chain (:mod:`._six_r`, either convention):

- joint 1: any twist with ``sin alpha1 != 0`` (else four parallel axes), any ``a1, d1``;
- joints 2, 3, 4: parallel axes (``alpha2 = alpha3 = 0``), ``a2 != 0``, ``a3 != 0``; ``d2, d3,
  d4`` and ``a4`` free;
- joint 5 not parallel to them and joint 6 not parallel to joint 5 (``sin alpha4 != 0``,
  ``sin alpha5 != 0``); ``a5``, ``d5``, ``d6``, ``a6`` and ``alpha6`` free. Two families:

  * ``intersecting``: ``a5 = 0``, axes 5 and 6 meet (the UR arms, :mod:`.ur_wrist`): quadratics;
  * ``general``: ``a5 != 0``: a quartic (IK-Geo solves it with its subproblem 6); refused when
    ``0 < |a5| < NEAR_MEET (|a2| + |a3|)`` (:data:`NEAR_MEET`: nearly meeting axes 5 and 6
    make the quartic's roots pair up too closely; such tables go to the numeric solver).

Solution (``t_i`` DH angles, ``q_i = t_i - theta_i`` [rad], lengths [m]; ``s``/``c`` of a twist
written ``sa_i``/``ca_i``). Frame 1 has the axes ``x1 = (c1, s1, 0)``, ``y1 = (-ca1 s1, ca1 c1,
sa1)``, ``z1 = (sa1 s1, -sa1 c1, ca1)`` and the origin ``o1 = (a1 c1, a1 s1, d1)``; joints 2-4
turn about ``z1``, so with ``phi = t2 + t3 + t4``, ``R_1_6 = Rz(phi) Rx(alpha4) Rz(t5) Rx(alpha5)
Rz(t6)`` and the origin of frame 5, ``W = p_0_6 - d6 z6``, is

    ``W - o1 = P(t2, t3) + Rz(phi) (a4 + a5 c5, ca4 a5 s5 - sa4 d5, 0) + (h + sa4 a5 s5) z1``

with ``h = d2 + d3 + d4 + ca4 d5`` and ``P`` the planar 2R (``a2`` at angle ``t2``, ``a3`` at
``t2 + t3`` in the plane of ``x1, y1``).

1. The components along ``z1`` involve ``t1`` and ``t5`` only (``z1 . o1 = ca1 d1``; ``z6 = (nx,
   ny, nz)``):

   ``A(t1) = sa1 (Wx s1 - Wy c1) + ca1 (Wz - d1) - h = sa4 a5 sin t5`` and
   ``B(t1) = sa1 (nx s1 - ny c1) + ca1 nz - ca4 ca5 = -sa4 sa5 cos t5``.

   - intersecting (``a5 = 0``): ``A(t1) = 0`` is ``sin(beta - t1) = (ca1 (Wz - d1) - h) / (sa1
     rho)`` (``rho, beta`` the polar coordinates of ``W`` in the base plane): two ``t1``
     (shoulder left: ``beta - asin``, right: ``beta - pi + asin``); ``B`` gives ``cos t5`` and two
     signs of ``sin t5`` (wrist up: ``sin t5 >= 0``, down: ``< 0``; with both wrist twists at
     +-90 deg ``|sin t5|`` is read as in :mod:`.ur_wrist`, without cancellation);
   - general: ``u = A / (sa4 a5)`` and ``v = -B / (sa4 sa5)`` are ``(sin t5, cos t5)``, so
     ``E(t1) = u^2 + v^2 - 1 = 0``. ``u``, ``v`` are affine in ``(c1, s1)``, so ``E`` is a
     trigonometric polynomial of degree 2: a quartic in ``x = tan((t1 - tau) / 2)``, solved as
     in :mod:`.pieper`: the shift ``tau`` (a multiple of 45 deg) makes the leading coefficient
     ``E(tau + pi)`` the largest of eight, the real eigenvalues of the companion matrix are
     polished by Newton steps on ``E`` itself and kept when ``|E|`` is below the bound of
     :data:`REACH_TOL`; they are ordered by ``q1`` (``arm 1 .. 4``) and ``t5 = atan2(u, v)``.
2. ``z1`` seen in frame 6 is ``(x6, y6, w) = Rz(-t6) Rx(-alpha5) Rz(-t5) (0, sa4, ca4)``: ``t6``
   turns ``(sa4 s5, ca5 sa4 c5 + sa5 ca4)`` onto ``(x6, y6)``; when ``(x6, y6) = 0`` axis 6 is
   parallel to axes 2-4 and ``q6`` is free: it takes the value ``free``.
3. ``phi`` from the first column of ``Rz(phi) = R_1_6 (Rx(alpha4) Rz(t5) Rx(alpha5) Rz(t6))^T``;
   the 2R ``(a2, a3)`` reaches ``(W - o1) - Rz(phi) (a4 + a5 c5, ca4 a5 s5 - sa4 d5)`` in the
   plane of ``x1, y1`` by the law of cosines (elbow up: ``sin t3 >= 0``, down: ``< 0``); then
   ``t2``, and ``t4 = phi - t2 - t3``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ...exceptions import TargetError
from ...target import PoseTarget
from ._six_r import (
    LENGTH_TOL,
    NAN_ROW,
    SINGULAR,
    SixRChecker,
    TargetFrame,
    clip_unit,
    sin_cos,
    wrap,
)
from ._trig_quartic import (
    EPS,
    candidates,
    polish,
)
from .three_parallel_batch import ThreeParallelBatch, harmonics

#: A general-family root is kept when, after polishing, ``|E(t1)| max(|sa4 a5| [m], |sa4 sa5|)
#: <= 2 REACH_TOL`` (plus the rounding of ``E``): ``(sin t5, cos t5)`` then meets ``A`` within
#: about ``REACH_TOL`` [m] and ``B`` within about ``REACH_TOL`` [-].
REACH_TOL = 1e-10
#: ``|a5|`` below ``NEAR_MEET (|a2| + |a3|)`` (but not 0) is refused: axes 5 and 6 nearly meet,
#: the roots of ``E`` come in pairs about ``|a5|`` apart that the companion matrix and Newton
#: steps no longer resolve (q is then missed on more than 0.1 % of targets).
NEAR_MEET = 1e-3
_ARM_LABELS = {
    "intersecting": tuple(
        f"shoulder {s}, wrist {w}" for s in ("left", "right") for w in ("up", "down")
    ),
    "general": tuple(f"arm {k} (q1 ascending)" for k in range(1, 5)),
}


@dataclass(frozen=True)
class ThreeParallel6R(ThreeParallelBatch):
    """A 6R arm with axes 2, 3, 4 parallel: parameters in SI, and its closed form (8 branches).

    Attributes:
        robot: Robot name.
        family: ``"intersecting"`` (``a5 = 0``) or ``"general"`` (see the module).
        alpha1: Twist between axis 1 and the parallel axes 2-4 [rad].
        a1: Radial offset of axis 2 [m].
        d1: Height of axis 2 along axis 1 [m].
        a2: Upper-arm length [m].
        a3: Forearm length [m].
        lateral: ``h = d2 + d3 + d4 + cos(alpha4) d5``, offset of frame 5 along the parallel
            axes from frame 1 at ``t5 = 0`` [m].
        a4: Offset of axis 5 from axis 4 along ``x4`` [m].
        alpha4: Twist between axis 4 and axis 5 [rad].
        d5: Distance along axis 5 from axis 4 to the normal of axes 5 and 6 [m].
        a5: Length of the common normal of axes 5 and 6 [m] (0 in the intersecting family).
        alpha5: Twist between axis 5 and axis 6 [rad].
        d6: Distance along axis 6 from frame 5 to standard frame 6 [m].
        offsets: Joint offsets ``theta1 .. theta6`` [rad] (DH angle = q + offset).
        T_base: World -> standard DH frame 0 (4x4) [m].
        T_tool: Standard frame 6 (``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
    """

    name: ClassVar[str] = "three_parallel"
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)

    robot: str
    family: str
    alpha1: float
    a1: float
    d1: float
    a2: float
    a3: float
    lateral: float
    a4: float
    alpha4: float
    d5: float
    a5: float
    alpha5: float
    d6: float
    offsets: tuple[float, ...]
    T_base: np.ndarray = field(repr=False)
    T_tool: np.ndarray = field(repr=False)
    _frame: TargetFrame = field(init=False, repr=False, compare=False)
    _k: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _classic: bool = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_frame", TargetFrame(self.T_base, self.T_tool))
        s1, c1 = sin_cos(self.alpha1)
        s4, c4 = sin_cos(self.alpha4)
        s5, c5 = sin_cos(self.alpha5)
        object.__setattr__(self, "_k", (s1, c1, s4, c4, s5, c5))
        # Both wrist twists +-90 deg: |sin t5| is then read without cancellation.
        object.__setattr__(self, "_classic", c4 == 0.0 and c5 == 0.0)

    @property
    def branch_labels(self) -> tuple[str, ...]:
        """The meaning of the 8 rows of :meth:`solve`: the family's ``(t1, t5)`` slot, the elbow."""
        return tuple(
            f"{arm}, elbow {e}" for arm in _ARM_LABELS[self.family] for e in ("up", "down")
        )

    @classmethod
    def recognise(cls, table: DHTable) -> ThreeParallel6R:
        """The parameters of ``table``'s arm.

        Raises:
            StructureError: The table is not a 6R arm with three parallel axes 2-4 and finitely
                many solutions; the message names the row and the parameter that does not fit.
        """
        check = SixRChecker(table, "6R three parallel axes")
        alpha1 = check.skew(0, "axis 2 must not be parallel to axis 1")
        check.twist(1, (0.0,), "axes 2, 3 and 4 must be parallel")
        check.twist(2, (0.0,), "axes 2, 3 and 4 must be parallel")
        a2 = check.nonzero(1, "a", "the upper arm between axes 2 and 3")
        a3 = check.nonzero(2, "a", "the forearm between axes 3 and 4")
        alpha4 = check.skew(3, "axis 5 must not be parallel to axes 2-4")
        alpha5 = check.skew(4, "axis 6 must not be parallel to axis 5")
        a5 = float(check.a[4])
        family = "intersecting" if abs(a5) <= LENGTH_TOL else "general"
        least = NEAR_MEET * (abs(a2) + abs(a3))
        if family == "general" and abs(a5) < least:
            raise check.fail(
                f"{check.where(4, 'a')} = {a5:g} m, expected 0 or at least {least:g} m "
                f"({NEAR_MEET:g} of |a2| + |a3|: axes 5 and 6 nearly meet, and the quartic's "
                "roots come in pairs too close to separate)"
            )
        d = check.d
        return cls(
            robot=table.name,
            family=family,
            alpha1=float(alpha1),
            a1=float(check.a[0]),
            d1=float(d[0]),
            a2=a2,
            a3=a3,
            lateral=float(d[1] + d[2] + d[3] + sin_cos(alpha4)[1] * d[4]),
            a4=float(check.a[3]),
            alpha4=float(alpha4),
            d5=float(d[4]),
            a5=0.0 if family == "intersecting" else a5,
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
            free: Value of ``q6`` [rad] where the wrist is singular (axis 6 parallel to 2-4).

        Returns:
            Joint vectors [rad] in (-pi, pi], (8, 6), one row per :attr:`branch_labels`; a row of
            NaN where that branch does not reach the target. Not verified, not wrapped into limits.
        """
        if rotation is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs a full pose")
        p, r = self._frame.scalar(position, rotation)  # type: ignore[arg-type]
        d6 = self.d6
        n = (r[0][2], r[1][2], r[2][2])
        w = (p[0] - d6 * n[0], p[1] - d6 * n[1], p[2] - d6 * n[2])
        if self.family == "general":
            slots = self._general_slots(w, n)
        else:
            slots = self._intersecting_slots(w, n)
        out: list[tuple[float, ...]] = [NAN_ROW] * 8
        for index, slot in enumerate(slots):
            if slot is not None:
                out[2 * index], out[2 * index + 1] = self._arm_scalar(slot, w, r, free)
        return np.array(out)

    def _intersecting_slots(
        self, w: tuple[float, float, float], n: tuple[float, float, float]
    ) -> list[tuple[float, float, float] | None]:
        """``(t1, cos t5, sin t5)`` of the four slots (shoulder, wrist) when ``a5 = 0``."""
        s1, c1, s4, c4, s5, c5 = self._k
        out: list[tuple[float, float, float] | None] = [None] * 4
        rho = math.hypot(w[0], w[1])
        if rho == 0.0:
            return out
        k = (c1 * (w[2] - self.d1) - self.lateral) / (s1 * rho)
        if (clipped := clip_unit(k)) is None:
            return out
        k = clipped
        beta = math.atan2(w[1], w[0])
        asin_k = math.asin(k)
        for shoulder in (0, 1):
            t1 = beta - asin_k if shoulder == 0 else beta - math.pi + asin_k
            ct, st = math.cos(t1), math.sin(t1)
            z1 = (s1 * st, -s1 * ct, c1)
            cos5 = (c4 * c5 - (n[0] * z1[0] + n[1] * z1[1] + n[2] * z1[2])) / (s4 * s5)
            if self._classic:  # |sin t5| = |(x6, y6)|: the part of z1 across z6
                cross = (n[1] * z1[2] - n[2] * z1[1], n[2] * z1[0] - n[0] * z1[2],
                         n[0] * z1[1] - n[1] * z1[0])  # fmt: skip
                sin5 = math.hypot(*cross)
            else:
                if (clipped := clip_unit(cos5)) is None:
                    continue
                cos5 = clipped
                sin5 = math.sqrt(1.0 - cos5 * cos5)
            out[2 * shoulder] = (t1, cos5, sin5)
            out[2 * shoulder + 1] = (t1, cos5, -sin5)
        return out

    def _general_slots(
        self, w: tuple[float, float, float], n: tuple[float, float, float]
    ) -> list[tuple[float, float, float] | None]:
        """``(t1, cos t5, sin t5)`` of the real roots of ``E(t1)``, in ascending ``q1``."""
        uv = self._uv(*w, *n)
        out: list[tuple[float, float, float] | None] = [None] * 4
        roots = []
        for start in candidates(*harmonics(uv)):
            root = self._polish(start, uv)
            if root is not None:
                roots.append(root)
        o1 = self.offsets[0]
        roots.sort(key=lambda root: wrap(root[0] - o1))
        for index, root in enumerate(roots):
            out[index] = root
        return out

    def _uv(self, wx: Any, wy: Any, wz: Any, nx: Any, ny: Any, nz: Any) -> tuple[Any, ...]:
        """``u = u0 + uc c1 + us s1``, ``v = v0 + vc c1 + vs s1`` and their rounding scales.

        Floats or arrays: ``(u0, uc, us, v0, vc, vs, su, sv)``, ``su``, ``sv`` the sums of the
        magnitudes that make up ``u``, ``v`` [-].
        """
        s1, c1, s4, c4, s5, c5 = self._k
        ka, kb = s4 * self.a5, s4 * s5
        u0 = (c1 * (wz - self.d1) - self.lateral) / ka
        v0 = (c4 * c5 - c1 * nz) / kb
        su = abs(s1) * (abs(wx) + abs(wy)) + abs(c1) * (abs(wz) + abs(self.d1)) + abs(self.lateral)
        sv = abs(s1) * (abs(nx) + abs(ny)) + abs(c1 * nz) + abs(c4 * c5)
        return (u0, -s1 * wy / ka, s1 * wx / ka, v0, s1 * ny / kb, -s1 * nx / kb,
                su / abs(ka), sv / abs(kb))  # fmt: skip

    def _residual(
        self, t1: Any, uv: tuple[Any, ...], cos: Any, sin: Any
    ) -> tuple[Any, Any, Any, Any, Any]:
        """``E(t1)`` [-], ``dE/dt1`` [-], the bound on ``|E|`` of a kept root, ``u`` and ``v``.

        Floats with ``math.cos``, ``math.sin`` or arrays with ``np.cos``, ``np.sin``.
        """
        u0, uc, us, v0, vc, vs, su, sv = uv
        c, s = cos(t1), sin(t1)
        u = u0 + uc * c + us * s
        v = v0 + vc * c + vs * s
        e = u * u + v * v - 1.0
        de = 2.0 * (u * (us * c - uc * s) + v * (vs * c - vc * s))
        _, _, s4, _, s5, _ = self._k
        reach = 2.0 * REACH_TOL / max(abs(s4 * self.a5), abs(s4 * s5))
        bound = reach + 16.0 * EPS * (abs(u) * su + abs(v) * sv + 1.0)
        return e, de, bound, u, v

    def _polish(self, t1: float, uv: tuple[float, ...]) -> tuple[float, float, float] | None:
        """Newton steps on ``E(t1)``: ``(t1, cos t5, sin t5)``; None if ``|E|`` stays too large."""
        root = polish(lambda t: self._residual(t, uv, math.cos, math.sin), t1)
        if root is None:
            return None
        t1, (u, v) = root
        size = math.hypot(u, v)
        return t1, v / size, u / size

    def _arm_scalar(
        self,
        slot: tuple[float, float, float],
        w: tuple[float, float, float],
        r: list[list[float]],
        free: float,
    ) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The rows (elbow up, down) of a slot ``(t1, cos t5, sin t5)``: ``q`` [rad], NaN: none."""
        t1, cos5, st5 = slot
        s1, c1, s4, c4, s5a, c5a = self._k
        a2, a3, a5 = self.a2, self.a3, self.a5
        o1, o2, o3, o4, o5, o6 = self.offsets
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = r
        ct, st = math.cos(t1), math.sin(t1)
        y1 = (-c1 * st, c1 * ct, s1)
        z1 = (s1 * st, -s1 * ct, c1)
        # 2. z1 in frame 6 (x6, y6), turned onto (vx, vy) by t6
        x6 = r00 * z1[0] + r10 * z1[1] + r20 * z1[2]
        y6 = r01 * z1[0] + r11 * z1[1] + r21 * z1[2]
        t5 = math.atan2(st5, cos5)
        if math.hypot(x6, y6) <= SINGULAR:
            t6 = free + o6
        else:
            vx, vy = s4 * st5, c5a * s4 * cos5 + s5a * c4
            t6 = math.atan2(vy, vx) - math.atan2(y6, x6)
        # 3. phi from the first row of Rx(alpha4) Rz(t5) Rx(alpha5) Rz(t6)
        ct6, st6 = math.cos(t6), math.sin(t6)
        xi0 = cos5 * ct6 - st5 * c5a * st6
        xi1 = -cos5 * st6 - st5 * c5a * ct6
        xi2 = s5a * st5
        rx = r00 * xi0 + r01 * xi1 + r02 * xi2
        ry = r10 * xi0 + r11 * xi1 + r12 * xi2
        rz = r20 * xi0 + r21 * xi1 + r22 * xi2
        phi = math.atan2(y1[0] * rx + y1[1] * ry + y1[2] * rz, ct * rx + st * ry)
        cp, sp = math.cos(phi), math.sin(phi)
        # W - o1 in the arm plane, less the wrist offset turned by phi
        qx, qy, qz = w[0] - self.a1 * ct, w[1] - self.a1 * st, w[2] - self.d1
        ex, ey = self.a4 + a5 * cos5, c4 * a5 * st5 - s4 * self.d5
        bx = ct * qx + st * qy - (cp * ex - sp * ey)
        by = y1[0] * qx + y1[1] * qy + y1[2] * qz - (sp * ex + cp * ey)
        cos3 = (bx * bx + by * by - (a2 * a2 + a3 * a3)) / (2.0 * a2 * a3)
        if (clipped := clip_unit(cos3)) is None:
            return NAN_ROW, NAN_ROW
        cos3 = clipped
        sin3 = math.sqrt(1.0 - cos3 * cos3)
        heading = math.atan2(by, bx)
        rows = []
        for st3 in (sin3, -sin3):
            t3 = math.atan2(st3, cos3)
            t2 = heading - math.atan2(a3 * st3, a2 + a3 * cos3)
            t4 = phi - t2 - t3
            rows.append(
                (
                    wrap(t1 - o1),
                    wrap(t2 - o2),
                    wrap(t3 - o3),
                    wrap(t4 - o4),
                    wrap(t5 - o5),
                    wrap(t6 - o6),
                )  # fmt: skip
            )
        return rows[0], rows[1]
