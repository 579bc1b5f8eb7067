"""Closed-form IK of a 6R arm with a spherical wrist and any first three joints (Pieper's case).

Structure, read from the table brought to the standard chain (:mod:`._six_r`, either convention):

- joints 4, 5, 6: a spherical wrist (``a4 = a5 = d5 = 0``,
  ``sin alpha4 != 0``, ``sin alpha5 != 0``; ``d6``, ``a6``, ``alpha6`` free);
- joints 1, 2, 3: any lengths and twists for which the wrist-centre problem has finitely many
  solutions: a forearm ``(a3, sin(alpha3) d4) != 0`` (the wrist centre is off axis 3), axes 2 and
  3 not the same line, and one of three families (Craig, *Introduction to Robotics*, sec. 4.6;
  the IK-Geo families "spherical wrist and two intersecting / two parallel axes / general"):

  * ``intersecting``: ``a1 = 0``, ``sin alpha1 != 0`` (axes 1 and 2 meet), axis 3 not through
    that point (``(a2, sin(alpha2) d2) != 0``);
  * ``parallel``: ``sin alpha1 = 0``, ``a1 != 0`` (axes 1 and 2 parallel), axis 3 not parallel
    to them (``sin alpha2 != 0``);
  * ``general``: ``a1 != 0`` and ``sin alpha1 != 0``;
  * ``parallel23``: ``sin alpha1 != 0``, axes 2 and 3 parallel (``alpha2 = 0``, ``a2 != 0``), any
    ``a1``: the spherical-wrist case (PUMA 560, Kinova Jaco 2 and most industrial arms), read
    before the three others: :class:`SphericalWrist6R`, named ``spherical_wrist`` in answers,
    solved by the family's algorithm and by its compiled twin (``kin/_native/ik/analytic/six_r/_pieper_arms.c``).

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

   - parallel23 (``alpha2 = 0``): in frame 1 the wrist centre is ``(x1, y1, h)`` with a constant
     ``h = d2 + d3 + ca3 d4``; frame 0 sees ``Rz(t1) (a1 + x1, ca1 y1 - sa1 h, d1 + sa1 y1 + ca1
     h)``: the height gives ``y1``, the base radius ``a1 + x1 = +-sqrt(Wx^2 + Wy^2 - (ca1 y1 -
     sa1 h)^2)`` (shoulder right / left) and the heading ``t1``; ``(x1, y1) = Rz(t2) ((a2, 0) +
     Rz(t3) (a3, -sa3 d4))`` by the law of cosines (elbow up: ``-acos``, down: ``+acos``), then
     ``t2``.

   Then ``t2 = atan2(h2, h1) - atan2(g2, g1)`` and
   ``t1 = atan2(Wy, Wx) - atan2(ca1 h2 - sa1 h3, a1 + h1)`` with ``h = Rz(t2) g``.
3. ``N = R_0_3^T R_0_6 = Rz(t4) Rx(alpha4) Rz(t5) Rx(alpha5) Rz(t6)``: ``cos t5`` from its third
   column, two signs of ``sin t5`` (wrist no flip:
   ``sin t5 >= 0``, flip: ``< 0``), ``t4``, then ``t6`` from the first column; at ``sin t5 = 0``
   (axes 4 and 6 aligned) ``q4`` takes the value ``free``.

One algorithm, in NumPy, for N targets (:mod:`.pieper_batch`, the general family's equation in
:mod:`.pieper_quartic`; one target is N = 1); one compiled twin repeats it target by target for
the four families (``_pieper_arms.c``, the general family's quartic by NumPy's LAPACK or SciPy's).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from types import ModuleType
from typing import Any, ClassVar

import numpy as np

from dh2urdf import DHTable
from kin._native import twin

from ...exceptions import StructureError
from ...targets.target import PoseTarget
from ._six_r import ANGLE_TOL, LENGTH_TOL, SixRChecker, TargetFrame
from .pieper_batch import PieperBatch
from .six_r_family import SixRFamily
from .six_r_twin import TwinVerifier, frame_fields, quartic_twin

#: The family's compiled twin (its four families), or None when it is not built; the families by
#: their number in its parameters.
_TWIN = twin("_pieper_arms")
_FAMILIES = ("intersecting", "parallel", "general", "parallel23")


def _arms_twin(family: str) -> ModuleType | None:
    """The compiled twin for an arm of ``family``, or None when it is not built.

    Also None for the general family when no LAPACK can be loaded for its quartic.
    """
    return quartic_twin(_TWIN) if family == "general" else _TWIN


_SHOULDER_ELBOW = tuple(
    f"shoulder {s}, elbow {e}" for s in ("right", "left") for e in ("up", "down")
)
_ARM_LABELS = {
    "intersecting": _SHOULDER_ELBOW,
    "parallel": tuple(f"arm {s}, elbow {e}" for s in ("ccw", "cw") for e in ("up", "down")),
    "general": tuple(f"arm {k} (q3 ascending)" for k in range(1, 5)),
    "parallel23": _SHOULDER_ELBOW,
}


def _labels(family: str) -> tuple[str, ...]:
    """The meaning of the 8 rows of a family: its arm slot, then the wrist."""
    return tuple(f"{arm}, wrist {w}" for arm in _ARM_LABELS[family] for w in ("no flip", "flip"))


def _fields(check: SixRChecker, family: str, a1: float, alpha1: float) -> dict[str, Any]:
    """The fields of a :class:`Pieper6R` read by ``check`` (the wrist already checked)."""
    a, alpha, d = check.a, check.alpha, check.d
    return {
        "robot": check.table.name,
        "family": family,
        "a1": a1,
        "d1": float(d[0]),
        "alpha1": alpha1,
        "a2": float(a[1]),
        "alpha2": 0.0 if family == "parallel23" else float(alpha[1]),
        "d2": float(d[1]),
        "a3": float(a[2]),
        "alpha3": float(alpha[2]),
        "d3": float(d[2]),
        "d4": float(d[3]),
        "alpha4": float(alpha[3]),
        "alpha5": float(alpha[4]),
        "d6": float(d[5]),
        "offsets": tuple(float(v) for v in check.theta),
        "T_base": check.T_base,
        "T_tool": check.T_tool,
    }


def _wrist(check: SixRChecker) -> None:
    """Raise unless joints 4-6 are a spherical wrist and the wrist centre is off axis 3."""
    check.zero(3, "a", "the wrist axes 4, 5 and 6 must meet")
    check.zero(4, "a", "the wrist axes 4, 5 and 6 must meet")
    check.zero(4, "d", "the wrist axes 4, 5 and 6 must meet")
    check.skew(3, "wrist axes 4 and 5 must not be parallel")
    check.skew(4, "wrist axes 5 and 6 must not be parallel")
    if math.hypot(check.a[2], math.sin(check.alpha[2]) * check.d[3]) <= LENGTH_TOL:
        raise check.fail(
            f"{check.where(2, 'a')} and {check.where(3, 'd')}: the wrist centre is on axis 3 "
            "(zero forearm), expected a forearm of non-zero length"
        )


def _read_spherical(table: DHTable) -> dict[str, Any]:
    """The fields of the parallel23 case (:class:`SphericalWrist6R`), or StructureError."""
    check = SixRChecker(table, "6R spherical-wrist")
    alpha1 = check.skew(0, "axis 2 must not be parallel to axis 1")
    check.twist(1, (0.0,), "axes 2 and 3 must be parallel")
    check.nonzero(1, "a", "the upper arm between the parallel axes 2 and 3")
    _wrist(check)
    return _fields(check, "parallel23", float(check.a[0]), float(alpha1))


def _read(table: DHTable) -> dict[str, Any]:
    """The fields of a table of the intersecting, parallel or general family, or StructureError."""
    check = SixRChecker(table, "6R Pieper")
    _wrist(check)
    a, alpha, d = check.a, check.alpha, check.d
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
        return _fields(check, "parallel", float(a[0]), check.twist(0, (0.0, math.pi, -math.pi), ""))
    if abs(a[0]) > LENGTH_TOL:
        return _fields(check, "general", float(a[0]), alpha1)
    if math.hypot(a[1], math.sin(alpha[1]) * d[1]) <= LENGTH_TOL:
        raise check.fail(
            f"{check.where(0, 'a')} = 0 m, {check.where(1, 'a')} = 0 m and "
            f"{check.where(1, 'd')} = {d[1]:g} m: axes 1, 2 and 3 meet in one point "
            "(a spherical shoulder), expected axis 3 away from where axes 1 and 2 meet"
        )
    return _fields(check, "intersecting", 0.0, alpha1)


@dataclass(frozen=True)
class Pieper6R:
    """A 6R arm with a spherical wrist and a general 3R arm: parameters in SI, closed form (8 branches).

    :meth:`recognise` gives the spherical-wrist case (axes 2 and 3 parallel) as a
    :class:`SphericalWrist6R`. It holds its NumPy algorithm (:class:`~.pieper_batch.PieperBatch`)
    and its solve of one or N targets (:class:`~.six_r_family.SixRFamily`: the compiled twin
    where it fits, else that algorithm).

    Attributes:
        robot: Robot name.
        family: ``"intersecting"`` (axes 1, 2 meet), ``"parallel"`` (axes 1, 2 parallel),
            ``"general"`` or ``"parallel23"`` (axes 2, 3 parallel; see the module).
        offsets: Joint offsets ``theta1 .. theta6`` [rad] (DH angle = q + offset).
        T_base: World -> standard DH frame 0 (4x4) [m].
        T_tool: Standard frame 6 (``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
        a1: Length of the common normal of axes 1 and 2 [m].
        d1: Height of that normal along axis 1 [m].
        alpha1: Twist between axes 1 and 2 [rad] (0 or pi exactly in the parallel family).
        a2, alpha2, d2: Common normal, twist and offset of joint 2 [m], [rad].
        a3, alpha3, d3: The same of joint 3 [m], [rad].
        d4: Offset along axis 4 from the normal of axes 3 and 4 to the wrist centre [m].
        alpha4: Twist between axes 4 and 5 [rad].
        alpha5: Twist between axes 5 and 6 [rad].
        d6: Distance from the wrist centre to standard frame 6 along axis 6 [m].
    """

    name: ClassVar[str] = "pieper"
    #: Six revolute joints; a full pose as the target.
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    #: The family's compiled twin (``kin/_native/ik/analytic/six_r/_pieper_arms.c``, its four families), or None
    #: when it is not built; a general-family arm uses it only when LAPACK loads for its quartic.
    compiled_twin: ClassVar[ModuleType | None] = _TWIN
    #: The family's special cases (subclasses), asked first by the registry.
    cases: ClassVar[tuple[type[Pieper6R], ...]] = ()

    robot: str
    family: str
    offsets: tuple[float, ...]
    T_base: np.ndarray = field(repr=False)
    T_tool: np.ndarray = field(repr=False)
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
    _batch: PieperBatch = field(init=False, repr=False, compare=False)
    _solve: SixRFamily = field(init=False, repr=False, compare=False)
    #: The held :class:`~.six_r_family.SixRFamily`'s ``solve`` (the 8 branches (8, 6) [rad] of
    #: one tool pose), ``solve_batch`` ((N, 8, 6) of N) and ``verifier`` (the compiled
    #: solve-and-verify, or None): its bound methods, no call in between.
    solve: Callable[..., np.ndarray] = field(init=False, repr=False, compare=False)
    solve_batch: Callable[..., np.ndarray] = field(init=False, repr=False, compare=False)
    verifier: Callable[..., TwinVerifier | None] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        lengths = (self.a1, self.d1, self.a2, self.d2, self.a3, self.d3, self.d4, self.d6)
        twists = (self.alpha1, self.alpha2, self.alpha3, self.alpha4, self.alpha5)
        frame = TargetFrame(self.T_base, self.T_tool)
        batch = PieperBatch.of(self.family, self.offsets, frame, lengths, twists)
        object.__setattr__(self, "_batch", batch)
        fits = _arms_twin(self.family) is not None
        fields = self.c_fields if fits else None
        SixRFamily.of(self.name, batch.solve_block, self.compiled_twin, fields).hand_to(self)

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (its ``LAYOUT``; [m], [rad])."""
        batch = self._batch
        return {
            **frame_fields(self.T_base, self.T_tool),
            "family": (float(_FAMILIES.index(self.family)),),
            "k": batch.k[2:5],
            "e": batch.e + (0.0,) * (9 - len(batch.e)),
            "g": tuple(v for row in batch.g for v in row),
            "wrist": batch.wrist,
            "classic": (float(batch.classic),),
            "len": (self.a1, self.d1, self.d6),
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
        """The meaning of the 8 rows of :meth:`solve`: the family's arm, then the wrist."""
        return _labels(self.family)

    @classmethod
    def recognise(cls, table: DHTable) -> Pieper6R:
        """The parameters of ``table``'s arm (a :class:`SphericalWrist6R` when axes 2, 3 are parallel).

        Raises:
            StructureError: The table is not a 6R arm with a spherical wrist and a 3R arm of
                finitely many solutions; the message names the row and the parameter.
        """
        try:
            return SphericalWrist6R(**_read_spherical(table))
        except StructureError:
            return cls.read(table)

    @classmethod
    def read(cls, table: DHTable) -> Pieper6R:
        """``table``'s arm in the intersecting, parallel or general family, never parallel23.

        What :meth:`recognise` gives when axes 2 and 3 are not parallel; of a spherical-wrist
        table, the same arm solved by the general equations (the tests compare the two).

        Raises:
            StructureError: As :meth:`recognise`.
        """
        return Pieper6R(**_read(table))


@dataclass(frozen=True)
class SphericalWrist6R(Pieper6R):
    """The spherical-wrist case of :class:`Pieper6R`: axes 2 and 3 parallel; 8 branches.

    PUMA 560, Kinova Jaco 2 and most industrial arms: the family's ``parallel23`` arms, named
    ``spherical_wrist`` (in :attr:`~kin.ik.result.IKResult.method` and the solver's name), solved
    by the family's algorithm and its compiled twin. Fields as :class:`Pieper6R`'s.
    """

    name: ClassVar[str] = "spherical_wrist"
    branch_labels: ClassVar[tuple[str, ...]] = _labels("parallel23")  # type: ignore[misc]

    @property
    def lateral(self) -> float:
        """Offset of the wrist centre along axis 2 in frame 1, ``d2 + d3 + cos(alpha3) d4`` [m]."""
        return self._batch.e[4]

    @property
    def forearm(self) -> tuple[float, float]:
        """In-plane vector from axis 3 to the wrist centre, ``(a3, -sin(alpha3) d4)`` [m]."""
        return self._batch.e[0], self._batch.e[1]

    @classmethod
    def recognise(cls, table: DHTable) -> SphericalWrist6R:
        """The parameters of ``table``'s arm.

        Raises:
            StructureError: The table is not a 6R arm of the spherical-wrist case; the message
                names the row and the parameter that does not fit.
        """
        return cls(**_read_spherical(table))


Pieper6R.cases = (SphericalWrist6R,)
