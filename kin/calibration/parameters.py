"""The parameter model of a calibration: what is estimated, named, with its unit.

Per joint row, the row's four DH values (``theta``: the joint's zero offset, ``d``, ``a``,
``alpha``) and, where the row's joint axis is parallel to the next one (plain DH then moves the
common normal arbitrarily far for a tilt of a hundredth of a degree), Hayati's extra tilt ``beta``
about the row's y axis: ``Rz(theta + q) Tz(d) Tx(a) Rx(alpha) Ry(beta)`` (standard) or
``Rx(alpha) Ry(beta) Tx(a) Rz(theta + q) Tz(d)`` (modified). Then the measurement frame:
``base`` (6: the pose of DH frame 0 in the tracker's frame, a small shift and rotation vector
in DH frame 0's axes after a reference pose, so that ``base.z`` and ``base.rz`` act along and about
the first joint's axis), and the measured point: ``tool`` (6, for full poses: position in the
last DH frame and a small rotation about ``R0_tool``) or ``marker<k>`` (3 each, for positions).

The vector ``x`` holds absolute values [m] / [rad] for DH values and tool or marker positions, and
increments for the base and the tool's rotation vector.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from dh2urdf import DHTable

#: |sin(alpha)| of a row below which its joint axis counts as parallel to the next (0.57 deg).
PARALLEL_SINE = 1e-2
ROW_KINDS = ("theta", "d", "a", "alpha", "beta")
AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Parameter:
    """One estimated value.

    Attributes:
        name: ``"<joint>.<kind>"``, ``"base.rz"``, ``"tool.x"`` or ``"marker1.y"``.
        group: Joint name, ``"base"``, ``"tool"`` or ``"marker<k>"``.
        kind: ``theta``, ``d``, ``a``, ``alpha``, ``beta``, ``t`` (translation) or ``r`` (rotation).
        row: 0-based joint row of a row parameter, else None.
        axis: 0..2 for a translation or rotation component, else 0.
        angle: True for an angle [rad], False for a length [m].
    """

    name: str
    group: str
    kind: str
    row: int | None
    axis: int
    angle: bool


@dataclass(frozen=True, eq=False)
class ParameterModel:
    """The parameters of one calibration and the references their increments are taken from.

    Attributes:
        table: The nominal DH table (its base and tool are replaced by the estimated ones).
        parameters: The parameters, in the order of ``x``.
        beta_rows: 0-based rows with a ``beta`` term (joint axis parallel to the next).
        markers: Number of measured points per row; 0 for full poses (a tool frame).
        T0_base: Reference pose of DH frame 0 in the measurement frame (4x4) [m].
        R0_tool: Reference rotation of the tool in the last DH frame (3x3; poses only).
    """

    table: DHTable
    parameters: tuple[Parameter, ...]
    beta_rows: tuple[int, ...]
    markers: int
    T0_base: np.ndarray
    R0_tool: np.ndarray

    @property
    def names(self) -> tuple[str, ...]:
        """The parameter names, in the order of ``x``."""
        return tuple(p.name for p in self.parameters)

    def index(self, name: str) -> int:
        """Position of parameter ``name`` in ``x``."""
        return self.names.index(name)

    def recentred(self, x: np.ndarray) -> tuple[ParameterModel, np.ndarray]:
        """The same arm with the references moved to ``x``'s pose and zero increments in ``x``."""
        x = np.array(x, dtype=float)
        T0_base = self.T_measurement_base(x)
        x[self.slice("base", "t") + self.slice("base", "r")] = 0.0
        R0_tool = self.R0_tool
        if self.markers == 0:
            tool_r = self.slice("tool", "r")
            R0_tool = self.R0_tool @ Rotation.from_rotvec(x[tool_r]).as_matrix()
            x[tool_r] = 0.0
        return dataclasses.replace(self, T0_base=T0_base, R0_tool=R0_tool), x

    def slice(self, group: str, kind: str) -> list[int]:
        """Indices of ``group``'s parameters of ``kind`` (e.g. ``("base", "r")``)."""
        return [i for i, p in enumerate(self.parameters) if p.group == group and p.kind == kind]

    def T_measurement_base(self, x: np.ndarray) -> np.ndarray:
        """Pose of DH frame 0 in the measurement frame (4x4) [m]."""
        step = np.eye(4)
        step[:3, :3] = Rotation.from_rotvec(x[self.slice("base", "r")]).as_matrix()
        step[:3, 3] = x[self.slice("base", "t")]
        return np.asarray(self.T0_base @ step)

    def T_last_tool(self, x: np.ndarray) -> np.ndarray:
        """Pose of the tool in the last DH frame (4x4) [m]: the measured frame, or marker 1."""
        out = np.eye(4)
        if self.markers == 0:
            out[:3, :3] = (
                self.R0_tool @ Rotation.from_rotvec(x[self.slice("tool", "r")]).as_matrix()
            )
            out[:3, 3] = x[self.slice("tool", "t")]
        else:
            out[:3, :3] = self.R0_tool
            out[:3, 3] = self.marker(x, 1)
        return out

    def marker(self, x: np.ndarray, k: int) -> np.ndarray:
        """Position of marker ``k`` (1-based) in the last DH frame [m]."""
        return np.asarray(x[self.slice(f"marker{k}", "t")])

    def row_values(self, x: np.ndarray, row: int) -> dict[str, float]:
        """``theta``, ``d``, ``a``, ``alpha``, ``beta`` of a 0-based row [rad] / [m]."""
        values = {"beta": self.table.rows[row].beta}
        for i, p in enumerate(self.parameters):
            if p.row == row:
                values[p.kind] = float(x[i])
        return values


def parallel_rows(table: DHTable) -> tuple[int, ...]:
    """0-based rows whose joint axis is parallel to the next joint's (they get ``beta``).

    Standard rows ``i < n``: ``|sin(alpha_i)| < PARALLEL_SINE``; modified rows ``i >= 2``:
    ``|sin(alpha_{i-1})|`` small (a modified row holds the twist before its joint). Also every
    row whose nominal table already has a tilt (a calibrated table calibrated again).
    """
    rows = table.rows
    if table.convention == "standard":
        parallel = [i for i in range(len(rows) - 1) if abs(math.sin(rows[i].alpha)) < PARALLEL_SINE]
    else:
        parallel = [i for i in range(1, len(rows)) if abs(math.sin(rows[i].alpha)) < PARALLEL_SINE]
    return tuple(i for i, row in enumerate(rows) if i in parallel or row.beta != 0.0)


def build_model(
    table: DHTable, markers: int, T_measurement_base: np.ndarray, T_last_tool: np.ndarray
) -> tuple[ParameterModel, np.ndarray]:
    """The parameter model of ``table`` and its starting vector.

    Args:
        table: The nominal DH table (SI units).
        markers: Measured points per row (>= 1), or 0 for full poses.
        T_measurement_base: First guess of DH frame 0 in the measurement frame (4x4) [m].
        T_last_tool: First guess of the tool (marker 1: its position) in the last DH frame [m].

    Returns:
        The model and ``x`` of the nominal rows with the guessed base and tool.
    """
    betas = parallel_rows(table)
    params: list[Parameter] = []
    values: list[float] = []
    for i, row in enumerate(table.rows):
        for kind in ROW_KINDS:
            if kind == "beta" and i not in betas:
                continue
            params.append(
                Parameter(
                    f"{row.name}.{kind}", row.name, kind, i, 0, kind in ("theta", "alpha", "beta")
                )
            )
            values.append(float(getattr(row, kind)))
    groups = [("base", True)] + (
        [("tool", True)] if markers == 0 else [(f"marker{k}", False) for k in range(1, markers + 1)]
    )
    for group, rotates in groups:
        for j in range(3):
            params.append(Parameter(f"{group}.{AXES[j]}", group, "t", None, j, False))
        if rotates:
            for j in range(3):
                params.append(Parameter(f"{group}.r{AXES[j]}", group, "r", None, j, True))
    base = np.asarray(T_measurement_base, dtype=float)
    tool = np.asarray(T_last_tool, dtype=float)
    for group, rotates in groups:
        origin = np.zeros(3) if group == "base" else tool[:3, 3]
        values += list(origin) + ([0.0, 0.0, 0.0] if rotates else [])
    model = ParameterModel(table, tuple(params), betas, markers, base.copy(), tool[:3, :3].copy())
    return model, np.array(values)
