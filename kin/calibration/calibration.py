"""Calibrate a DH arm from measurements: first guess, identifiability, fit, errors, cross-check.

:func:`calibrate` places the nominal arm in the measurement frame (the base and the tool or
markers alone, from a closed-form first guess), decides which parameters the data determine
(:mod:`kin.calibration.identifiability`), fits those (:mod:`kin.calibration.fit`), computes
every parameter's standard deviation from the covariance ``s^2 (J^T J)^-1`` (``s^2`` the weighted
residuals' variance), and repeats the whole calibration k times on k - 1 of k folds of the rows to
predict the fold left out (cross-validated errors).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from dh2urdf import DHTable

from ..audit.se3_fit import fit_base_tool
from ..batch_fk import batch_forward_kinematics
from .errors import Errors, errors
from .exceptions import CalibrationError
from .fit import LOSSES, Noise, fit, residuals
from .identifiability import RANK_TOLERANCE, Identifiability, identify
from .measurements import Measurements, read_measurements
from .parameters import ParameterModel, build_model

#: Range [rad] / [m] below which a joint counts as held still in the data.
STILL = 1e-6


@dataclass(frozen=True, eq=False)
class Calibration:
    """A calibrated arm and how well it fits.

    Attributes:
        table: The nominal table.
        measurements: The data it was fitted to.
        model: The parameter model (its references at the fitted rotations).
        start: Parameters of the nominal arm placed in the measurement frame (best base and tool).
        x: The fitted parameters.
        std: Standard deviation of each parameter (NaN where not identifiable) [m] / [rad].
        identifiability: The rank decision.
        before: Errors of ``start`` on the data; ``after``: of ``x``.
        cross_validated: Errors of each row predicted by a calibration without its fold, or None.
        folds: Number of folds (0: no cross-validation).
        evaluations: Residual evaluations of the main fit.
        seconds: Wall-clock time of the main fit (not of the cross-validation) [s].
        noise: The noise the residuals were weighted by.
        loss: The loss function.
    """

    table: DHTable
    measurements: Measurements
    model: ParameterModel
    start: np.ndarray
    x: np.ndarray
    std: np.ndarray
    identifiability: Identifiability
    before: Errors
    after: Errors
    cross_validated: Errors | None
    folds: int
    evaluations: int
    seconds: float
    noise: Noise
    loss: str


def first_guess(table: DHTable, data: Measurements) -> tuple[np.ndarray, np.ndarray]:
    """DH frame 0 in the measurement frame and the tool (marker 1) in the last DH frame [m].

    Poses: the closed-form base and tool fit of the audit (:func:`kin.audit.se3_fit.fit_base_tool`).
    Points: the rotation and shift that best map the nominal tool points onto marker 1's
    (Kabsch, scipy's ``Rotation.align_vectors``), the nominal tool.
    """
    nominal = batch_forward_kinematics(table, data.q)
    if data.rotations is not None:
        measured = np.tile(np.eye(4), (data.count, 1, 1))
        measured[:, :3, :3] = data.rotations
        measured[:, :3, 3] = data.points[:, 0]
        found = fit_base_tool(nominal, measured)
        return found.T_ref_base @ table.T_world_base, table.T_last_tool @ found.T_tool_ref
    mine, theirs = nominal[:, :3, 3], data.points[:, 0]
    out = np.eye(4)
    if data.count >= 3:
        rotation, _ = Rotation.align_vectors(theirs - theirs.mean(0), mine - mine.mean(0))
        out[:3, :3] = rotation.as_matrix()
    out[:3, 3] = theirs.mean(0) - out[:3, :3] @ mine.mean(0)
    return out @ table.T_world_base, np.array(table.T_last_tool)


def preference_order(
    model: ParameterModel, data: Measurements
) -> tuple[list[int], dict[str, str], tuple[int, ...]]:
    """Parameter indices by preference, the reasons for still joints and their zero offsets.

    The measurement frame and the tool (or markers), unknown by nature, come first: they absorb
    what no joint motion separates from them (the first joint's zero and ``d``, the last row's
    values), so that the rows change only where the data determines them.
    """
    still = {i for i in range(data.q.shape[1]) if np.ptp(data.q[:, i]) < STILL}
    rows, others, last = [], [], []
    reasons = {}
    for i, p in enumerate(model.parameters):
        if p.row is None:
            others.append(i)
        elif p.row in still and p.kind == "theta":
            last.append(i)
            reasons[p.name] = f"joint '{p.group}' never moves in the data"
        else:
            rows.append(i)
    return others + rows, reasons, tuple(last)


def _placed(table: DHTable, data: Measurements, noise: Noise) -> tuple[ParameterModel, np.ndarray]:
    """The model and the nominal arm's parameters with the best base and tool (or markers)."""
    base, tool = first_guess(table, data)
    model, x = build_model(table, data.markers, base, tool)
    J = residuals(model, x, data, noise, jacobian=True)[1]
    assert J is not None
    placing = [i for i, p in enumerate(model.parameters) if p.row is None]
    free = identify(J, model.names, placing).identifiable
    x = fit(model, x, free, data, noise).x
    return model.recentred(x)


def needed_rows(markers: int, parameters: int) -> int:
    """Fewest rows whose values outnumber ``parameters`` (``markers`` 0: full poses)."""
    per_row = 3 * max(markers, 1) + (3 if markers == 0 else 0)
    return -(-(parameters + 1) // per_row)


#: Configurations of the rich data set that counts the parameters an arm's calibration identifies.
RICH_ROWS = 64


def probe_tool(table: DHTable) -> np.ndarray:
    """The nominal tool moved 3 cm off the last joint's axis (4x4) [m].

    A marker on that axis hides the last joint's zero, which a real marker seldom does.
    """
    tool = np.array(table.T_last_tool)
    tool[:2, 3] += 0.03
    return tool


def identifiable_count(table: DHTable, data: Measurements, noise: Noise, tolerance: float) -> int:
    """Parameters identifiable from rich data of the same kind (joints still in ``data`` still).

    Uniform configurations within the limits (seed 0) of the nominal arm; the rows ``data`` needs
    to determine them all are at least this count over the values per row.
    """
    q = np.random.default_rng(0).uniform(table.lower, table.upper, (RICH_ROWS, table.dof))
    still = np.ptp(data.q, axis=0) < STILL
    q[:, still] = data.q[0, still]
    rotations = None if data.rotations is None else np.tile(np.eye(3), (RICH_ROWS, 1, 1))
    rich = Measurements(
        q, np.zeros((RICH_ROWS, max(data.markers, 1), 3)), rotations, np.arange(RICH_ROWS)
    )
    model, x = build_model(table, data.markers, np.array(table.T_world_base), probe_tool(table))
    J = residuals(model, x, rich, noise, jacobian=True)[1]
    assert J is not None
    order, _, excluded = preference_order(model, rich)
    return identify(J, model.names, order, tolerance, excluded=excluded).rank


def _fit_once(
    table: DHTable, data: Measurements, noise: Noise, loss: str, tolerance: float
) -> tuple[ParameterModel, np.ndarray, np.ndarray, Identifiability, int, float]:
    wanted = identifiable_count(table, data, noise, tolerance)
    if data.count < needed_rows(data.markers, wanted):
        raise CalibrationError(
            f"{data.count} rows are too few for the {wanted} parameters this arm's calibration "
            f"identifies: measure at least {needed_rows(data.markers, wanted)} rows (3 times that is better)",
            data.path,
        )
    model, start = _placed(table, data, noise)
    J = residuals(model, start, data, noise, jacobian=True)[1]
    assert J is not None
    order, reasons, still = preference_order(model, data)
    found = identify(J, model.names, order, tolerance, reasons, still)
    clock = time.perf_counter()
    result = fit(model, start, found.identifiable, data, noise, loss)
    seconds = time.perf_counter() - clock
    return model, start, result.x, found, result.evaluations, seconds


def _std(
    model: ParameterModel, x: np.ndarray, data: Measurements, noise: Noise, free: np.ndarray
) -> np.ndarray:
    r, J = residuals(model, x, data, noise, jacobian=True)
    assert J is not None
    Jf = J[:, free]
    dof = max(len(r) - Jf.shape[1], 1)
    variance = float(r @ r) / dof
    scale = np.linalg.norm(Jf, axis=0)
    inner = np.linalg.pinv((Jf / scale).T @ (Jf / scale))
    out = np.full(len(x), np.nan)
    out[free] = np.sqrt(variance * np.diag(inner)) / scale
    return out


def _cross_validated(
    table: DHTable, data: Measurements, noise: Noise, loss: str, tolerance: float, folds: int
) -> Errors | None:
    order = np.random.default_rng(0).permutation(data.count)
    position = np.zeros((data.count, max(data.markers, 1)))
    rotation = None if data.rotations is None else np.zeros(data.count)
    for k in range(folds):
        held = order[k::folds]
        train = np.setdiff1d(order, held)
        try:
            model, _, x, *_ = _fit_once(table, data.subset(train), noise, loss, tolerance)
        except CalibrationError:
            return None  # too few rows in a fold
        found = errors(model, x, data.subset(held))
        position[held] = found.position
        if rotation is not None:
            assert found.rotation is not None
            rotation[held] = found.rotation
    return Errors(position, rotation)


def calibrate(
    robot: DHTable | str | Path,
    measurements: Measurements | str | Path,
    *,
    unit: str = "m",
    degrees: bool = False,
    noise: Noise | None = None,
    loss: str = "linear",
    folds: int = 5,
    tolerance: float = RANK_TOLERANCE,
    base: str | None = None,
    tip: str | None = None,
) -> Calibration:
    """Calibrate ``robot`` from ``measurements``.

    Args:
        robot: A DH table, a table file, a shipped robot name or a URDF (its chain as a table,
            from link ``base`` to link ``tip``).
        measurements: Measurements, or a CSV / JSON-lines file (:mod:`kin.calibration.measurements`).
        unit: Length unit of a measurement file (``m``, ``cm``, ``mm``).
        degrees: A measurement file's angles are in degrees.
        noise: Measurement noise weighting positions against rotations (default 0.05 mm, 0.01 deg).
        loss: ``"linear"`` (Levenberg-Marquardt) or a robust loss: ``soft_l1``, ``huber``, ``cauchy``.
        folds: Folds of the cross-validation (0: none).
        tolerance: Relative rank tolerance of the identifiability decision [1].
        base: A URDF's base link (default: its root).
        tip: A URDF's tip link (default: its single leaf).

    Raises:
        CalibrationError: Bad measurements, or too few of them for the identifiable parameters.
    """
    if loss not in LOSSES:
        raise CalibrationError(f"unknown loss '{loss}': choose one of {', '.join(LOSSES)}")
    if isinstance(robot, DHTable):
        table = robot
    else:
        from ..audit.audited_table import load_audited_table

        table = load_audited_table(str(robot), base, tip).table
    data = (
        measurements
        if isinstance(measurements, Measurements)
        else read_measurements(measurements, table, unit, degrees)
    )
    if data.q.shape[1] != table.dof:
        raise CalibrationError(
            f"{data.q.shape[1]} joint values per row; the robot has {table.dof} joints", data.path
        )
    noise = noise or Noise()
    model, start, x, found, evaluations, seconds = _fit_once(table, data, noise, loss, tolerance)
    std = _std(model, x, data, noise, found.identifiable)
    crossed = _cross_validated(table, data, noise, loss, tolerance, folds) if folds >= 2 else None
    return Calibration(
        table,
        data,
        model,
        start,
        x,
        std,
        found,
        errors(model, start, data),
        errors(model, x, data),
        crossed,
        folds if crossed is not None else 0,
        evaluations,
        seconds,
        noise,
        loss,
    )
