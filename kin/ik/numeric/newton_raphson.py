"""The paper's Newton-Raphson IK (000, section III.B), kept to reproduce its Table IX.

Position only, no joint limits, the right pseudo-inverse of the 3 x 7 position Jacobian:

    dq = J^T (J J^T)^-1 e,    q <- q + dq,    stop when |e| < tol or after 1000 iterations.

Units follow the paper: the error ``e = t - r(q)`` is in centimeters and the default stop is
``|e| < 1e-5 cm`` (= 1e-7 m); joint values are radians. The result is then judged like every
other solver (Pinocchio, ``1e-5 m``, limits): the paper's method does not know the limits, so
its answer is often on target but outside them (``status="outside_limits"``).

At a singular configuration (the stretched home pose ``q = 0``: all joints on one line, no
velocity along it) ``J J^T`` is singular; the plain inverse would return a huge or NaN step.
There the step uses the SVD pseudo-inverse, which drops the singular direction (relative cut
``1e-10``): the arm moves in the directions it can, leaves the singularity, and the next steps
are plain Newton-Raphson again. If the error lies entirely in the singular direction (a target
on the stretched line itself) the step is zero (below 1e-12 rad) and the solver stops with ``status="singular"``.
"""

from __future__ import annotations

import time

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import RobotModel
from kin.configuration import default_seed, seed_inside

from ..result import IKResult, IKSolution, Status
from .numeric_target import NumericTarget, measure

CM = 0.01  # [m]

#: Relative singular value below which a direction counts as singular.
SINGULAR_CUT = 1e-10


def newton_raphson(
    robot: RobotModel,
    position: npt.ArrayLike,
    q0: npt.ArrayLike | None = None,
    tol_cm: float = 1e-5,
    max_iterations: int = 1000,
) -> IKResult:
    """Solve a position target with the paper's Newton-Raphson (no limits, cm units).

    Args:
        robot: The robot.
        position: Target tool position in the world frame [m].
        q0: Initial joint vector [rad], moved into the limits; the stretched home ``q = 0`` if
            None (or the nearest joint vector to it inside the limits).
        tol_cm: Stop when ``|e| < tol_cm`` [cm] (the paper: 1e-5).
        max_iterations: The paper's cap, 1000.

    Returns:
        An :class:`IKResult` with ``solver="nr"``: ``success`` only when Pinocchio measures the
        final ``q`` on target (1e-5 m) and inside the limits; otherwise the final ``q`` is in
        ``rejected`` and ``status`` says why (``outside_limits``, ``singular``,
        ``not_found``).
    """
    start = time.perf_counter()
    target = NumericTarget.from_arrays(position)
    model, data = robot.model, robot.model.createData()
    fid = model.getFrameId(robot.tool_frame)
    if q0 is None:
        q = default_seed(robot)
    else:
        q = seed_inside(robot, np.array(q0, dtype=float).reshape(robot.nq))
    target_cm = target.position / CM
    iterations = singular_steps = 0
    stalled = False
    while True:
        jacobian = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)[:3] / CM
        e = target_cm - data.oMf[fid].translation / CM
        if np.linalg.norm(e) < tol_cm or iterations >= max_iterations:
            break
        normal = jacobian @ jacobian.T
        singular_values = np.linalg.svd(jacobian, compute_uv=False)
        if singular_values[-1] <= SINGULAR_CUT * singular_values[0]:
            singular_steps += 1
            dq = np.linalg.pinv(jacobian, rcond=SINGULAR_CUT) @ e
        else:
            dq = jacobian.T @ np.linalg.solve(normal, e)
        iterations += 1
        if np.abs(dq).max() < 1e-12:
            stalled = True
            break
        q = q + dq
    elapsed = time.perf_counter() - start
    verdict = measure(robot, data, q, target)
    solution = IKSolution(q, "", verdict.within_limits, verdict.position_error, None)
    on_target = verdict.on_target()
    note = (
        f" ({singular_steps} singular step(s) through the SVD pseudo-inverse)"
        if singular_steps
        else ""
    )
    if on_target and verdict.within_limits:
        return IKResult(
            True,
            "nr",
            "ok",
            f"converged in {iterations} iterations{note}",
            (solution,),
            iterations=iterations,
            time=elapsed,
            method="newton_raphson",
        )
    if on_target:
        message = (
            f"on target in {iterations} iterations but outside the joint limits: "
            + _violations(robot, q)
            + note
        )
        status: Status = "outside_limits"
    elif stalled:
        message = (
            f"stopped at a singular configuration after {iterations} iterations: the error "
            f"({verdict.position_error:.3g} m) lies in the direction the arm cannot move"
        )
        status = "singular"
    else:
        message = (
            f"no convergence in {iterations} iterations; error {verdict.position_error:.3g} m"
            + note
        )
        status = "not_found"
    return IKResult(
        False, "nr", status, message, (), (solution,), iterations=iterations, time=elapsed
    )


def _violations(robot: RobotModel, q: np.ndarray) -> str:
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    parts = [
        f"{name} {np.degrees(v):.1f} deg (limits {np.degrees(lo):.0f}..{np.degrees(hi):.0f})"
        for name, v, lo, hi in zip(robot.joint_names, q, lower, upper)
        if v < lo or v > hi
    ]
    return ", ".join(parts)
