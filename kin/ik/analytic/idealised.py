"""Closed forms despite rounding: the idealised table a structure fits, and the polish of its answers.

Makers' URDFs round: example-robot-data's xArm7 writes 1.5708 for pi/2, which moves its tool by a
few micrometers and breaks every exact structure test. :func:`idealise` snaps the twists within
:data:`ANGLE_TOLERANCE` of a multiple of 90 deg to it, a row's Hayati tilt ``beta`` within it to
zero (:mod:`dh2urdf.dh_table`: no closed form takes a tilted row), and the lengths ``a``, ``d``
below :data:`LENGTH_TOLERANCE` to zero; the idealised arm is accepted only if its tool stays within
:data:`FK_TOLERANCE` of the true one over sampled joint vectors (so that its answers start inside
Newton's basin). A closed form then solves the idealised geometry and :func:`polish` moves each
branch onto the true chain with Gauss-Newton steps on Pinocchio's FK of the true model (to about
1e-13), where the judge verifies it as any other answer. Joint limits are not used by the polish:
a branch outside them is kept as rejected, as for an exact structure.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from dh2urdf import DHTable
from kin._native import twin
from kin.batch_fk import batch_forward_kinematics

#: Largest change of a twist snapped to a multiple of 90 deg [rad].
ANGLE_TOLERANCE = 1e-4
#: Largest ``|a|`` or ``|d|`` snapped to zero [m].
LENGTH_TOLERANCE = 1e-5
#: Largest tool displacement of the idealised arm over the sampled joint vectors [m].
FK_TOLERANCE = 1e-3
#: Gauss-Newton steps of a polish, and the error it stops at [m, rad].
POLISH_STEPS = 12
POLISH_TOLERANCE = 1e-13
#: A polish that no longer lowers its error once below this [m, rad] stops there (Gauss-Newton
#: converges quadratically so near a root: the rest is a residual no step removes).
STALL = 1e-8


@dataclass(frozen=True, eq=False)
class Idealised:
    """An idealised table and how far its tool strays from the true one.

    Attributes:
        table: The table with its twists and small lengths snapped.
        deviation: Largest tool displacement from the true table over sampled q [m].
        changes: One line per snapped value (``"row 2 alpha 1.5708 -> pi/2"``).
        position_bound: Bound on the tool displacement from the true table at every q [m]
            (:func:`snap_bounds`).
        rotation_bound: Bound on the tool rotation from the true table at every q [rad].
    """

    table: DHTable
    deviation: float
    changes: tuple[str, ...]
    position_bound: float
    rotation_bound: float


def idealise(table: DHTable) -> Idealised | None:
    """The idealised table, or None when nothing is within the tolerances (or it strays)."""
    rows = []
    changes: list[str] = []
    for row in table.rows:
        alpha = _snap_angle(row.alpha)
        a = 0.0 if 0.0 < abs(row.a) < LENGTH_TOLERANCE else row.a
        d = row.d
        if row.joint_type == "revolute" and 0.0 < abs(row.d) < LENGTH_TOLERANCE:
            d = 0.0
        beta = 0.0 if abs(row.beta) < ANGLE_TOLERANCE else row.beta
        for name, old, new in (
            ("alpha", row.alpha, alpha),
            ("beta", row.beta, beta),
            ("a", row.a, a),
            ("d", row.d, d),
        ):
            if old != new:
                changes.append(f"row {row.index} {name} {old!r} -> {new!r}")
        rows.append(dataclasses.replace(row, alpha=alpha, beta=beta, a=a, d=d))
    if not changes:
        return None
    ideal = dataclasses.replace(table, rows=tuple(rows))
    rng = np.random.default_rng(0)
    q = rng.uniform(table.lower, table.upper, size=(256, table.dof))
    true = batch_forward_kinematics(table, q)[:, :3, 3]
    snapped = batch_forward_kinematics(ideal, q)[:, :3, 3]
    deviation = float(np.linalg.norm(true - snapped, axis=1).max())
    if not deviation <= FK_TOLERANCE:
        return None
    return Idealised(ideal, deviation, tuple(changes), *snap_bounds(table, ideal))


def snap_bounds(true: DHTable, ideal: DHTable) -> tuple[float, float]:
    """Bounds on how far the ideal table's tool is from the true one, at any joint vector.

    Snap one value at a time: a twist or a tilt changed by ``e`` [rad] turns the rest of the
    chain by ``e`` about an axis no farther from the tool than the arm's reach ``R`` (every ``|a|``
    and ``|d|``, a prismatic joint's travel and the tool offset), so the tool moves at most ``e R``
    and turns at most ``e``; a length changed by ``e`` [m] moves it at most ``e``. Summed over
    the snapped values (the triangle inequality): ``sum(e R) + sum(e)`` [m], ``sum(e)`` [rad].

    Returns:
        The position bound [m] and the rotation bound [rad].
    """
    reach = float(np.linalg.norm(true.T_last_tool[:3, 3]))
    turned = moved = 0.0
    for row, snapped in zip(true.rows, ideal.rows):
        travel = max(abs(row.lower), abs(row.upper)) if row.joint_type == "prismatic" else 0.0
        reach += abs(row.a) + abs(row.d) + travel
        turned += abs(math.remainder(row.alpha - snapped.alpha, 2.0 * math.pi))
        turned += abs(row.beta - snapped.beta)
        moved += abs(row.a - snapped.a) + abs(row.d - snapped.d)
    return turned * reach + moved, turned


def _snap_angle(angle: float) -> float:
    quarter = math.pi / 2
    nearest = round(angle / quarter) * quarter
    if angle != nearest and abs(angle - nearest) < ANGLE_TOLERANCE:
        return math.remainder(nearest, 2 * math.pi) if abs(nearest) > math.pi else nearest
    return angle


def polish(
    model: pin.Model,
    data: pin.Data,
    frame_id: int,
    q: np.ndarray,
    position: np.ndarray,
    rotation: np.ndarray | None,
    compiled: bool = True,
    give_up: float = math.inf,
) -> np.ndarray:
    """``q`` moved onto the target on the true chain by Gauss-Newton steps (no limits).

    A full pose's steps are measured and solved by damped Newton's compiled twin when it is built
    and ``compiled`` (:mod:`kin.ik.numeric._damped_step`: the rotation vector, the minimum-norm
    step ``J^T (J J^T)^-1 e`` by Cholesky); when that does not reach :data:`POLISH_TOLERANCE` (a
    Jacobian too near a singularity for the normal equations), the least-squares steps of NumPy
    (SVD) run from ``q`` again. A position's steps are the twin's minimum-norm steps too; fewer
    joints than equations step by the normal equations ``(J^T J) s = J^T e``.

    ``give_up`` [m], [rad]: when ``q`` starts farther from the target than this (the largest
    component of the position error and of the rotation vector), no step is taken and the answer
    is NaN (a branch of an idealised arm's pose projection that far cannot reach the pose).

    Returns the best joint vector found (``q`` itself when no step helps).
    """
    use_twin = compiled and _damped_step is not None
    # The minimum-norm step J^T (J J^T)^-1 e needs a Jacobian of full row rank: fewer joints
    # than equations (a full pose on fewer than six, a position on fewer than three) step by
    # Gauss-Newton's normal equations (J^T J) s = J^T e instead, solved by the same twin.
    overdetermined = len(q) < (3 if rotation is None else 6)
    # A position, or a pose on fewer joints, steps as NumPy's least squares would (full rank):
    # a residual the twin's steps stall at is not searched again by NumPy's.
    six_or_more = rotation is not None and not overdetermined
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    best = q
    for twin_steps in (True, False) if use_twin else (False,):
        best, best_error = q, math.inf
        current = np.array(q, dtype=float)
        error = np.empty(6)
        step = np.empty(current.shape[0])
        for _ in range(POLISH_STEPS):
            jacobian = pin.computeFrameJacobian(model, data, current, frame_id, world)
            pose = data.oMf[frame_id]
            if (
                twin_steps
                and rotation is not None
                and _pose_error(position, pose.translation, rotation, pose.rotation, error)
            ):
                size = max(map(abs, error.tolist()))
            else:
                if rotation is None:
                    error = position - pose.translation
                    jacobian = jacobian[:3]
                else:
                    error = np.concatenate(
                        (position - pose.translation, pin.log3(rotation @ pose.rotation.T))
                    )
                size = max(map(abs, error.tolist()))
            if give_up < math.inf and best_error == math.inf and not size <= give_up:
                return np.full(len(q), np.nan)
            if size < best_error:
                best, best_error = current, size  # current is replaced, never changed in place
            elif best_error < STALL:
                break  # a residual the chain cannot remove (a near miss of a branch): no progress
            if size < POLISH_TOLERANCE:
                break
            if not (twin_steps and _twin_step(jacobian, error, step, overdetermined)):
                step = np.linalg.lstsq(jacobian, error, rcond=None)[0]
            current = current + step
        if best_error < POLISH_TOLERANCE or (best_error < STALL and not six_or_more):
            break  # the twin's steps reached the target (or a residual): NumPy's are not needed
    return best


def _twin_step(jacobian: np.ndarray, error: np.ndarray, out: np.ndarray, normal: bool) -> bool:
    """A Gauss-Newton step into ``out`` by the twin: minimum-norm, or by the normal equations."""
    if normal:
        return bool(_damped_step(jacobian.T @ jacobian, jacobian.T @ error, 0.0, out) == 0)
    return bool(_damped_step(jacobian, error, 0.0, out) == 0)


# damped Newton's compiled twin (kin/_native/ik/numeric/_damped_step.c)
_twin = twin("_damped_step")
if _twin is not None:
    _damped_step, _pose_error = _twin.damped_step, _twin.pose_error
else:  # pragma: no cover - NumPy's least squares and Pinocchio's log3 alone
    _damped_step = _pose_error = None
