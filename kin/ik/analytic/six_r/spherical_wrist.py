"""Closed-form IK of a 6R arm with a spherical wrist (Pieper's case: PUMA 560 and most industrial arms).

Structure, read from the table brought to the standard chain (:mod:`._six_r`, either convention):

- joint 1: any twist ``alpha1`` with ``sin alpha1 != 0`` (axis 2 not parallel to axis 1), any
  ``a1, d1`` (radial offset, shoulder height);
- joints 2, 3: parallel axes (``alpha2 = 0``), ``a2 != 0``; ``d2, d3`` (shoulder offset), ``a3``,
  ``alpha3`` and ``d4`` free, with ``(a3, -sin(alpha3) d4) != 0`` (the forearm);
- joints 4, 5, 6: axes meeting in the wrist centre ``W = o4`` (``a4 = a5 = d5 = 0``) and not
  parallel (``sin alpha4 != 0``, ``sin alpha5 != 0``); ``d6``, ``a6``, ``alpha6`` free.

Solution (``t_i`` DH angles, ``q_i = t_i - theta_i`` joint values [rad], lengths [m]):

1. ``W = p_0_6 - d6 z_6`` (frame 6 is standard frame 6, the tool folded out).
2. In frame 1 the wrist centre is ``(x1, y1, h)``, ``h = d2 + d3 + cos(alpha3) d4``, and frame 0
   sees ``Rz(t1) (a1 + x1, c1 y1 - s1 h, d1 + s1 y1 + c1 h)``: the height gives ``y1``, the
   horizontal radius ``a1 + x1 = +-sqrt(Wx^2 + Wy^2 - (c1 y1 - s1 h)^2)`` (shoulder right / left),
   the heading ``t1``.
3. ``(x1, y1) = Rz(t2) ((a2, 0) + Rz(t3) (a3, -sin(alpha3) d4))``: law of cosines for ``t3`` (elbow
   up: the ``-acos`` root, down: ``+acos``), then ``t2``.
4. ``N = R_0_3^T R_0_6 = Rz(t4) Rx(alpha4) Rz(t5) Rx(alpha5) Rz(t6)``: its third column gives
   ``cos t5`` and the two signs of ``sin t5`` (wrist no flip: ``sin t5 >= 0``, flip: ``< 0``), then
   ``t4``; its first column gives ``t6``. When axes 4 and 6 line up (``sin t5 = 0`` for a 90-deg
   wrist), ``q4`` is free: it takes the value ``free`` and ``t6`` the rest.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import ModuleType
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable
from kin._native import twin

from ...exceptions import TargetError
from ...target import PoseTarget
from ._six_r import (
    NAN_ROW,
    SINGULAR,
    SLACK,
    SixRChecker,
    TargetFrame,
    clip_cosines,
    clip_unit,
    in_blocks,
    wrap,
    wrap_array,
)
from .six_r_twin import CompiledSixR, twin_solve


def _labels() -> tuple[str, ...]:
    return tuple(
        f"shoulder {s}, elbow {e}, wrist {w}"
        for s in ("right", "left")
        for e in ("up", "down")
        for w in ("no flip", "flip")
    )


@dataclass(frozen=True)
class SphericalWrist6R(CompiledSixR):
    """A 6R arm with a spherical wrist: parameters in SI, and its closed form (8 branches).

    Attributes:
        name: Robot name.
        a1: Radial offset of axis 2 from axis 1 [m].
        d1: Height of axis 2 along axis 1 [m].
        alpha1: Twist between axes 1 and 2 [rad].
        a2: Upper-arm length (between the parallel axes 2 and 3) [m].
        alpha3: Twist between axes 3 and 4 [rad].
        lateral: Offset of the wrist centre along axis 2 in frame 1: ``d2 + d3 + cos(alpha3) d4``
            [m].
        forearm: In-plane vector from axis 3 to the wrist centre, ``(a3, -sin(alpha3) d4)`` [m].
        alpha4: Twist between axes 4 and 5 [rad].
        alpha5: Twist between axes 5 and 6 [rad].
        d6: Distance from the wrist centre to standard frame 6 along axis 6 [m].
        offsets: Joint offsets ``theta1 .. theta6`` [rad] (DH angle = q + offset).
        T_base: World -> standard DH frame 0 (4x4) [m].
        T_tool: Standard frame 6 (``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
    """

    name: ClassVar[str] = "spherical_wrist"
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    branch_labels: ClassVar[tuple[str, ...]] = _labels()
    #: The compiled twin (``kin/_native/_spherical_wrist.c``), or None when it is not built.
    compiled_twin: ClassVar[ModuleType | None] = twin("_spherical_wrist")

    robot: str
    a1: float
    d1: float
    alpha1: float
    a2: float
    alpha3: float
    lateral: float
    forearm: tuple[float, float]
    alpha4: float
    alpha5: float
    d6: float
    offsets: tuple[float, ...]
    T_base: np.ndarray = field(repr=False)
    T_tool: np.ndarray = field(repr=False)
    _frame: TargetFrame = field(init=False, repr=False, compare=False)
    _k: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _c_params: np.ndarray | None = field(init=False, repr=False, compare=False)
    _classic: bool = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_frame", TargetFrame(self.T_base, self.T_tool))
        lx, ly = self.forearm
        k: tuple[float, ...] = ()
        for angle in (self.alpha1, self.alpha3, self.alpha4, self.alpha5):
            k += (math.sin(angle), math.cos(angle))
        k += (lx, ly, math.hypot(lx, ly), math.atan2(ly, lx))
        object.__setattr__(self, "_k", k)
        # Both wrist twists +-90 deg: |sin t5| is then read without cancellation.
        object.__setattr__(self, "_classic", abs(k[5]) < 1e-15 and abs(k[7]) < 1e-15)
        self._pack_twin()

    def _c_own(self) -> dict[str, tuple[float, ...]]:
        return {
            "k": self._k,
            "classic": (float(self._classic),),
            "len": (self.a1, self.d1, self.a2, self.lateral, self.d6),
            "off": self.offsets,
        }

    @classmethod
    def recognise(cls, table: DHTable) -> SphericalWrist6R:
        """The parameters of ``table``'s arm.

        Raises:
            StructureError: The table is not a 6R arm of this family; the message names the row
                and the parameter that does not fit.
        """
        check = SixRChecker(table, "6R spherical-wrist")
        alpha1 = check.skew(0, "axis 2 must not be parallel to axis 1")
        check.twist(1, (0.0,), "axes 2 and 3 must be parallel")
        a2 = check.nonzero(1, "a", "the upper arm between the parallel axes 2 and 3")
        check.zero(3, "a", "the wrist axes 4, 5 and 6 must meet")
        check.zero(4, "a", "the wrist axes 4, 5 and 6 must meet")
        check.zero(4, "d", "the wrist axes 4, 5 and 6 must meet")
        alpha4 = check.skew(3, "wrist axes 4 and 5 must not be parallel")
        alpha5 = check.skew(4, "wrist axes 5 and 6 must not be parallel")
        alpha3, a3, d4 = check.alpha[2], check.a[2], check.d[3]
        forearm = (float(a3), float(-math.sin(alpha3) * d4))
        if math.hypot(*forearm) <= 1e-12:
            raise check.fail(
                f"{check.where(2, 'a')} and {check.where(3, 'd')}: the wrist centre is on axis 3 "
                "(zero forearm), expected a forearm of non-zero length"
            )
        return cls(
            robot=table.name,
            a1=float(check.a[0]),
            d1=float(check.d[0]),
            alpha1=float(alpha1),
            a2=a2,
            alpha3=float(alpha3),
            lateral=float(check.d[1] + check.d[2] + math.cos(alpha3) * d4),
            forearm=forearm,
            alpha4=float(alpha4),
            alpha5=float(alpha5),
            d6=float(check.d[5]),
            offsets=tuple(float(v) for v in check.theta),
            T_base=check.T_base,
            T_tool=check.T_tool,
        )

    def solve(
        self,
        position: npt.ArrayLike,
        rotation: npt.ArrayLike | None,
        free: float = 0.0,
        *,
        compiled: bool = True,
    ) -> np.ndarray:
        """The 8 branches reaching a tool pose.

        Args:
            position: Tool position in the world frame [m], (3,).
            rotation: Tool rotation ``R_world_tool``, (3, 3).
            free: Value of ``q4`` [rad] where the wrist is singular (axes 4 and 6 aligned).
            compiled: Run the compiled twin when it is built (False: this module's Python).

        Returns:
            Joint vectors [rad] in (-pi, pi], (8, 6), one row per :attr:`branch_labels`; a row of
            NaN where that branch does not reach the target. Not verified, not wrapped into limits.
        """
        if rotation is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs a full pose")
        twin = self.compiled_twin
        if compiled and twin is not None:
            p1 = np.reshape(np.asarray(position, dtype=float), (1, 3))
            r1 = np.reshape(np.asarray(rotation, dtype=float), (1, 3, 3))
            return twin_solve(twin, self._c_params, p1, r1, free)[0]  # type: ignore[arg-type]
        p, r = self._frame.scalar(position, rotation)  # type: ignore[arg-type]
        s1, c1, sa3, ca3, s4, c4, s5, c5, lx, ly, l3, phi3 = self._k
        classic = self._classic
        a1, d1, a2, h, d6 = self.a1, self.d1, self.a2, self.lateral, self.d6
        o1, o2, o3, o4, o5, o6 = self.offsets
        out = [NAN_ROW] * 8
        # 1. wrist centre, 2. joint 1
        wx, wy, wz = p[0] - d6 * r[0][2], p[1] - d6 * r[1][2], p[2] - d6 * r[2][2]
        y1 = (wz - d1 - c1 * h) / s1
        b = c1 * y1 - s1 * h
        rho2 = wx * wx + wy * wy
        a_sq = rho2 - b * b
        if a_sq < 0.0:
            if a_sq < -SLACK * (rho2 + b * b + 1.0):
                return np.array(out)
            a_sq = 0.0
        radius = math.sqrt(a_sq)
        heading = math.atan2(wy, wx)
        u0 = (r[0][0], r[1][0], r[2][0])  # columns 0 and 2 of R_0_6
        n0 = (r[0][2], r[1][2], r[2][2])
        two_a2_l3 = 2.0 * a2 * l3
        base_sq = a2 * a2 + l3 * l3
        for shoulder in (0, 1):
            big_a = radius if shoulder == 0 else -radius
            t1 = heading - math.atan2(b, big_a)
            x1 = big_a - a1
            # 3. elbow
            cos3 = (x1 * x1 + y1 * y1 - base_sq) / two_a2_l3
            if (clipped := clip_unit(cos3)) is None:
                continue
            cos3 = clipped
            delta = math.acos(cos3)
            ct1, st1 = math.cos(t1), math.sin(t1)
            # Rx(alpha1)^T Rz(t1)^T applied to the two columns
            ux, uy = ct1 * u0[0] + st1 * u0[1], -st1 * u0[0] + ct1 * u0[1]
            ux, uy, uz = ux, c1 * uy + s1 * u0[2], -s1 * uy + c1 * u0[2]
            nx, ny = ct1 * n0[0] + st1 * n0[1], -st1 * n0[0] + ct1 * n0[1]
            nx, ny, nz = nx, c1 * ny + s1 * n0[2], -s1 * ny + c1 * n0[2]
            heading1 = math.atan2(y1, x1)
            for elbow in (0, 1):
                t3 = -phi3 - delta if elbow == 0 else -phi3 + delta
                ct3, st3 = math.cos(t3), math.sin(t3)
                t2 = heading1 - math.atan2(lx * st3 + ly * ct3, a2 + lx * ct3 - ly * st3)
                t23 = t2 + t3
                c23, s23 = math.cos(t23), math.sin(t23)
                # Rx(alpha3)^T Rz(t23)^T: the columns of N = R_0_3^T R_0_6
                vx, vy = c23 * ux + s23 * uy, -s23 * ux + c23 * uy
                wvx, wvy = c23 * nx + s23 * ny, -s23 * nx + c23 * ny
                vy, vz = ca3 * vy + sa3 * uz, -sa3 * vy + ca3 * uz
                mz = -sa3 * wvy + ca3 * nz
                wvy = ca3 * wvy + sa3 * nz
                # 4. wrist: third column (wvx, wvy, mz), first column (vx, vy, vz)
                cos5 = (c4 * c5 - mz) / (s4 * s5)
                if classic:
                    sin5 = math.hypot(wvx, wvy)
                else:
                    if (clipped := clip_unit(cos5)) is None:
                        continue
                    cos5 = clipped
                    sin5 = math.sqrt(max(0.0, 1.0 - cos5 * cos5))
                q123 = (wrap(t1 - o1), wrap(t2 - o2), wrap(t3 - o3))
                index = 4 * shoulder + 2 * elbow
                for flip in (0, 1):
                    st5 = sin5 if flip == 0 else -sin5
                    t5 = math.atan2(st5, cos5)
                    mx = s5 * st5
                    my = -(c4 * s5 * cos5 + s4 * c5)
                    if math.hypot(mx, my) <= SINGULAR:
                        t4 = free + o4
                    else:
                        t4 = math.atan2(wvy, wvx) - math.atan2(my, mx)
                    # t6: Rx(alpha5)^T Rz(t5)^T Rx(alpha4)^T Rz(t4)^T (first column of N)
                    ct4, st4 = math.cos(t4), math.sin(t4)
                    ex, ey = ct4 * vx + st4 * vy, -st4 * vx + ct4 * vy
                    ey, ez = c4 * ey + s4 * vz, -s4 * ey + c4 * vz
                    ct5 = math.cos(t5)
                    fx, fy = ct5 * ex + st5 * ey, -st5 * ex + ct5 * ey
                    fy = c5 * fy + s5 * ez
                    t6 = math.atan2(fy, fx)
                    out[index + flip] = (*q123, wrap(t4 - o4), wrap(t5 - o5), wrap(t6 - o6))
        return np.array(out)

    def solve_batch(
        self,
        positions: npt.ArrayLike,
        rotations: npt.ArrayLike | None,
        free: float = 0.0,
        *,
        compiled: bool = True,
    ) -> np.ndarray:
        """:meth:`solve` of N tool poses at once, in NumPy.

        Args:
            positions: Tool positions in the world frame [m], (N, 3).
            rotations: Tool rotations ``R_world_tool``, (N, 3, 3).
            free: Value of ``q4`` [rad] where the wrist is singular.
            compiled: Run the compiled twin when it is built (False: NumPy).

        Returns:
            Joint vectors [rad] in (-pi, pi], (N, 8, 6), NaN where a branch does not exist.
        """
        if rotations is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs full poses")
        twin = self.compiled_twin
        if compiled and twin is not None:
            return twin_solve(twin, self._c_params, positions, rotations, free)  # type: ignore[arg-type]
        return in_blocks(self._solve_block, positions, rotations, free)

    def _solve_block(self, positions: np.ndarray, rotations: np.ndarray, free: float) -> np.ndarray:
        p, r = self._frame.batch(positions, rotations)
        s1, c1, sa3, ca3, s4, c4, s5, c5, lx, ly, l3, phi3 = self._k
        a1, d1, a2, h, d6 = self.a1, self.d1, self.a2, self.lateral, self.d6
        o1, o2, o3, o4, o5, o6 = self.offsets
        out = np.full((p.shape[0], 8, 6), np.nan)
        with np.errstate(invalid="ignore"):
            wx, wy, wz = (p - d6 * r[:, :, 2]).T
            y1 = (wz - d1 - c1 * h) / s1
            b = c1 * y1 - s1 * h
            rho2 = wx * wx + wy * wy
            a_sq = rho2 - b * b
            a_sq = np.where((a_sq < 0.0) & (a_sq >= -SLACK * (rho2 + b * b + 1.0)), 0.0, a_sq)
            radius = np.sqrt(a_sq)  # NaN out of reach
            heading = np.arctan2(wy, wx)
            u0x, u0y, u0z = r[:, 0, 0], r[:, 1, 0], r[:, 2, 0]
            n0x, n0y, n0z = r[:, 0, 2], r[:, 1, 2], r[:, 2, 2]
            for shoulder in (0, 1):
                big_a = radius if shoulder == 0 else -radius
                t1 = heading - np.arctan2(b, big_a)
                x1 = big_a - a1
                cos3 = (x1 * x1 + y1 * y1 - (a2 * a2 + l3 * l3)) / (2.0 * a2 * l3)
                cos3 = clip_cosines(cos3)
                delta = np.arccos(cos3)
                ct1, st1 = np.cos(t1), np.sin(t1)
                ux, uy = ct1 * u0x + st1 * u0y, -st1 * u0x + ct1 * u0y
                uy, uz = c1 * uy + s1 * u0z, -s1 * uy + c1 * u0z
                nx, ny = ct1 * n0x + st1 * n0y, -st1 * n0x + ct1 * n0y
                ny, nz = c1 * ny + s1 * n0z, -s1 * ny + c1 * n0z
                heading1 = np.arctan2(y1, x1)
                for elbow in (0, 1):
                    t3 = -phi3 - delta if elbow == 0 else -phi3 + delta
                    ct3, st3 = np.cos(t3), np.sin(t3)
                    t2 = heading1 - np.arctan2(lx * st3 + ly * ct3, a2 + lx * ct3 - ly * st3)
                    t23 = t2 + t3
                    c23, s23 = np.cos(t23), np.sin(t23)
                    vx, vy = c23 * ux + s23 * uy, -s23 * ux + c23 * uy
                    wvx, wvy = c23 * nx + s23 * ny, -s23 * nx + c23 * ny
                    vy, vz = ca3 * vy + sa3 * uz, -sa3 * vy + ca3 * uz
                    mz = -sa3 * wvy + ca3 * nz
                    wvy = ca3 * wvy + sa3 * nz
                    cos5 = (c4 * c5 - mz) / (s4 * s5)
                    if self._classic:
                        sin5 = np.hypot(wvx, wvy)
                    else:
                        cos5 = clip_cosines(cos5)
                        sin5 = np.sqrt(np.maximum(0.0, 1.0 - cos5 * cos5))
                    index = 4 * shoulder + 2 * elbow
                    for flip in (0, 1):
                        st5 = sin5 if flip == 0 else -sin5
                        t5 = np.arctan2(st5, cos5)
                        mx = s5 * st5
                        my = -(c4 * s5 * cos5 + s4 * c5)
                        t4 = np.arctan2(wvy, wvx) - np.arctan2(my, mx)
                        t4 = np.where(np.hypot(mx, my) <= SINGULAR, free + o4, t4)
                        ct4, st4 = np.cos(t4), np.sin(t4)
                        ex, ey = ct4 * vx + st4 * vy, -st4 * vx + ct4 * vy
                        ey, ez = c4 * ey + s4 * vz, -s4 * ey + c4 * vz
                        ct5 = np.cos(t5)
                        fx, fy = ct5 * ex + st5 * ey, -st5 * ex + ct5 * ey
                        fy = c5 * fy + s5 * ez
                        t6 = np.arctan2(fy, fx)
                        q = np.stack((t1 - o1, t2 - o2, t3 - o3, t4 - o4, t5 - o5, t6 - o6), -1)
                        out[:, index + flip] = wrap_array(q)
        rows = np.isnan(out).any(axis=2)
        out[rows] = np.nan
        return out
