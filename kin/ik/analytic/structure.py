"""What the closed-form structures share: DH-table checks, link vectors, DH frame 0, SevenDof.

Each closed-form structure is a plug-in module (:mod:`.closed_form_structure` says what one
provides; :mod:`.registry` lists them): it recognises its tables with a :class:`Checker`, which
names the row and parameter that does not fit (:class:`~kin.ik.exceptions.StructureError`), and
reads everything its solver uses (link lengths, offsets, signs) from the table, so an arm of the
same structure with other numbers works unchanged. Targets arrive in the world frame;
:class:`BaseFrame` brings them into DH frame 0.

:class:`SevenDof` (seven joints, axes 2 and 3 meeting at a shoulder point, axes 5-7 at a wrist
centre: humanoid7) is redundant: not a registered closed form, the numeric solver solves it in
closed form for chosen joint-1 angles (:mod:`.seven_dof`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
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


@dataclass(frozen=True, eq=False)
class BaseFrame:
    """DH frame 0 seen from the world (the URDF root): brings world targets into frame 0.

    Attributes:
        T_world_base: Fixed transform from the world to DH frame 0 (4x4, [m]).
        identity: Whether it is the identity (then nothing is converted).
    """

    T_world_base: np.ndarray = field(repr=False)
    identity: bool = field(init=False)
    _inverse: np.ndarray = field(init=False, repr=False)
    _rows: tuple[tuple[float, ...], ...] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        base = np.asarray(self.T_world_base, dtype=float)
        inverse = np.linalg.inv(base)
        object.__setattr__(self, "identity", bool(np.array_equal(base, np.eye(4))))
        object.__setattr__(self, "_inverse", inverse)
        object.__setattr__(self, "_rows", tuple(tuple(r) for r in inverse[:3, :].tolist()))

    @classmethod
    def of(cls, table: DHTable) -> BaseFrame:
        """The table's ``T_world_base``."""
        return cls(np.array(table.T_world_base, dtype=float))

    def point(self, p: Sequence[float]) -> list[float]:
        """A world point [m] in frame 0."""
        if self.identity:
            return list(p)
        x, y, z = p
        return [r[0] * x + r[1] * y + r[2] * z + r[3] for r in self._rows]

    def rotation(self, r: Sequence[Sequence[float]]) -> list[list[float]]:
        """A world rotation (rows) in frame 0: ``R_0_world R``."""
        if self.identity:
            return [list(row) for row in r]
        return [
            [b[0] * r[0][j] + b[1] * r[1][j] + b[2] * r[2][j] for j in range(3)] for b in self._rows
        ]

    def vector_to_world(self, v: Sequence[float]) -> tuple[float, float, float]:
        """A frame-0 direction in the world: ``R_world_0 v``."""
        if self.identity:
            x, y, z = v
            return x, y, z
        w = np.asarray(self.T_world_base, dtype=float)[:3, :3] @ np.asarray(v, dtype=float)
        return float(w[0]), float(w[1]), float(w[2])

    def points(self, positions: np.ndarray) -> np.ndarray:
        """World points (N, 3) [m] in frame 0."""
        if self.identity:
            return positions
        return positions @ self._inverse[:3, :3].T + self._inverse[:3, 3]

    def rotations(self, rotations: np.ndarray) -> np.ndarray:
        """World rotations (N, 3, 3) in frame 0."""
        if self.identity:
            return rotations
        return self._inverse[:3, :3] @ rotations

    def vectors_to_world(self, vectors: np.ndarray) -> np.ndarray:
        """Frame-0 directions (N, 3) in the world."""
        if self.identity:
            return vectors
        return vectors @ np.asarray(self.T_world_base, dtype=float)[:3, :3].T


@dataclass(frozen=True)
class SevenDof:
    """Seven revolute joints with a shoulder point and a spherical wrist (redundant: joint 1 free).

    The axes of joints 2 and 3 meet at the shoulder point (``a2 = 0``, ``alpha2`` not 0 or 180 deg)
    and the axes of joints 5, 6 and 7 at the wrist centre (``a5 = a6 = d6 = 0``, ``alpha5`` not 0 or
    180 deg). Joint 1 and the elbow (joint 4) are general. For a given joint-1 angle the rest is a 6R
    arm with a spherical wrist: closed form, up to 8 branches (:mod:`.seven_dof`).

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


def near(value: float, expected: float, tol: float) -> bool:
    """Whether ``|value - expected| <= tol``."""
    return abs(value - expected) <= tol


def angle_near(value: float, expected: float) -> bool:
    """Whether two angles [rad] are equal modulo ``2 pi`` within :data:`ANGLE_TOL`."""
    return abs(math.remainder(value - expected, 2 * math.pi)) <= ANGLE_TOL


def deg(value: float) -> str:
    """An angle [rad] in degrees, for messages."""
    return f"{math.degrees(value):g} deg"


def refuse_tilts(table: DHTable, solver: str) -> None:
    """Raise when a row carries Hayati's tilt ``beta`` (:mod:`dh2urdf.dh_table`).

    Every closed form (and its compiled twin) reads the four DH values of each row: a tilted
    row is an arm none of them describes. The idealised route (:mod:`.idealised`) snaps a tilt
    within its angle tolerance and polishes on the true chain; a larger one is solved
    numerically.

    Raises:
        StructureError: The first tilted row, named.
    """
    for row in table.rows:
        if row.beta != 0.0:
            raise StructureError(
                table.name,
                solver,
                f"row {row.index} ('{row.name}'): beta = {deg(row.beta)}, expected 0 (a closed "
                "form solves plain DH rows, without Hayati's tilt)",
            )


class Checker:
    """Checks a table against a structure; its errors name the row and parameter.

    A table with a tilted row (``beta``) fits no structure: :func:`refuse_tilts` on creation.
    """

    def __init__(self, table: DHTable, solver: str):
        refuse_tilts(table, solver)
        self.table = table
        self.solver = solver

    def fail(self, mismatch: str) -> StructureError:
        """The error naming ``mismatch`` (to raise)."""
        return StructureError(self.table.name, self.solver, mismatch)

    def rows(self, count: int) -> None:
        """Standard DH, ``count`` revolute joints."""
        if self.table.convention != "standard":
            raise self.fail(f"convention is '{self.table.convention}', expected 'standard'")
        self.revolute(count)

    def revolute(self, count: int) -> None:
        """``count`` revolute joints (either convention)."""
        if self.table.dof != count:
            raise self.fail(f"{self.table.dof} joints, expected {count}")
        for row in self.table.rows:
            if row.joint_type != "revolute":
                raise self.fail(
                    f"row {row.index} ('{row.name}') is {row.joint_type}, expected revolute"
                )

    def alpha(self, row: DHRow, choices: tuple[float, ...]) -> float:
        """The one of ``choices`` [rad] that ``row.alpha`` equals."""
        for value in choices:
            if angle_near(row.alpha, value):
                return value
        wanted = " or ".join(deg(v) for v in choices)
        raise self.fail(
            f"row {row.index} ('{row.name}'): alpha = {deg(row.alpha)}, expected {wanted}"
        )

    def zero(self, row: DHRow, field: str, why: str) -> None:
        """``row.<field>`` is 0 [m] (``why`` says what needs it)."""
        value = getattr(row, field)
        if not near(value, 0.0, LENGTH_TOL):
            raise self.fail(
                f"row {row.index} ('{row.name}'): {field} = {value:g} m, expected 0 ({why})"
            )

    def link(self, x: float, y: float, where: str) -> Link:
        """The in-plane link vector ``(x, y)`` [m], of non-zero length."""
        length = math.hypot(x, y)
        if length <= LENGTH_TOL:
            raise self.fail(f"{where}: zero link length, expected a link of non-zero length")
        return Link(length, math.atan2(y, x))


def tool_point(table: DHTable) -> np.ndarray:
    """The tool origin in the last DH frame [m]."""
    return np.asarray(table.T_last_tool[:3, 3], dtype=float)


def seven_dof(table: DHTable) -> SevenDof:
    """Parameters of a 7R arm with a shoulder point (axes 2, 3) and a spherical wrist (axes 5-7).

    Raises:
        StructureError: The table does not have that structure.
    """
    check = Checker(table, "seven-joint (shoulder point, spherical wrist)")
    check.rows(7)
    rows = table.rows
    check.zero(rows[1], "a", "the axes of joints 2 and 3 must meet")
    for row in (rows[1], rows[4]):
        if abs(math.sin(row.alpha)) <= ANGLE_TOL:
            raise check.fail(
                f"row {row.index} ('{row.name}'): alpha = {deg(row.alpha)}, expected an angle "
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
