"""Closed-form IK of a 6R arm with three parallel axes and an offset wrist (Universal Robots family).

Structure, read from the table brought to the standard chain (:mod:`._six_r`, either convention):

- joint 1: any twist with ``sin alpha1 != 0`` (UR: 90 deg), any ``a1, d1``;
- joints 2, 3, 4: parallel axes (``alpha2 = alpha3 = 0``), ``a2 != 0``, ``a3 != 0``; ``d2, d3,
  d4`` free (their sum is the shoulder offset), ``a4`` free;
- joint 5 not parallel to them and joint 6 not parallel to joint 5 (``sin alpha4 != 0``,
  ``sin alpha5 != 0``), axes 5 and 6 meeting (``a5 = 0``); ``d5``, ``d6``, ``a6`` and ``alpha6``
  free. This is IK-Geo's "three parallel axes, two intersecting" family.

UR3, UR5, UR10 (and the e-series) are the case ``alpha = (90, 0, 0, 90, -90, 0) deg``,
``a = (0, a2, a3, 0, 0, 0)``, ``d = (d1, 0, 0, d4, d5, d6)``.

Solution (``t_i`` DH angles, ``q_i = t_i - theta_i`` [rad], lengths [m]); frame 1's ``z1`` is the
common direction of axes 2-4, and the origin of frame 5 lies at the offset
``h = d2 + d3 + d4 + cos(alpha4) d5`` along it (from frame 1):

1. ``p5 = p_0_6 - d6 z6`` (the origin of frame 5); ``(p5 - o1) . z1 = h`` is
   ``sin(beta - t1) = (cos(alpha1) (p5z - d1) - h) / (sin(alpha1) rho)`` with ``rho, beta`` the
   polar coordinates of ``p5`` in the base plane: two ``t1`` (shoulder left: ``beta - asin``,
   right: ``beta - pi + asin``).
2. ``z1`` seen in frame 6 is ``(x6, y6, w) = Rz(-t6) v`` with ``v = Rx(-alpha5) Rz(-t5) (0,
   sin alpha4, cos alpha4)``: ``w = cos(alpha4) cos(alpha5) - sin(alpha4) sin(alpha5) cos t5``
   gives ``cos t5`` and two signs of ``sin t5`` (wrist up: ``sin t5 >= 0``, down: ``< 0``; with
   both wrist twists at +-90 deg ``|sin t5| = hypot(x6, y6)``, read without cancellation), and
   ``t6`` turns ``(v_x, v_y)`` onto ``(x6, y6)``; when ``(x6, y6) = 0`` axis 6 is parallel to
   axes 2-4 and ``q6`` is free: it takes the value ``free``.
3. ``phi = t2 + t3 + t4`` from ``R_1_6 = Rz(phi) Rx(alpha4) Rz(t5) Rx(alpha5) Rz(t6)``; the point
   of axis 3 in the arm plane is ``p5 - Rz(phi) (a4, -sin(alpha4) d5)``, and the planar 2R
   ``(a2, a3)`` reaches it by the law of cosines (elbow up: ``sin t3 >= 0``, down: ``< 0``); then
   ``t2``, and ``t4 = phi - t2 - t3``.
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
    SixRChecker,
    TargetFrame,
    clip_cosines,
    clip_unit,
    in_blocks,
    sin_cos,
    wrap,
    wrap_array,
)
from .six_r_twin import CompiledSixR, twin_solve


def _labels() -> tuple[str, ...]:
    return tuple(
        f"shoulder {s}, wrist {w}, elbow {e}"
        for s in ("left", "right")
        for w in ("up", "down")
        for e in ("up", "down")
    )


@dataclass(frozen=True)
class URWrist6R(CompiledSixR):
    """A 6R arm of the UR family: parameters in SI, and its closed form (8 branches).

    Attributes:
        robot: Robot name.
        alpha1: Twist between axis 1 and the parallel axes 2-4 [rad].
        a1: Radial offset of axis 2 [m].
        d1: Height of axis 2 along axis 1 [m].
        a2: Upper-arm length [m].
        a3: Forearm length [m].
        lateral: ``h = d2 + d3 + d4 + cos(alpha4) d5``, offset of frame 5 along the parallel
            axes from frame 1 [m].
        a4: Offset of axis 5 from axis 4 along ``x4`` [m].
        alpha4: Twist between axis 4 and axis 5 [rad].
        d5: Distance along axis 5 from axis 4 to axis 6 [m].
        alpha5: Twist between axis 5 and axis 6 [rad].
        d6: Distance along axis 6 from frame 5 to standard frame 6 [m].
        offsets: Joint offsets ``theta1 .. theta6`` [rad] (DH angle = q + offset).
        T_base: World -> standard DH frame 0 (4x4) [m].
        T_tool: Standard frame 6 (``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
    """

    name: ClassVar[str] = "ur_wrist"
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    branch_labels: ClassVar[tuple[str, ...]] = _labels()
    #: The compiled twin (``kin/_native/_ur_wrist.c``), or None when it is not built.
    compiled_twin: ClassVar[ModuleType | None] = twin("_ur_wrist")

    robot: str
    alpha1: float
    a1: float
    d1: float
    a2: float
    a3: float
    lateral: float
    a4: float
    alpha4: float
    d5: float
    alpha5: float
    d6: float
    offsets: tuple[float, ...]
    T_base: np.ndarray = field(repr=False)
    T_tool: np.ndarray = field(repr=False)
    _frame: TargetFrame = field(init=False, repr=False, compare=False)
    _k: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _classic: bool = field(init=False, repr=False, compare=False)
    _c_params: np.ndarray | None = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_frame", TargetFrame(self.T_base, self.T_tool))
        s1, c1 = sin_cos(self.alpha1)
        s4, c4 = sin_cos(self.alpha4)
        s5, c5 = sin_cos(self.alpha5)
        # wrist-to-axis-3 vector in the arm plane, rotated by phi: (a4, -sin(alpha4) d5)
        k = (s1, c1, self.a4, -s4 * self.d5, s4, c4, s5, c5)
        object.__setattr__(self, "_k", k)
        # Both wrist twists +-90 deg: |sin t5| is then read without cancellation.
        object.__setattr__(self, "_classic", c4 == 0.0 and c5 == 0.0)
        self._pack_twin()

    def _c_own(self) -> dict[str, tuple[float, ...]]:
        lengths = (self.a1, self.d1, self.a2, self.a3, self.lateral, self.d6)
        return {
            "k": self._k,
            "classic": (float(self._classic),),
            "len": lengths,
            "off": self.offsets,
        }

    @classmethod
    def recognise(cls, table: DHTable) -> URWrist6R:
        """The parameters of ``table``'s arm.

        Raises:
            StructureError: The table is not a 6R arm of this family; the message names the row
                and the parameter that does not fit.
        """
        check = SixRChecker(table, "6R UR-wrist (three parallel axes)")
        alpha1 = check.skew(0, "axis 2 must not be parallel to axis 1")
        check.twist(1, (0.0,), "axes 2, 3 and 4 must be parallel")
        check.twist(2, (0.0,), "axes 2, 3 and 4 must be parallel")
        a2 = check.nonzero(1, "a", "the upper arm between axes 2 and 3")
        a3 = check.nonzero(2, "a", "the forearm between axes 3 and 4")
        alpha4 = check.skew(3, "axis 5 must not be parallel to axes 2-4")
        alpha5 = check.skew(4, "axis 6 must not be parallel to axis 5")
        check.zero(4, "a", "axes 5 and 6 must meet")
        d = check.d
        return cls(
            robot=table.name,
            alpha1=float(alpha1),
            a1=float(check.a[0]),
            d1=float(d[0]),
            a2=a2,
            a3=a3,
            lateral=float(d[1] + d[2] + d[3] + sin_cos(alpha4)[1] * d[4]),
            a4=float(check.a[3]),
            alpha4=float(alpha4),
            d5=float(d[4]),
            alpha5=float(alpha5),
            d6=float(d[5]),
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
            free: Value of ``q6`` [rad] where the wrist is singular (axis 6 parallel to 2-4).
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
        s1, c1, ex, ey, s4, c4, s5a, c5a = self._k
        classic = self._classic
        a1, d1, a2, a3, h, d6 = self.a1, self.d1, self.a2, self.a3, self.lateral, self.d6
        o1, o2, o3, o4, o5, o6 = self.offsets
        out = [NAN_ROW] * 8
        r00, r01, r02 = r[0]
        r10, r11, r12 = r[1]
        r20, r21, r22 = r[2]
        # 1. joint 1 from p5
        px, py, pz = p[0] - d6 * r02, p[1] - d6 * r12, p[2] - d6 * r22
        rho = math.hypot(px, py)
        if rho == 0.0:
            return np.array(out)
        k = (c1 * (pz - d1) - h) / (s1 * rho)
        if (clipped := clip_unit(k)) is None:
            return np.array(out)
        k = clipped
        beta = math.atan2(py, px)
        asin_k = math.asin(k)
        two_a2a3 = 2.0 * a2 * a3
        base_sq = a2 * a2 + a3 * a3
        for shoulder in (0, 1):
            t1 = beta - asin_k if shoulder == 0 else beta - math.pi + asin_k
            ct, st = math.cos(t1), math.sin(t1)
            # axes of frame 1 in frame 0: x1, y1, z1
            x1 = (ct, st, 0.0)
            y1 = (-c1 * st, c1 * ct, s1)
            z1 = (s1 * st, -s1 * ct, c1)
            # 2. z1 in frame 6: R^T z1
            x6 = r00 * z1[0] + r10 * z1[1] + r20 * z1[2]
            y6 = r01 * z1[0] + r11 * z1[1] + r21 * z1[2]
            w = r02 * z1[0] + r12 * z1[1] + r22 * z1[2]
            cos5 = (c4 * c5a - w) / (s4 * s5a)
            xy6 = math.hypot(x6, y6)
            if classic:
                sin5 = xy6
            else:
                if (clipped := clip_unit(cos5)) is None:
                    continue
                cos5 = clipped
                sin5 = math.sqrt(1.0 - cos5 * cos5)
            # p5 - o1 in the arm plane
            qx, qy, qz = px - a1 * ct, py - a1 * st, pz - d1
            ax = x1[0] * qx + x1[1] * qy
            ay = y1[0] * qx + y1[1] * qy + y1[2] * qz
            for wrist in (0, 1):
                st5 = sin5 if wrist == 0 else -sin5
                t5 = math.atan2(st5, cos5)
                if xy6 <= SINGULAR:
                    t6 = free + o6
                else:  # (x6, y6) = Rz(-t6) (vx, vy)
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
                cphi = x1[0] * rx + x1[1] * ry
                sphi = y1[0] * rx + y1[1] * ry + y1[2] * rz
                phi = math.atan2(sphi, cphi)
                cp, sp = math.cos(phi), math.sin(phi)
                bx = ax - (cp * ex - sp * ey)
                by = ay - (sp * ex + cp * ey)
                cos3 = (bx * bx + by * by - base_sq) / two_a2a3
                if (clipped := clip_unit(cos3)) is None:
                    continue
                cos3 = clipped
                sin3 = math.sqrt(1.0 - cos3 * cos3)
                heading = math.atan2(by, bx)
                q156 = (wrap(t1 - o1), wrap(t5 - o5), wrap(t6 - o6))
                index = 4 * shoulder + 2 * wrist
                for elbow in (0, 1):
                    st3 = sin3 if elbow == 0 else -sin3
                    t3 = math.atan2(st3, cos3)
                    t2 = heading - math.atan2(a3 * st3, a2 + a3 * cos3)
                    t4 = phi - t2 - t3
                    out[index + elbow] = (
                        q156[0],
                        wrap(t2 - o2),
                        wrap(t3 - o3),
                        wrap(t4 - o4),
                        q156[1],
                        q156[2],
                    )
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
            free: Value of ``q6`` [rad] where the wrist is singular.
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
        s1, c1, ex, ey, s4, c4, s5a, c5a = self._k
        a1, d1, a2, a3, h, d6 = self.a1, self.d1, self.a2, self.a3, self.lateral, self.d6
        o1, o2, o3, o4, o5, o6 = self.offsets
        out = np.full((p.shape[0], 8, 6), np.nan)
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = (
            (r[:, i, 0], r[:, i, 1], r[:, i, 2]) for i in range(3)
        )
        with np.errstate(invalid="ignore", divide="ignore"):
            px, py, pz = p[:, 0] - d6 * r02, p[:, 1] - d6 * r12, p[:, 2] - d6 * r22
            rho = np.hypot(px, py)
            k = (c1 * (pz - d1) - h) / (s1 * rho)
            k = np.where(rho == 0.0, np.nan, clip_cosines(k))
            beta = np.arctan2(py, px)
            asin_k = np.arcsin(k)
            for shoulder in (0, 1):
                t1 = beta - asin_k if shoulder == 0 else beta - math.pi + asin_k
                ct, st = np.cos(t1), np.sin(t1)
                y1 = (-c1 * st, c1 * ct, s1)
                z1 = (s1 * st, -s1 * ct, c1)
                x6 = r00 * z1[0] + r10 * z1[1] + r20 * z1[2]
                y6 = r01 * z1[0] + r11 * z1[1] + r21 * z1[2]
                w = r02 * z1[0] + r12 * z1[1] + r22 * z1[2]
                cos5 = (c4 * c5a - w) / (s4 * s5a)
                xy6 = np.hypot(x6, y6)
                if self._classic:
                    sin5 = xy6
                else:
                    cos5 = clip_cosines(cos5)
                    sin5 = np.sqrt(1.0 - cos5 * cos5)
                qx, qy, qz = px - a1 * ct, py - a1 * st, pz - d1
                ax = ct * qx + st * qy
                ay = y1[0] * qx + y1[1] * qy + y1[2] * qz
                for wrist in (0, 1):
                    st5 = sin5 if wrist == 0 else -sin5
                    t5 = np.arctan2(st5, cos5)
                    vx, vy = s4 * st5, c5a * s4 * cos5 + s5a * c4
                    t6 = np.where(
                        xy6 <= SINGULAR, free + o6, np.arctan2(vy, vx) - np.arctan2(y6, x6)
                    )
                    ct6, st6 = np.cos(t6), np.sin(t6)
                    xi0 = cos5 * ct6 - st5 * c5a * st6
                    xi1 = -cos5 * st6 - st5 * c5a * ct6
                    xi2 = s5a * st5
                    rx = r00 * xi0 + r01 * xi1 + r02 * xi2
                    ry = r10 * xi0 + r11 * xi1 + r12 * xi2
                    rz = r20 * xi0 + r21 * xi1 + r22 * xi2
                    cphi = ct * rx + st * ry
                    sphi = y1[0] * rx + y1[1] * ry + y1[2] * rz
                    phi = np.arctan2(sphi, cphi)
                    cp, sp = np.cos(phi), np.sin(phi)
                    bx = ax - (cp * ex - sp * ey)
                    by = ay - (sp * ex + cp * ey)
                    cos3 = clip_cosines((bx * bx + by * by - (a2 * a2 + a3 * a3)) / (2.0 * a2 * a3))
                    sin3 = np.sqrt(1.0 - cos3 * cos3)
                    heading = np.arctan2(by, bx)
                    index = 4 * shoulder + 2 * wrist
                    for elbow in (0, 1):
                        st3 = sin3 if elbow == 0 else -sin3
                        t3 = np.arctan2(st3, cos3)
                        t2 = heading - np.arctan2(a3 * st3, a2 + a3 * cos3)
                        t4 = phi - t2 - t3
                        q = np.stack((t1 - o1, t2 - o2, t3 - o3, t4 - o4, t5 - o5, t6 - o6), -1)
                        out[:, index + elbow] = wrap_array(q)
        out[np.isnan(out).any(axis=2)] = np.nan
        return out
