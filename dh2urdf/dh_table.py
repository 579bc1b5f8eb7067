"""DH table values: a row per joint, the whole table with its base and tool, all in SI units.

Conventions (``convention`` of a table):

- ``"standard"`` (Denavit-Hartenberg, Spong): ``T_{i-1,i} = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``;
- ``"modified"`` (Craig): ``T_{i-1,i} = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``, the
  row ``i`` holding ``alpha_{i-1}`` and ``a_{i-1}``.

A row may add Hayati's tilt ``beta`` (a rotation about the y axis of the frame its twist leaves,
for a joint axis nearly parallel to its neighbour's, where plain DH moves the common normal
arbitrarily far; :mod:`kin.calibration` fits it): ``Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)
Ry(beta_i)`` (standard) and ``Rx(alpha_{i-1}) Ry(beta_i) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``
(modified). ``beta = 0`` (the default) is plain DH.

For a revolute joint the DH angle is ``theta + direction * q`` (``theta`` is the offset); for a
prismatic one the DH length is ``d + direction * q`` (``d`` is the offset) and ``theta`` is fixed.
``direction`` is 1 unless the row reverses its joint (-1: the joint turns or slides the other
way, as the Robotics Toolbox's ``flip``); the limits are always those of ``q``.

The other values a table holds are here too, frozen like its rows: a row's :class:`Housing` and
:class:`AllowedContact` (read by :mod:`dh2urdf.link_volumes`) and the table's
:class:`NamedState` (read by :mod:`dh2urdf.table_states`); the modules that read and use them
import this one, never the other way round.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from .drive_section import JointDrive
from .exceptions import TableError
from .joint_cap import MAX_JOINTS
from .link_meshes import LinkMesh
from .table_values import MAX_ANGLE, MAX_LENGTH
from .transforms import rot_x, rot_y, rot_z, translation

Convention = Literal["standard", "modified"]
JointType = Literal["revolute", "prismatic"]


@dataclass(frozen=True)
class Housing:
    """A flat-ended cylinder fixed in DH frame ``i`` of its row.

    Attributes:
        start: Centre of one end face, in DH frame ``i`` [m] (3,).
        end: Centre of the other end face, in DH frame ``i`` [m] (3,).
        radius: Cylinder radius [m].
    """

    start: tuple[float, float, float]
    end: tuple[float, float, float]
    radius: float


@dataclass(frozen=True)
class AllowedContact:
    """An earlier row whose body this row's body is not checked against.

    Attributes:
        row: The earlier row (1-based).
        reason: Why the pair is not checked (one line).
    """

    row: int
    reason: str


@dataclass(frozen=True)
class NamedState:
    """A joint vector with a name.

    Attributes:
        name: The state's name (``ready``).
        q: One value per joint, base to tip [rad, or m for a prismatic joint].
    """

    name: str
    q: tuple[float, ...]


@dataclass(frozen=True)
class DHRow:
    """One row of a DH table, in meters and radians.

    Attributes:
        index: 1-based row number in the table.
        name: Joint name used in the URDF.
        joint_type: ``"revolute"`` or ``"prismatic"``.
        a: Link length [m] (``a_i`` standard, ``a_{i-1}`` modified).
        alpha: Link twist [rad] (``alpha_i`` standard, ``alpha_{i-1}`` modified).
        d: Link offset [m]; for a prismatic joint, the offset added to ``q``.
        theta: Joint angle offset [rad] added to ``q`` (revolute) or fixed angle (prismatic).
        lower: Lower limit of the joint variable ``q`` [rad] or [m].
        upper: Upper limit of the joint variable ``q`` [rad] or [m].
        velocity: Velocity limit [rad/s] or [m/s].
        effort: Effort limit [N m] or [N].
        acceleration: Acceleration limit [rad/s^2] or [m/s^2], or None when the table gives
            none (path timing then uses its default).
        mass: Mass of the link this row moves [kg], or None (placeholder inertial).
        radius: Radius of the row's segments [m] (and of the link's primitive for ``mass``), or
            None (:data:`~dh2urdf.link_volumes.DEFAULT_RADIUS`); see :mod:`dh2urdf.link_volumes`.
        radius_a: Radius of the row's ``a`` segment [m], or None (``radius``).
        radius_d: Radius of the row's ``d`` segment [m], or None (``radius``).
        housings: Cylinders fixed in DH frame ``i`` (motor housings, offset tubes).
        allowed_contacts: Earlier rows whose bodies this row's is not checked against.
        meshes: Meshes fixed in DH frame ``i`` (:mod:`dh2urdf.link_meshes`).
        continuous: A revolute joint without limits (a URDF ``continuous`` joint): its limits
            are [-pi, pi], every angle having a copy there; the solvers wrap into them.
        direction: 1, or -1 for a reversed joint: the DH angle is ``theta + direction * q``
            (revolute), the DH length ``d + direction * q`` (prismatic) [1].
        beta: Hayati's tilt [rad] about the y axis after the twist (module docstring); 0: plain DH.
    """

    index: int
    name: str
    joint_type: JointType
    a: float
    alpha: float
    d: float
    theta: float
    lower: float
    upper: float
    velocity: float
    effort: float
    acceleration: float | None = None
    mass: float | None = None
    radius: float | None = None
    radius_a: float | None = None
    radius_d: float | None = None
    housings: tuple[Housing, ...] = ()
    allowed_contacts: tuple[AllowedContact, ...] = ()
    meshes: tuple[LinkMesh, ...] = ()
    continuous: bool = False
    direction: int = 1
    beta: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.beta, bool) or not math.isfinite(self.beta):
            raise TableError(
                "<DHRow>",
                f"expected a finite angle, got {self.beta!r}: leave beta out for plain DH",
                self.index,
                "beta",
            )
        if self.direction not in (1, -1) or isinstance(self.direction, bool):
            raise TableError(
                "<DHRow>",
                f"expected 1 or -1, got {self.direction!r}: write direction = -1 for a joint "
                "that moves the other way, else leave it out",
                self.index,
                "direction",
            )
        bound = MAX_ANGLE if self.joint_type == "revolute" else MAX_LENGTH
        if not -bound <= self.lower <= self.upper <= bound:
            raise TableError(
                "<DHRow>",
                f"expected lower <= upper within +-{bound:g}, got [{self.lower!r}, {self.upper!r}]",
                self.index,
                "limits",
            )

    def dh_values(self, q: float) -> tuple[float, float]:
        """The row's full DH angle [rad] and length [m] at joint value ``q`` [rad] or [m].

        Revolute: ``(theta + direction * q, d)``; prismatic: ``(theta, d + direction * q)``.
        """
        if self.joint_type == "revolute":
            return self.theta + self.direction * q, self.d
        return self.theta, self.d + self.direction * q

    def transform(self, convention: Convention, q: float) -> np.ndarray:
        """``T_{i-1,i}`` (4x4, [m]) of the row at joint value ``q`` [rad] or [m], its tilt included."""
        theta, d = self.dh_values(q)
        return dh_link_transform(convention, self.a, self.alpha, d, theta, self.beta)


def _readonly(matrix: np.ndarray) -> np.ndarray:
    out = np.array(matrix, dtype=float)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class DHTable:
    """A serial arm described by DH rows, with optional fixed base and tool transforms.

    Attributes:
        name: Robot name (file stem of the table).
        description: One line saying what the arm is.
        source: Where the numbers come from (paper, table, datasheet).
        convention: ``"standard"`` or ``"modified"``.
        rows: The joint rows, base to tip.
        T_world_base: Fixed transform from the URDF root to DH frame 0 (4x4, [m]).
        T_last_tool: Fixed transform from the last DH frame to the tool frame (4x4, [m]).
        path: File the table was read from, if any.
        drives: Stepper drives of some joints (``[drives]`` section), in row order.
        base_meshes: Meshes fixed in DH frame 0 (``[[base_mesh]]``, :mod:`dh2urdf.link_meshes`).
        states: Named joint vectors (``[states]``, :mod:`dh2urdf.table_states`).
    """

    name: str
    description: str
    source: str
    convention: Convention
    rows: tuple[DHRow, ...]
    T_world_base: np.ndarray = field(default_factory=lambda: _readonly(np.eye(4)))
    T_last_tool: np.ndarray = field(default_factory=lambda: _readonly(np.eye(4)))
    path: str | None = None
    drives: tuple[JointDrive, ...] = ()
    base_meshes: tuple[LinkMesh, ...] = ()
    states: tuple[NamedState, ...] = ()

    def __post_init__(self) -> None:
        if len(self.rows) > MAX_JOINTS:
            raise TableError(
                self.path or self.name,
                f"{len(self.rows)} joints; at most {MAX_JOINTS} are supported",
                None,
                "joints",
            )
        object.__setattr__(self, "T_world_base", _readonly(self.T_world_base))
        object.__setattr__(self, "T_last_tool", _readonly(self.T_last_tool))

    @property
    def dof(self) -> int:
        """Number of joints."""
        return len(self.rows)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Joint names, base to tip."""
        return tuple(row.name for row in self.rows)

    @property
    def directions(self) -> np.ndarray:
        """Per joint, 1.0, or -1.0 where the row reverses its joint (:attr:`DHRow.direction`)."""
        return np.array([float(row.direction) for row in self.rows])

    @property
    def lower(self) -> np.ndarray:
        """Lower joint limits [rad] or [m]."""
        return np.array([row.lower for row in self.rows])

    @property
    def upper(self) -> np.ndarray:
        """Upper joint limits [rad] or [m]."""
        return np.array([row.upper for row in self.rows])


def dh_link_transform(
    convention: Convention, a: float, alpha: float, d: float, theta: float, beta: float = 0.0
) -> np.ndarray:
    """Transform of one DH row with its full angle ``theta`` [rad] and length ``d`` [m].

    ``beta`` [rad]: Hayati's tilt about y after the twist (module docstring). Used for the
    DH-style ``[base]`` and ``[tool]`` rows of a table file and by :meth:`DHRow.transform`.
    """
    if convention == "standard":
        out = rot_z(theta) @ translation(z=d) @ translation(x=a) @ rot_x(alpha)
        return out @ rot_y(beta) if beta else out
    twist = rot_x(alpha) @ rot_y(beta) if beta else rot_x(alpha)
    return twist @ translation(x=a) @ rot_z(theta) @ translation(z=d)
