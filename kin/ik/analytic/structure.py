"""Recognise, from a DH table, which closed-form solver fits the arm, and read its parameters.

Four structures are recognised (standard DH, revolute joints only):

- :class:`Planar2R`: two joints with parallel axes (``alpha1 = 0``); the tool point moves in a plane.
- :class:`Offset3R`: base yaw, then two parallel pitch joints (``alpha1 = +-90 deg``,
  ``alpha2 = 0``); the lateral offset ``d2 + d3 + tool z`` (the shoulder offset) may be non-zero.
- :class:`FiveDof`: base yaw, three parallel pitch joints and a wrist roll (``alpha1 = +-90``,
  ``alpha2 = alpha3 = 0``, ``alpha4 = +-90``, ``a5 = 0``) with the tool point on the roll axis and
  no lateral offset (``d2 + d3 + d4 = 0``); ``a1`` (SCORBOT shoulder offset) and ``a4`` are allowed.
- :class:`SevenDof`: seven joints, axes 2 and 3 meeting at a shoulder point, axes 5-7 at a wrist
  centre (humanoid7). Redundant: :func:`recognise` leaves it to the numeric solver, which solves
  it in closed form for chosen joint-1 angles (:mod:`ik.seven_dof`).

Everything the solvers use (link lengths, offsets, signs) is read here from the table, so an arm of
the same structure with other numbers works unchanged. A table that does not fit raises
:class:`~ik.exceptions.StructureError` naming the row and parameter that does not fit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from dh2urdf import DHRow, DHTable

from ..exceptions import StructureError

#: Tolerance on DH angles [rad] and lengths [m] when matching a structure.
ANGLE_TOL = 1e-9
LENGTH_TOL = 1e-12


@dataclass(frozen=True)
class Link:
    """An in-plane link vector of a chain of parallel joints.

    Attributes:
        length: Length of the vector [m] (> 0).
        angle: Angle of the vector from the joint's DH x axis [rad].
    """

    length: float
    angle: float


@dataclass(frozen=True)
class Planar2R:
    """Two-joint planar arm: the tool point is ``Rz(t1) l1 + Rz(t1 + t2) l2`` at height ``z``.

    Attributes:
        link1, link2: In-plane link vectors (the second includes the tool point).
        height: z of the plane of motion in frame 0 [m].
        offsets: DH angle offsets ``theta`` [rad] (DH angle = q + offset).
    """

    link1: Link
    link2: Link
    height: float
    offsets: tuple[float, ...]


@dataclass(frozen=True)
class Offset3R:
    """Base yaw and two parallel pitch joints, with a possible shoulder (lateral) offset.

    Attributes:
        sign1: Sign of ``alpha1`` (+1 or -1): the arm plane's "up" is ``sign1 * z0``.
        a1: Radial offset of the shoulder axis from the base axis [m].
        d1: Height of the shoulder axis [m].
        lateral: Offset of the arm plane along ``z1`` [m] (``d2 + d3 + tool z``).
        link2, link3: In-plane link vectors (the last includes the tool point).
        offsets: DH angle offsets [rad].
    """

    sign1: float
    a1: float
    d1: float
    lateral: float
    link2: Link
    link3: Link
    offsets: tuple[float, ...]


@dataclass(frozen=True)
class FiveDof:
    """Base yaw, three parallel pitch joints, wrist roll; tool point on the roll axis.

    Attributes:
        sign1: Sign of ``alpha1``.
        sign4: Sign of ``alpha4``: the roll axis is at ``theta2 + theta3 + theta4 - sign4 pi/2``
            in the arm plane.
        a1: Radial shoulder offset [m].
        d1: Shoulder height [m].
        link2, link3: In-plane link vectors of the upper arm and forearm.
        a4: Wrist link along ``x4`` [m] (usually 0).
        reach: Distance from the wrist centre (frame 4 origin) to the tool point along the roll
            axis [m] (``d5`` plus the tool's offset along it).
        R_roll_tool: Rotation of the tool in the frame ``Rz(theta5)`` leaves (``Rx(alpha5)`` times
            the tool rotation).
        offsets: DH angle offsets [rad].
        roll_tool_rows: ``R_roll_tool`` as rows of floats, or None when it is the identity
            (derived, for the scalar solver).
    """

    sign1: float
    sign4: float
    a1: float
    d1: float
    link2: Link
    link3: Link
    a4: float
    reach: float
    R_roll_tool: np.ndarray
    offsets: tuple[float, ...]
    roll_tool_rows: tuple[tuple[float, ...], ...] | None = field(
        init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        rows = tuple(tuple(row) for row in np.asarray(self.R_roll_tool, dtype=float).tolist())
        identity = rows == ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        object.__setattr__(self, "roll_tool_rows", None if identity else rows)


@dataclass(frozen=True)
class SevenDof:
    """Seven revolute joints with a shoulder point and a spherical wrist (redundant: joint 1 free).

    The axes of joints 2 and 3 meet at the shoulder point (``a2 = 0``, ``alpha2`` not 0 or 180 deg)
    and the axes of joints 5, 6 and 7 at the wrist centre (``a5 = a6 = d6 = 0``, ``alpha5`` not 0 or
    180 deg). Joint 1 and the elbow (joint 4) are general. For a given joint-1 angle the rest is a 6R
    arm with a spherical wrist: closed form, up to 8 branches (:mod:`ik.seven_dof`).

    Attributes:
        a: DH lengths ``a1 .. a7`` [m].
        alpha: DH twists ``alpha1 .. alpha7`` [rad].
        d: DH offsets ``d1 .. d7`` [m].
        offsets: DH angle offsets ``theta1 .. theta7`` [rad] (DH angle = q + offset).
        T_world_base: Fixed transform from the URDF root to DH frame 0 (4x4, [m]).
        T_last_tool: Fixed transform from DH frame 7 to the tool frame (4x4, [m]).
    """

    a: tuple[float, ...]
    alpha: tuple[float, ...]
    d: tuple[float, ...]
    offsets: tuple[float, ...]
    T_world_base: np.ndarray = field(repr=False)
    T_last_tool: np.ndarray = field(repr=False)


Structure = Planar2R | Offset3R | FiveDof


def _near(value: float, expected: float, tol: float) -> bool:
    return abs(value - expected) <= tol


def _angle_near(value: float, expected: float) -> bool:
    return abs(math.remainder(value - expected, 2 * math.pi)) <= ANGLE_TOL


def _deg(value: float) -> str:
    return f"{math.degrees(value):g} deg"


class _Checker:
    """Collects the reason a table does not fit a solver, naming row and parameter."""

    def __init__(self, table: DHTable, solver: str):
        self.table = table
        self.solver = solver

    def fail(self, mismatch: str) -> StructureError:
        return StructureError(self.table.name, self.solver, mismatch)

    def rows(self, count: int) -> None:
        if self.table.convention != "standard":
            raise self.fail(f"convention is '{self.table.convention}', expected 'standard'")
        if self.table.dof != count:
            raise self.fail(f"{self.table.dof} joints, expected {count}")
        for row in self.table.rows:
            if row.joint_type != "revolute":
                raise self.fail(
                    f"row {row.index} ('{row.name}') is {row.joint_type}, expected revolute"
                )

    def alpha(self, row: DHRow, choices: tuple[float, ...]) -> float:
        for value in choices:
            if _angle_near(row.alpha, value):
                return value
        wanted = " or ".join(_deg(v) for v in choices)
        raise self.fail(
            f"row {row.index} ('{row.name}'): alpha = {_deg(row.alpha)}, expected {wanted}"
        )

    def zero(self, row: DHRow, field: str, why: str) -> None:
        value = getattr(row, field)
        if not _near(value, 0.0, LENGTH_TOL):
            raise self.fail(
                f"row {row.index} ('{row.name}'): {field} = {value:g} m, expected 0 ({why})"
            )

    def link(self, x: float, y: float, where: str) -> Link:
        length = math.hypot(x, y)
        if length <= LENGTH_TOL:
            raise self.fail(f"{where}: zero link length, expected a link of non-zero length")
        return Link(length, math.atan2(y, x))


def _tool_point(table: DHTable) -> np.ndarray:
    return np.asarray(table.T_last_tool[:3, 3], dtype=float)


def planar2r(table: DHTable) -> Planar2R:
    """Parameters of a two-joint planar arm.

    Raises:
        StructureError: The table is not a planar 2R arm.
    """
    check = _Checker(table, "planar 2R")
    check.rows(2)
    row1, row2 = table.rows
    check.alpha(row1, (0.0,))
    check.alpha(row2, (0.0,))
    tool = _tool_point(table)
    return Planar2R(
        link1=check.link(row1.a, 0.0, f"row 1 ('{row1.name}')"),
        link2=check.link(row2.a + tool[0], tool[1], f"row 2 ('{row2.name}') with the tool"),
        height=row1.d + row2.d + tool[2],
        offsets=(row1.theta, row2.theta),
    )


def offset3r(table: DHTable) -> Offset3R:
    """Parameters of a base-yaw + two-pitch arm with shoulder offset.

    Raises:
        StructureError: The table does not have that structure.
    """
    check = _Checker(table, "offset 3R")
    check.rows(3)
    row1, row2, row3 = table.rows
    sign1 = math.copysign(1.0, check.alpha(row1, (math.pi / 2, -math.pi / 2)))
    check.alpha(row2, (0.0,))
    check.alpha(row3, (0.0,))
    tool = _tool_point(table)
    return Offset3R(
        sign1=sign1,
        a1=row1.a,
        d1=row1.d,
        lateral=row2.d + row3.d + tool[2],
        link2=check.link(row2.a, 0.0, f"row 2 ('{row2.name}')"),
        link3=check.link(row3.a + tool[0], tool[1], f"row 3 ('{row3.name}') with the tool"),
        offsets=(row1.theta, row2.theta, row3.theta),
    )


def five_dof(table: DHTable) -> FiveDof:
    """Parameters of a base yaw + three pitch + wrist roll arm.

    Raises:
        StructureError: The table does not have that structure.
    """
    check = _Checker(table, "five-joint (yaw, 3 pitch, roll)")
    check.rows(5)
    row1, row2, row3, row4, row5 = table.rows
    sign1 = math.copysign(1.0, check.alpha(row1, (math.pi / 2, -math.pi / 2)))
    check.alpha(row2, (0.0,))
    check.alpha(row3, (0.0,))
    sign4 = math.copysign(1.0, check.alpha(row4, (math.pi / 2, -math.pi / 2)))
    lateral = row2.d + row3.d + row4.d
    if not _near(lateral, 0.0, LENGTH_TOL):
        raise check.fail(
            f"rows 2-4: d2 + d3 + d4 = {lateral:g} m, expected 0 (pitch joints in a plane through "
            "the base axis)"
        )
    check.zero(row5, "a", "the tool point must be on the wrist-roll axis")
    ca, sa = math.cos(row5.alpha), math.sin(row5.alpha)
    rot_x = np.array([[1.0, 0.0, 0.0], [0.0, ca, -sa], [0.0, sa, ca]])
    tool = rot_x @ _tool_point(table)
    if math.hypot(tool[0], tool[1]) > LENGTH_TOL:
        raise check.fail(
            f"tool point ({tool[0]:g}, {tool[1]:g}) m off the wrist-roll axis, expected on the axis"
        )
    return FiveDof(
        sign1=sign1,
        sign4=sign4,
        a1=row1.a,
        d1=row1.d,
        link2=check.link(row2.a, 0.0, f"row 2 ('{row2.name}')"),
        link3=check.link(row3.a, 0.0, f"row 3 ('{row3.name}')"),
        a4=row4.a,
        reach=row5.d + float(tool[2]),
        R_roll_tool=rot_x @ np.asarray(table.T_last_tool[:3, :3], dtype=float),
        offsets=tuple(row.theta for row in table.rows),
    )


def seven_dof(table: DHTable) -> SevenDof:
    """Parameters of a 7R arm with a shoulder point (axes 2, 3) and a spherical wrist (axes 5-7).

    Raises:
        StructureError: The table does not have that structure.
    """
    check = _Checker(table, "seven-joint (shoulder point, spherical wrist)")
    check.rows(7)
    rows = table.rows
    check.zero(rows[1], "a", "the axes of joints 2 and 3 must meet")
    for row in (rows[1], rows[4]):
        if abs(math.sin(row.alpha)) <= ANGLE_TOL:
            raise check.fail(
                f"row {row.index} ('{row.name}'): alpha = {_deg(row.alpha)}, expected an angle "
                "other than 0 or 180 deg (the next axis must not be parallel)"
            )
    check.zero(rows[4], "a", "the wrist axes 5, 6 and 7 must meet")
    check.zero(rows[5], "a", "the wrist axes 5, 6 and 7 must meet")
    check.zero(rows[5], "d", "the wrist axes 5, 6 and 7 must meet")
    return SevenDof(
        a=tuple(row.a for row in rows),
        alpha=tuple(row.alpha for row in rows),
        d=tuple(row.d for row in rows),
        offsets=tuple(row.theta for row in rows),
        T_world_base=np.array(table.T_world_base, dtype=float),
        T_last_tool=np.array(table.T_last_tool, dtype=float),
    )


#: The registered closed-form structures: (number of joints, recogniser), in the order they are
#: asked. Several structures may share a joint count; the first that fits the table wins.
CLOSED_FORMS: tuple[tuple[int, Callable[[DHTable], Structure]], ...] = (
    (2, planar2r),
    (3, offset3r),
    (5, five_dof),
)


def recognise(table: DHTable) -> Structure:
    """The structure of the table's arm: the first of :data:`CLOSED_FORMS` that fits.

    Raises:
        StructureError: No closed-form solver fits; the message says what does not fit each one
            that has the table's number of joints.
    """
    failures = []
    for dof, recogniser in CLOSED_FORMS:
        if dof != table.dof:
            continue
        try:
            return recogniser(table)
        except StructureError as err:
            failures.append(err)
    if len(failures) == 1:
        raise failures[0]
    if failures:
        raise StructureError(table.name, "closed-form", "; ".join(err.mismatch for err in failures))
    counts = sorted({dof for dof, _ in CLOSED_FORMS})
    raise StructureError(
        table.name,
        "closed-form",
        f"{table.dof} joints; closed-form solvers exist for "
        + ", ".join(str(c) for c in counts)
        + " joints (2: planar, 3: yaw + 2 pitch, 5: yaw + 3 pitch + roll)",
    )
