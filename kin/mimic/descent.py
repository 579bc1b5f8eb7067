"""IK of a chain with mimic joints: damped least squares on the coupled Jacobian, seeded starts.

The stages take a frozen :class:`CoupledChain` (the table's model, the coupling, the limits of
the independent joints and the judge), not the arm (:class:`kin.mimic.arm.MimicArm` builds one
per search). Units: joint values [rad] or [m], lengths [m], angles [rad].
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from ..ik.judge import POSITION_TOLERANCE, ROTATION_TOLERANCE
from ..ik.result import IKSolution
from ..robot_model import RobotModel

__all__ = ["CoupledChain", "MimicSearch", "descend", "search"]

#: Largest change of one joint in one descent step [rad] or [m].
_MAX_STEP = 0.5
#: Steps after which a descent that has not cut its residual by 10 % gives up (a local minimum).
_STALL = 15


@dataclass(frozen=True, eq=False)
class MimicSearch:
    """What one IK search of a :class:`~kin.mimic.arm.MimicArm` found.

    Attributes:
        answer: The first joint vector judged on target inside every joint's limits, or None.
        best: The attempt nearest the target (by the search's own residual), as judged.
        starts: Starts tried (the seed first, then random ones).
        iterations: Damped least-squares steps taken, all starts together.
    """

    answer: IKSolution | None
    best: IKSolution
    starts: int
    iterations: int


@dataclass(frozen=True, eq=False)
class CoupledChain:
    """A chain with mimic joints as its search sees it.

    Attributes:
        robot: The table's model (one variable per joint of the chain): the Jacobians.
        expand: The independent joints' values to every joint's (the coupling, offsets included).
        coupling: ``d q_all / d q`` (joints of the chain) x (independent joints).
        lower: Lower limits of the independent joints [rad] or [m]; ``upper`` the upper ones.
        judge: ``judge(q, goal, oriented)``: ``q`` measured against ``goal`` (``T_base_tip``
            [m]) by the URDF's mimic model, with every joint's limits.
    """

    robot: RobotModel
    expand: Callable[[np.ndarray], np.ndarray]
    coupling: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    judge: Callable[[np.ndarray, pin.SE3, bool], IKSolution]


def search(
    chain: CoupledChain,
    goal: pin.SE3,
    oriented: bool,
    first: np.ndarray,
    restarts: int,
    max_iter: int,
    rng_seed: int,
    timeout: float | None,
    near: Callable[[], npt.ArrayLike] | None = None,
) -> MimicSearch:
    """:func:`descend` from ``first``, then ``near`` and random starts, until one is on target.

    Args:
        chain: The chain.
        goal: Target ``T_base_tip`` [m]; its rotation counts when ``oriented``.
        oriented: Whether the goal's rotation counts.
        first: The first start [rad] or [m], inside the limits.
        restarts: Random starts after it (seeded by ``rng_seed``).
        max_iter: Damped least-squares steps per start.
        rng_seed: Seed of the random starts.
        timeout: No new start after this time [s] (the first one always runs); None: all.
        near: Gives the starts (k, n) to try after ``first``, before random ones, within the
            ``restarts`` (samples whose poses are near the goal: :mod:`.starts`); called when
            ``first`` fails. None: random ones only.
    """
    ahead = np.zeros((0, len(first)))
    started = time.perf_counter()
    rng = np.random.default_rng(rng_seed)
    best, best_residual, iterations, starts = first, math.inf, 0, 0
    for start in range(restarts + 1):
        if start and timeout is not None and time.perf_counter() - started > timeout:
            break
        starts += 1
        if start == 1 and near is not None:
            ahead = np.asarray(near(), dtype=float).reshape(-1, len(first))
        if start == 0:
            q = first
        elif start <= len(ahead):
            q = np.clip(ahead[start - 1], chain.lower, chain.upper)
        else:
            q = rng.uniform(chain.lower, chain.upper)
        q, steps = descend(chain, q, goal, oriented, max_iter)
        iterations += steps
        answer = chain.judge(q, goal, oriented)
        if (
            answer.within_limits
            and answer.position_error < POSITION_TOLERANCE
            and (answer.rotation_error is None or answer.rotation_error < ROTATION_TOLERANCE)
        ):
            return MimicSearch(answer, answer, starts, iterations)
        residual = answer.position_error + (answer.rotation_error or 0.0)
        if residual < best_residual:
            best, best_residual = q, residual
    return MimicSearch(None, chain.judge(best, goal, oriented), starts, iterations)


def descend(
    chain: CoupledChain, q: np.ndarray, goal: pin.SE3, oriented: bool, max_iter: int
) -> tuple[np.ndarray, int]:
    """Levenberg-Marquardt steps from ``q`` inside the limits; the last ``q`` and the steps.

    The residual is the tip's pose error ``log6(T_tip^-1 T_goal)`` (LOCAL), or its position
    error in base axes when not ``oriented``; a step is kept when it lowers the residual
    (then the damping shrinks), else the damping grows; a step moves no joint more than
    :data:`_MAX_STEP`. A joint at a limit that the step would push further out is held there
    for that step, the step solved again over the others (an active set), so the others take
    its share instead of the step being clipped. The descent stops on target, after
    ``max_iter`` steps, or stuck
    (the damping past 1e8, or the residual cut by less than 10 % in :data:`_STALL` steps).
    """
    model = chain.robot.model
    data = model.createData()
    tool = model.getFrameId(chain.robot.tool_frame)
    coupling = chain.coupling
    frame = pin.LOCAL if oriented else pin.LOCAL_WORLD_ALIGNED
    rows = 6 if oriented else 3
    nq = coupling.shape[1]
    # The coupling is affine: every joint's value is ``coupling @ q`` plus the mimic offsets,
    # the same numbers ``chain.expand`` gives (one product per step instead of a column loop).
    shift = chain.expand(np.zeros(nq))
    regular = 1e-9 * np.eye(nq)

    def expand(q: np.ndarray) -> np.ndarray:
        return coupling @ q + shift

    def residual(q: np.ndarray) -> np.ndarray:
        pin.framesForwardKinematics(model, data, expand(q))
        if oriented:
            return pin.log6(data.oMf[tool].actInv(goal)).vector
        return goal.translation - data.oMf[tool].translation

    error = residual(q)
    norm = float(np.linalg.norm(error))
    damping = 1e-3
    history = [norm]
    for step_count in range(1, max_iter + 1):
        stalled = len(history) > _STALL and norm > 0.9 * history[-_STALL - 1]
        if norm < 1e-12 or damping > 1e8 or stalled:
            return q, step_count - 1
        full = expand(q)
        jacobian = pin.computeFrameJacobian(model, data, full, tool, frame)[:rows] @ coupling
        step = _step(jacobian, error, damping, regular)
        # a joint at a limit that the step pushes further out is held there: the step is
        # solved again without it, so the others take its share instead of being clipped
        held = ((q <= chain.lower) & (step < 0.0)) | ((q >= chain.upper) & (step > 0.0))
        if held.any() and not held.all():
            free = ~held
            step = np.zeros(nq)
            step[free] = _step(jacobian[:, free], error, damping, regular[np.ix_(free, free)])
        largest = float(np.abs(step).max())
        if largest > _MAX_STEP:
            step *= _MAX_STEP / largest
        trial = np.clip(q + step, chain.lower, chain.upper)
        trial_error = residual(trial)
        trial_norm = float(np.linalg.norm(trial_error))
        if trial_norm < norm:
            q, error, norm = trial, trial_error, trial_norm
            damping = max(damping / 5.0, 1e-9)
        else:
            damping *= 10.0
        history.append(norm)
    return q, max_iter


def _step(
    jacobian: np.ndarray, error: np.ndarray, damping: float, regular: np.ndarray
) -> np.ndarray:
    """The Levenberg-Marquardt step (Marquardt's diagonal scaling) of ``jacobian``, ``error``."""
    normal = jacobian.T @ jacobian
    return np.linalg.solve(
        normal + damping * (np.diag(np.diag(normal)) + regular), jacobian.T @ error
    )
