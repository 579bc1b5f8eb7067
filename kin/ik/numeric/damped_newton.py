"""Damped Newton (Levenberg-Marquardt) iterations on Pinocchio, clamped to the joint limits.

The fast path of the numeric solver: from a good starting joint vector, a few steps

    dq = z + J^T (J J^T + lambda I)^-1 (e - J z),    q <- clip(q + dq, lower, upper)

reach the target. ``e`` is the tool error in world-aligned axes at the tool origin
(``p_target - p`` [m] and ``log3(R_target R^T)`` [rad]), ``J`` the matching
``LOCAL_WORLD_ALIGNED`` frame Jacobian (position rows only for a position-only target), ``z`` a
pull toward a preferred posture that the null space of ``J`` keeps off the task (only while
``|e|`` is above ``posture_until``: the pull's second-order drift of the tool would make the last
steps converge linearly), and ``lambda = damping + error_damping * |e|^2`` the
Levenberg-Marquardt damping. A joint that the clamp stops at a limit while the step pushes it
outward is frozen (its column removed) and the step recomputed once: the other joints take over
its share. A run on a ``leash`` looks for the solution near its start only: it gives up as soon
as it has moved farther than that from the start.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from operator import le, sub

import numpy as np
import pinocchio as pin

from kin._native import twin

_twin = twin(
    "_damped_step"
)  # the step's error and linear algebra in C (kin/_native/ik/numeric/_damped_step.c)
if _twin is not None:
    _compiled_advance, _compiled_step, _compiled_error = (
        _twin.advance,
        _twin.damped_step,
        _twin.pose_error,
    )
else:  # pragma: no cover - built with a compiler; else NumPy / SciPy / Pinocchio
    _compiled_step = _compiled_error = _compiled_advance = None

#: Whether the compiled twin of the step's linear algebra is built.
COMPILED = _compiled_step is not None


def _numpy_solve_spd(matrix: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, int]:
    try:
        return np.linalg.solve(matrix, rhs), 0
    except np.linalg.LinAlgError:
        return rhs, 1


def _numpy_syrk(alpha: float, a: np.ndarray, beta: float, c: np.ndarray) -> np.ndarray:
    product = np.dot(a, a.T)
    if alpha != 1.0:
        product *= alpha
    product += beta * c
    return product


#: ``(syrk, posv)``: LAPACK through SciPy (about 6 us faster per step than ``np.linalg.solve``),
#: loaded on the first damped Newton run so that ``import kin.ik`` does not pay SciPy's import.
_LINALG: tuple = ()


#: ``(syrk, posv)`` in NumPy alone (no import to wait for; a few microseconds slower per step).
NUMPY_LINALG = (_numpy_syrk, _numpy_solve_spd)

#: Expected time to import SciPy's linear algebra [s] (about 0.15 s measured on a 2-core machine).
LINALG_COST = 0.25


def linalg_within(affordable: bool) -> tuple:
    """The steps' ``(syrk, posv)``: SciPy's when loaded or ``affordable`` (then loaded now).

    Else NumPy's (an import in a background thread would hold the interpreter lock for longer
    than a short budget): a solver built with ``prepare`` imports SciPy's, outside any call.
    """
    if _LINALG:
        return _LINALG
    return _linalg() if affordable else NUMPY_LINALG


def load_linalg() -> float:
    """Load the linear algebra of the steps now (once per process); the time it took [s]."""
    if _LINALG:
        return 0.0
    start = time.perf_counter()
    _linalg()
    return time.perf_counter() - start


def _linalg() -> tuple:
    """``(syrk, posv)``, SciPy's BLAS / LAPACK when installed, else NumPy (imported once)."""
    global _LINALG
    try:
        from scipy.linalg import blas, lapack
    except ImportError:  # pragma: no cover - SciPy comes with osqp
        _LINALG = NUMPY_LINALG
        return _LINALG

    def posv(upper: np.ndarray, rhs: np.ndarray) -> tuple[np.ndarray, int]:
        """Solve with a symmetric positive definite matrix given by its upper triangle."""
        _, x, info = lapack.dposv(upper, rhs)
        return x, info

    _LINALG = (blas.dsyrk, posv)
    return _LINALG


_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


@dataclass(frozen=True)
class NewtonOutcome:
    """Result of one damped Newton run.

    Attributes:
        q: Final joint vector [rad], inside the limits.
        converged: Both errors are below the tolerances at ``q``.
        iterations: Steps taken.
        position_error: ``|p - p_target|`` at ``q`` [m].
        rotation_error: Rotation angle to the target at ``q`` [rad] (0 if position only).
    """

    q: np.ndarray
    converged: bool
    iterations: int
    position_error: float
    rotation_error: float


def damped_newton(
    model: pin.Model,
    data: pin.Data,
    frame_id: int,
    q0: np.ndarray,
    position: np.ndarray,
    rotation: np.ndarray | None,
    max_iterations: int = 30,
    position_tol: float = 1e-6,
    rotation_tol: float = 1e-5,
    damping: float = 1e-9,
    error_damping: float = 1e-3,
    max_step: float = 0.5,
    posture: np.ndarray | None = None,
    posture_gain: float = 0.1,
    posture_until: float = 1e-2,
    patience: int | None = None,
    leash: float | None = None,
    linalg: tuple | None = None,
    compiled: bool = True,
) -> NewtonOutcome:
    """Run clamped damped Newton steps from ``q0`` toward a tool target.

    Args:
        model: Pinocchio model (its position limits are the clamp).
        data: Pinocchio data of ``model`` (overwritten; on return it holds the forward
            kinematics at the returned ``q``).
        frame_id: Index of the tool frame.
        q0: Start joint vector [rad] (clipped into the limits).
        position: Target position in the world frame [m].
        rotation: Target rotation ``R_world_tool``, or None for position only.
        max_iterations: Maximum number of steps.
        position_tol: Stop when the position error is below this [m] ...
        rotation_tol: ... and the rotation error below this [rad].
        damping: Constant Levenberg-Marquardt damping [m^2] (on ``J J^T``).
        error_damping: Damping proportional to the squared error [1].
        max_step: Largest joint change per step, infinity norm [rad].
        posture: Preferred joint vector [rad] pulled toward in the null space, or None.
        posture_gain: Fraction of the posture error pulled per step [1].
        posture_until: The pull stops once the error ``|e|`` is below this [m, rad]: the last
            steps are plain damped Newton, which converges quadratically.
        patience: Give up (``converged=False``) after this many steps in a row that do not
            halve the best error ``|e|`` so far (a start stuck at a limit or a local minimum),
            or None to always run ``max_iterations`` steps.
        leash: Give up (``converged=False``) once the joint vector, not yet converged, is
            farther than this from the clipped ``q0`` (largest joint change [rad]): the solution
            near ``q0``, if any, is not where the steps go. None: no leash.
        linalg: ``(syrk, posv)`` of the steps (:func:`linalg_within`), or None: SciPy's,
            imported now if it is not yet.
        compiled: Measure and solve a full pose's steps (the posture pull's too) with the
            compiled twin when it is built (:data:`COMPILED`): the error with its own rotation
            vector (as accurate as ``pin.log3``: within a few 1e-16 rad of the exact one, any
            angle up to a half turn) and the same Cholesky solve in one call each, about 7 us
            less per step; ``linalg`` then serves only where the twin declines (a normal
            matrix that is not positive definite).
    """
    # The loop runs a few microseconds per step: names are bound once, buffers are reused,
    # scalar work is done on Python floats (a NumPy call costs about a microsecond).
    lower, upper, lows, highs, translation, orientation, e6, e3 = _workspace(model, data, frame_id)
    q = np.array(q0, dtype=float)  # a copy: the caller's array is never returned
    values = q.tolist()
    if not (all(map(le, lows, values)) and all(map(le, values, highs))):
        q = np.minimum(np.maximum(q, lower), upper)
    full = rotation is not None
    m = 6 if full else 3
    identity = _IDENTITY[m]
    e = e6 if full else e3
    e_position = e[:3]
    e_rotation = e[3:]
    jacobian_of, log3, subtract, dot = pin.computeFrameJacobian, pin.log3, np.subtract, np.dot
    twin = _compiled_step if compiled and full else None
    error = _compiled_error if twin is not None else None
    advance = _compiled_advance if compiled else None
    empty, n = np.empty, q.shape[0]
    if twin is not None:
        # Not loaded for the twin's steps (SciPy's import costs more than whole calls).
        syrk, posv = linalg or _LINALG or NUMPY_LINALG
        solved = np.empty(q.shape[0])  # the twin's step, reused (dq is never kept)
    else:
        syrk, posv = linalg or _LINALG or _linalg()
    position_tol2, rotation_tol2 = position_tol * position_tol, rotation_tol * rotation_tol
    rotation_error2 = 0.0
    iterations = 0
    best = math.inf  # best squared error so far
    stalled = 0
    wait = max_iterations + 1 if patience is None else patience
    posture_until2 = posture_until * posture_until
    origin: list[float] = q.tolist() if leash is not None else []
    while True:
        # One Pinocchio call: forward kinematics, the tool placement and its Jacobian.
        jacobian = jacobian_of(model, data, q, frame_id, _LWA)
        measured = None if error is None else error(position, translation, rotation, orientation, e)
        if measured is not None:  # the twin's e and squared errors
            position_error2, rotation_error2 = measured
        else:
            subtract(position, translation, out=e_position)
            if full:
                e_rotation[:] = log3(dot(rotation, orientation.T))  # type: ignore[arg-type]
                ex, ey, ez, wx, wy, wz = e.tolist()
                rotation_error2 = wx * wx + wy * wy + wz * wz
            else:
                jacobian = jacobian[:3]
                ex, ey, ez = e.tolist()
            position_error2 = ex * ex + ey * ey + ez * ez
        if position_error2 < position_tol2 and rotation_error2 < rotation_tol2:
            return NewtonOutcome(
                q, True, iterations, math.sqrt(position_error2), math.sqrt(rotation_error2)
            )
        squared = position_error2 + rotation_error2
        if squared < 0.25 * best:  # the error halved: progress
            best = squared
            stalled = 0
        else:
            stalled += 1
        if (
            iterations >= max_iterations
            or stalled >= wait
            or (leash is not None and max(map(abs, map(sub, q.tolist(), origin))) > leash)
        ):
            return NewtonOutcome(
                q, False, iterations, math.sqrt(position_error2), math.sqrt(rotation_error2)
            )
        iterations += 1
        lam = damping + error_damping * squared
        if posture is None or squared < posture_until2:  # inlined: dq = J^T (J J^T + lam I)^-1 e
            z = None
            if twin is not None and twin(jacobian, e, lam, solved) == 0:
                dq = solved
            elif full:
                # Upper triangle of J J^T + lam I in one BLAS call, then a Cholesky solve.
                x, info = posv(syrk(1.0, jacobian, lam, identity), e)
                dq = dot(x, jacobian) if info == 0 else _step(jacobian, e, lam, identity, None)
            else:  # 3 x 3: the adjugate in Python floats beats a LAPACK call
                (a, b, c), (_, d, f), (_, _, g) = dot(jacobian, jacobian.T).tolist()
                a += lam
                d += lam
                g += lam
                c0, c1, c2 = d * g - f * f, c * f - b * g, b * f - c * d
                det = a * c0 + b * c1 + c * c2
                if det > 1e-300:
                    c4, c5, c8 = a * g - c * c, b * c - a * f, a * d - b * b
                    dq = dot(
                        (
                            (c0 * ex + c1 * ey + c2 * ez) / det,
                            (c1 * ex + c4 * ey + c5 * ez) / det,
                            (c2 * ex + c5 * ey + c8 * ez) / det,
                        ),
                        jacobian,
                    )
                else:
                    dq = _step(jacobian, e, lam, identity, None)
        else:
            z = posture_gain * (posture - q)
            dq = _step(jacobian, e, lam, identity, z, twin)
        bound = max_step if squared > 1e-4 else 0.0  # far from the target: bound the step
        stepped = empty(n)
        inside = -1 if advance is None else advance(dq, bound, q, lower, upper, stepped)
        if inside < 0:  # the twin's arithmetic in Python (inlined ``_bound``)
            if bound:
                values = dq.tolist()
                scale = max(max(values), -min(values))
                if scale > max_step:
                    dq *= max_step / scale
            stepped = q + dq
            values = stepped.tolist()
            inside = all(map(le, lows, values)) and all(map(le, values, highs))
        if not inside:
            # Freeze the joints the clamp stops while the step pushes them outward.
            blocked = (stepped < lower) | (stepped > upper)
            jacobian = jacobian * ~blocked  # a copy with the blocked columns zeroed
            if z is None:
                if twin is not None and twin(jacobian, e, lam, solved) == 0:
                    dq = solved
                else:
                    x, info = posv(syrk(1.0, jacobian, lam, identity), e)
                    dq = dot(x, jacobian) if info == 0 else _step(jacobian, e, lam, identity, None)
            else:
                z[blocked] = 0.0
                dq = _step(jacobian, e, lam, identity, z, twin)
            _bound(dq, max_step)
            stepped = np.minimum(np.maximum(q + dq, lower), upper)
        q = stepped


def _workspace(model: pin.Model, data: pin.Data, frame_id: int) -> tuple:
    """Limits (arrays and lists), tool placement views into ``data`` and error buffers.

    Cached per ``data`` (and its model and frame): the views stay valid while ``data`` lives (the
    cache holds it) and every Jacobian call on ``data`` refreshes them.
    """
    entry = _WORKSPACES.get(id(data))
    if entry is not None and entry[0] is data and entry[1] is model and entry[2] == frame_id:
        return entry[3]
    lower = model.lowerPositionLimit.copy()
    upper = model.upperPositionLimit.copy()
    pose = data.oMf[frame_id]
    work = (
        lower,
        upper,
        lower.tolist(),
        upper.tolist(),
        pose.translation,
        pose.rotation,
        np.empty(6),
        np.empty(3),
    )
    if len(_WORKSPACES) >= 32:  # many short-lived solvers: forget the old ones
        _WORKSPACES.clear()
    _WORKSPACES[id(data)] = (data, model, frame_id, work)
    return work


_WORKSPACES: dict[int, tuple] = {}


_IDENTITY = {3: np.eye(3), 6: np.eye(6)}


def _bound(dq: np.ndarray, max_step: float) -> None:
    """Scale ``dq`` in place so that its largest entry is at most ``max_step`` [rad]."""
    scale = max(map(abs, dq.tolist()))
    if scale > max_step:
        dq *= max_step / scale


def _step(
    jacobian: np.ndarray,
    e: np.ndarray,
    lam: float,
    identity: np.ndarray,
    z: np.ndarray | None,
    twin: object = None,
) -> np.ndarray:
    """``z + J^T (J J^T + lam I)^-1 (e - J z)`` through a Cholesky solve (``twin``'s if given)."""
    rhs = e if z is None else e - jacobian @ z
    if twin is not None:
        dq = np.empty(jacobian.shape[1])
        if twin(jacobian, rhs, lam, dq) == 0:  # type: ignore[operator]
            return dq if z is None else dq + z
    normal = jacobian @ jacobian.T + lam * identity
    x, info = (_LINALG or NUMPY_LINALG)[1](normal, rhs)
    if info != 0:  # not positive definite (no damping at an exact singularity)
        x = np.linalg.lstsq(normal, rhs, rcond=None)[0]
    dq = x @ jacobian
    return dq if z is None else dq + z
