"""Closed-form IK of a 6R arm with three parallel axes 2-4 and any joints 1, 5, 6 (IK-Geo).

Structure, read from the table brought to the standard chain (:mod:`._six_r`, either convention):

- joint 1: any twist with ``sin alpha1 != 0`` (else four parallel axes), any ``a1, d1``;
- joints 2, 3, 4: parallel axes (``alpha2 = alpha3 = 0``), ``a2 != 0``, ``a3 != 0``; ``d2, d3,
  d4`` and ``a4`` free;
- joint 5 not parallel to them and joint 6 not parallel to joint 5 (``sin alpha4 != 0``,
  ``sin alpha5 != 0``); ``a5``, ``d5``, ``d6``, ``a6`` and ``alpha6`` free. Two families:

  * ``intersecting``: ``a5 = 0``, axes 5 and 6 meet: quadratics. This is the UR case (UR3, UR5,
    UR10 and the e-series: ``alpha = (90, 0, 0, 90, -90, 0) deg``, ``a = (0, a2, a3, 0, 0, 0)``,
    ``d = (d1, 0, 0, d4, d5, d6)``; Unitree Z1): :class:`URWrist6R`, named ``ur_wrist`` in answers,
    solved by the family's algorithm and by its compiled twin (``kin/_native/ik/analytic/six_r/_three_parallel.c``);
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
     +-90 deg ``|sin t5| = |(x6, y6)|``, read without cancellation);
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

One algorithm, in NumPy, for N targets (:mod:`.three_parallel_batch`; one target is N = 1); one
compiled twin repeats it target by target for both families (``_three_parallel.c``, the general
family's quartic by NumPy's LAPACK or SciPy's).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from types import ModuleType
from typing import Any, ClassVar

import numpy as np

from dh2urdf import DHTable
from kin._native import twin

from ...targets.target import PoseTarget
from ._six_r import LENGTH_TOL, SixRChecker, TargetFrame, sin_cos
from .six_r_family import SixRFamily
from .six_r_twin import TwinVerifier, frame_fields, quartic_twin
from .three_parallel_batch import REACH_TOL, ThreeParallelBatch

__all__ = ["NEAR_MEET", "REACH_TOL", "ThreeParallel6R", "URWrist6R"]
#: ``|a5|`` below ``NEAR_MEET (|a2| + |a3|)`` (but not 0) is refused: axes 5 and 6 nearly meet,
#: the roots of ``E`` come in pairs about ``|a5|`` apart that the companion matrix and Newton
#: steps no longer resolve (q is then missed on more than 0.1 % of targets).
NEAR_MEET = 1e-3
#: The family's compiled twin (both families), or None when it is not built.
_TWIN = twin("_three_parallel")


def _general_twin() -> ModuleType | None:
    """The twin for a general-family arm: None when not built or no LAPACK loads for its quartic."""
    return quartic_twin(_TWIN)


_ARM_LABELS = {
    "intersecting": tuple(
        f"shoulder {s}, wrist {w}" for s in ("left", "right") for w in ("up", "down")
    ),
    "general": tuple(f"arm {k} (q1 ascending)" for k in range(1, 5)),
}


def _labels(family: str) -> tuple[str, ...]:
    """The meaning of the 8 rows of a family: its ``(t1, t5)`` slot, then the elbow."""
    return tuple(f"{arm}, elbow {e}" for arm in _ARM_LABELS[family] for e in ("up", "down"))


def _read(table: DHTable, solver: str, meet: bool) -> dict[str, Any]:
    """The fields of ``table``'s arm; ``meet``: axes 5 and 6 must meet (the UR case).

    Raises:
        StructureError: The table is not of the family; the message names the row and parameter.
    """
    check = SixRChecker(table, solver)
    alpha1 = check.skew(0, "axis 2 must not be parallel to axis 1")
    check.twist(1, (0.0,), "axes 2, 3 and 4 must be parallel")
    check.twist(2, (0.0,), "axes 2, 3 and 4 must be parallel")
    a2 = check.nonzero(1, "a", "the upper arm between axes 2 and 3")
    a3 = check.nonzero(2, "a", "the forearm between axes 3 and 4")
    alpha4 = check.skew(3, "axis 5 must not be parallel to axes 2-4")
    alpha5 = check.skew(4, "axis 6 must not be parallel to axis 5")
    if meet:
        check.zero(4, "a", "axes 5 and 6 must meet")
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
    return {
        "robot": table.name,
        "family": family,
        "alpha1": float(alpha1),
        "a1": float(check.a[0]),
        "d1": float(d[0]),
        "a2": a2,
        "a3": a3,
        "lateral": float(d[1] + d[2] + d[3] + sin_cos(alpha4)[1] * d[4]),
        "a4": float(check.a[3]),
        "alpha4": float(alpha4),
        "d5": float(d[4]),
        "a5": 0.0 if family == "intersecting" else a5,
        "alpha5": float(alpha5),
        "d6": float(d[5]),
        "offsets": tuple(float(v) for v in check.theta),
        "T_base": check.T_base,
        "T_tool": check.T_tool,
    }


@dataclass(frozen=True)
class ThreeParallel6R:
    """A 6R arm with axes 2, 3, 4 parallel: parameters in SI, and its closed form (8 branches).

    :meth:`recognise` gives the UR case (``a5 = 0``) as a :class:`URWrist6R`. It holds its NumPy
    algorithm (:class:`~.three_parallel_batch.ThreeParallelBatch`) and its solve of one or N
    targets (:class:`~.six_r_family.SixRFamily`: the compiled twin where it fits, else that
    algorithm).

    Attributes:
        robot: Robot name.
        family: ``"intersecting"`` (``a5 = 0``) or ``"general"`` (see the module).
        offsets: Joint offsets ``theta1 .. theta6`` [rad] (DH angle = q + offset).
        T_base: World -> standard DH frame 0 (4x4) [m].
        T_tool: Standard frame 6 (``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
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
    """

    name: ClassVar[str] = "three_parallel"
    #: Six revolute joints; a full pose as the target.
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    #: The family's compiled twin (``kin/_native/ik/analytic/six_r/_three_parallel.c``, both families), or None
    #: when it is not built; a general-family arm uses it only when LAPACK loads for its quartic.
    compiled_twin: ClassVar[ModuleType | None] = _TWIN
    #: The family's special cases (subclasses), asked first by the registry.
    cases: ClassVar[tuple[type[ThreeParallel6R], ...]] = ()

    robot: str
    family: str
    offsets: tuple[float, ...]
    T_base: np.ndarray = field(repr=False)
    T_tool: np.ndarray = field(repr=False)
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
    _batch: ThreeParallelBatch = field(init=False, repr=False, compare=False)
    _solve: SixRFamily = field(init=False, repr=False, compare=False)
    #: The held :class:`~.six_r_family.SixRFamily`'s ``solve`` (the 8 branches (8, 6) [rad] of
    #: one tool pose), ``solve_batch`` ((N, 8, 6) of N) and ``verifier`` (the compiled
    #: solve-and-verify, or None): its bound methods, no call in between.
    solve: Callable[..., np.ndarray] = field(init=False, repr=False, compare=False)
    solve_batch: Callable[..., np.ndarray] = field(init=False, repr=False, compare=False)
    verifier: Callable[..., TwinVerifier | None] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        lengths = (self.a1, self.d1, self.a2, self.a3, self.lateral, self.a4, self.d5, self.a5)
        twists = (self.alpha1, self.alpha4, self.alpha5)
        frame = TargetFrame(self.T_base, self.T_tool)
        batch = ThreeParallelBatch.of(self.family, self.offsets, frame, (*lengths, self.d6), twists)
        object.__setattr__(self, "_batch", batch)
        fits = self.family == "intersecting" or _general_twin() is not None
        fields = self.c_fields if fits else None
        SixRFamily.of(self.name, batch.solve_block, self.compiled_twin, fields).hand_to(self)

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (its ``LAYOUT``; [m], [rad])."""
        lengths = (self.a1, self.d1, self.a2, self.a3, self.lateral, self.a4, self.d5)
        return {
            **frame_fields(self.T_base, self.T_tool),
            "family": (float(self.family == "general"),),
            "k": self._batch.k,
            "classic": (float(self._batch.classic),),
            "len": (*lengths, self.a5, self.d6),
            "off": self.offsets,
        }

    @property
    def c_params(self) -> np.ndarray:
        """:meth:`c_fields` packed in the order the compiled twin declares (its ``LAYOUT``).

        Raises:
            RuntimeError: The twin is not built.
        """
        return self._solve.c_params

    @property
    def branch_labels(self) -> tuple[str, ...]:
        """The meaning of the 8 rows of :meth:`solve`: the family's ``(t1, t5)`` slot, the elbow."""
        return _labels(self.family)

    @classmethod
    def recognise(cls, table: DHTable) -> ThreeParallel6R:
        """The parameters of ``table``'s arm (a :class:`URWrist6R` when axes 5 and 6 meet).

        Raises:
            StructureError: The table is not a 6R arm with three parallel axes 2-4 and finitely
                many solutions; the message names the row and the parameter that does not fit.
        """
        fields = _read(table, "6R three parallel axes", meet=False)
        return (URWrist6R if fields["family"] == "intersecting" else ThreeParallel6R)(**fields)


@dataclass(frozen=True)
class URWrist6R(ThreeParallel6R):
    """The UR case of :class:`ThreeParallel6R`: axes 5 and 6 meet (``a5 = 0``); 8 branches.

    UR3, UR5, UR10 and the e-series, Unitree Z1: the family's ``intersecting`` arms, named
    ``ur_wrist`` (in :attr:`~kin.ik.result.IKResult.method` and the solver's name), solved by the
    family's algorithm and its compiled twin. Fields as :class:`ThreeParallel6R`'s.
    """

    name: ClassVar[str] = "ur_wrist"
    branch_labels: ClassVar[tuple[str, ...]] = _labels("intersecting")  # type: ignore[misc]

    @classmethod
    def recognise(cls, table: DHTable) -> URWrist6R:
        """The parameters of ``table``'s arm.

        Raises:
            StructureError: The table is not a 6R arm of the UR case; the message names the row
                and the parameter that does not fit.
        """
        return cls(**_read(table, "6R UR-wrist (three parallel axes)", meet=True))


ThreeParallel6R.cases = (URWrist6R,)
