"""Partial poses: a masked pose, a free tool axis, a full pose on an arm of fewer than six joints.

The targets real tasks give constrain fewer than six components of the tool pose: a SCARA's
position and yaw, a drill's position and axis (the roll about it free), any pose with a mask. An
arm of fewer than six joints asked for a full pose reaches it only when the pose lies in its
(lower-dimensional) set of poses. All of these are solved here, for any arm, by one method:

1. **Closed-form candidates** where the arm has a closed form (:mod:`.analytic.registry`): its
   branches for the pose (a mask keeps the given values of the free components); for an
   :class:`~kin.ik.AxisTarget`, the branches of the seed's roll (the seed's tool turned onto the
   axis by the smallest rotation: the answer nearest the seed), and of a grid of
   :data:`ROLL_GRID` rolls over a turn when those give none or when every roll is asked. An
   arm whose structure takes positions only (planar 2R, offset 3R) gives the branches of the
   position.
2. **Weighted least squares** (Levenberg-Marquardt, clamped to the joint limits) on the
   constrained components: from each off-target candidate, then from the seed, then from
   :data:`RANDOM_STARTS` random joint vectors inside the limits (a seeded draw: the same call gives
   the same answer on any machine; the timeout is only a cap, reported as ``timeout``). The
   residual is
   ``e = (p_target - p, w log3(R_target R^T))`` in world axes ([m], and [rad] weighted by
   :data:`ROTATION_WEIGHT` [m/rad]), the rows the mask keeps; for an axis target the rotation
   rows are ``w theta n`` with ``theta`` the angle from the tool axis to the target axis and
   ``n`` the unit vector of their cross product (the roll about the axis takes no part). Where
   the pose is not reachable this converges to the nearest pose the arm reaches (in that
   weighted sense), which the failure reports: ``not_found`` (the starts searched; no claim that
   the pose is unreachable) or ``timeout`` (the cap came first).

Every returned solution is measured by Pinocchio's forward kinematics on the constrained
components only (:class:`PartialTask`): position error ``|e_p|`` [m] and rotation error
``|e_r|`` [rad] of the kept components (the angle between the axes for an axis target), below
the judge's tolerances (:data:`~kin.ik.judge.POSITION_TOLERANCE`,
:data:`~kin.ik.judge.ROTATION_TOLERANCE`), and inside the joint limits. The result names the
free components (:attr:`IKResult.free`).
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import KinError, RobotModel, as_joint_vector
from kin.configuration import default_seed, seed_inside

from .exceptions import StructureError, TargetError
from .judge import POSITION_TOLERANCE, ROTATION_TOLERANCE
from .limit_rule import wrap_into
from .numeric.damped_newton import damped_newton
from .reach import reach_bound
from .result import IKResult, IKSolution
from .target import TOOL_AXES, AxisTarget, PoseTarget, PositionTarget, axis_turn, is_partial

__all__ = ["PartialPoseIK", "PartialTask", "is_partial"]

#: Weight of the rotation rows in the least squares [m/rad]: 1 rad of tool rotation weighs as
#: 0.1 m of tool position when a pose cannot be reached and the nearest one is sought.
ROTATION_WEIGHT = 0.1

#: Roll values of an axis target tried by a closed form (evenly spaced over a turn), besides the
#: seed's roll.
ROLL_GRID = 24

#: Default cap on the time of one solve [s]: the work (:data:`RANDOM_STARTS`) decides the answer;
#: a call the cap stops first says ``timeout``.
DEFAULT_TIMEOUT = 2.0

#: Random starts of the least squares (drawn inside the limits from ``random_seed``), after the
#: closed-form candidates, the seed and the seed-table samples: the work of one search.
RANDOM_STARTS = 32

#: Levenberg-Marquardt steps per start.
MAX_ITERATIONS = 100

#: Largest joint change of one step (infinity norm) [rad].
MAX_STEP = 0.5

#: Damped Newton steps per start, and its patience (:func:`.numeric.damped_newton.damped_newton`),
#: for a full pose before the least-squares starts (:meth:`PartialPoseIK._newton_starts`).
NEWTON_ITERATIONS, NEWTON_PATIENCE = 20, 3

#: Two solutions closer than this (largest joint difference [rad]) are the same.
SAME_SOLUTION = 1e-6

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

#: The components of a pose error a mask names (the Robotics Toolbox's order).
_POSITION_ROWS = (0, 1, 2)


class PartialTask:
    """The errors and least-squares rows of one partial target (:mod:`.partial_pose`).

    Args:
        target: A :class:`~kin.ik.PoseTarget` (with or without a mask) or an
            :class:`~kin.ik.AxisTarget`, in the world frame.
    """

    def __init__(self, target: PoseTarget | AxisTarget):
        self.target = target
        self.position = target.position
        self.axis_column: int | None = None
        if isinstance(target, AxisTarget):
            self.axis_column = TOOL_AXES[target.tool_axis]
            self.rows = np.arange(6)
            self.position_rows = [0, 1, 2]
            self.rotation_rows = [3, 4, 5]
        else:
            mask = target.mask or (True,) * 6
            self.rows = np.flatnonzero(mask)
            self.position_rows = [i for i in _POSITION_ROWS if mask[i]]
            self.rotation_rows = [i for i in range(3, 6) if mask[i]]
        self.weights = np.where(self.rows >= 3, ROTATION_WEIGHT, 1.0)
        self.free = target.free

    def error(self, p: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """The unweighted error (6,): position [m] and rotation vector [rad], world axes."""
        e = np.empty(6)
        e[:3] = self.position - p
        if self.axis_column is None:
            e[3:] = pin.log3(self.target.rotation @ rotation.T)  # type: ignore[union-attr]
        else:
            e[3:] = axis_turn(rotation[:, self.axis_column], self.target.axis)  # type: ignore[union-attr]
        return e

    def errors(self, e: np.ndarray) -> tuple[float, float]:
        """Position and rotation errors [m], [rad] of the constrained components of ``e``."""
        values = e.tolist()
        position = math.hypot(*[values[i] for i in self.position_rows])  # no overflow
        rotation = math.hypot(*[values[i] for i in self.rotation_rows])
        return position, rotation

    def jacobian(
        self, e: np.ndarray, rotation: np.ndarray, frame_jacobian: np.ndarray
    ) -> np.ndarray:
        """Rows (6, nq) of ``-d e / d q`` from the tool's ``LOCAL_WORLD_ALIGNED`` Jacobian."""
        rows = frame_jacobian.copy()
        if self.axis_column is None:
            rows[3:] = pin.Jlog3(self.target.rotation @ rotation.T) @ frame_jacobian[3:]  # type: ignore[union-attr]
        else:  # the roll about the current tool axis changes nothing
            a = rotation[:, self.axis_column]
            rows[3:] = frame_jacobian[3:] - np.outer(a, a @ frame_jacobian[3:])
        return rows


class PartialPoseIK:
    """IK of partial poses of one robot: closed-form candidates, then weighted least squares.

    Args:
        robot: The robot.
        structure: Its closed-form structure (:func:`kin.ik.analytic.registry.recognise` of its
            forward table, :func:`~kin.ik.analytic.joint_directions.forward_table`), or None:
            looked up (the idealised table's when the true one misses a structure by
            rounding), none if no structure fits.
        name: The pipeline reported in :attr:`IKResult.solver`.
        samples: ``samples(position, rotation, end)``: joint vectors of the seed-table samples
            nearest a pose (``rotation`` None: nearest the position alone), tried after the seed
            and before the random starts; or None. ``end`` is the call's cap (a
            ``time.perf_counter()`` value); the samples depend on the target alone. A five-joint
            arm's poses are a thin set: a start in the right basin matters more there than
            many random ones.
        pose_candidates: ``pose_candidates(position, rotations, seed)``: the closed form's
            branches of full poses as the arm's joint vectors
            (:meth:`~kin.ik.analytic.closed_form.ClosedFormSolver.pose_candidates`: its
            idealisation, offsets and joint directions applied), or None: ``structure``'s own
            branches are used.
    """

    def __init__(
        self,
        robot: RobotModel,
        structure: Any = None,
        name: str = "numeric",
        samples: Callable[[np.ndarray, np.ndarray | None, float], np.ndarray] | None = None,
        pose_candidates: Callable[
            [np.ndarray, np.ndarray, np.ndarray], list[tuple[np.ndarray, str]]
        ]
        | None = None,
    ):
        self.robot = robot
        self.name = name
        self.samples = samples
        self.pose_candidates = pose_candidates
        self.model = robot.model
        self.data = robot.model.createData()
        self.frame_id = robot.model.getFrameId(robot.tool_frame)
        self.nq = robot.model.nq
        self.lower = robot.model.lowerPositionLimit.copy()
        self.upper = robot.model.upperPositionLimit.copy()
        self.revolute = np.array([row.joint_type == "revolute" for row in robot.table.rows])
        self.continuous = np.array([row.continuous for row in robot.table.rows], dtype=bool)
        #: Search limits: continuous joints move through pi (wrapped back after).
        self.search_lower = np.where(self.continuous, -3.0 * math.pi, self.lower)
        self.search_upper = np.where(self.continuous, 3.0 * math.pi, self.upper)
        self.structure = structure if structure is not None else _structure(robot)
        #: The structure solves the forward table (every direction 1,
        #: :mod:`.analytic.joint_directions`): its ``q'`` is ``direction * q``.
        self.directions = robot.table.directions
        self.reach = reach_bound(robot)
        self._base = np.asarray(robot.table.T_world_base, dtype=float)[:3, 3].copy()
        self._lock = threading.Lock()

    # -- the solve ------------------------------------------------------------------------------

    def solve(
        self,
        target: PoseTarget | AxisTarget,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        random_seed: int = 0,
        position_tol: float = POSITION_TOLERANCE,
        rotation_tol: float = ROTATION_TOLERANCE,
        every_roll: bool = False,
    ) -> IKResult:
        """The joint vectors inside the limits that put the tool on ``target``'s constrained components.

        Args:
            target: A pose (masked, or full on an arm of fewer than six joints) or an axis target.
            seed: Start joint vector [rad] (or [m] for prismatic joints); the solutions are
                ordered by distance to it; moved into the limits first (None: zero, or the
                nearest joint vector to it inside the limits).
            timeout: Cap on the time [s] (None: :data:`DEFAULT_TIMEOUT`); the search stops at the
                first solution after the closed-form candidates, after its starts
                (:data:`RANDOM_STARTS` random ones; ``not_found``), or at the cap (``timeout``).
            random_seed: Seed of the random starts (results are reproducible).
            position_tol: Success tolerance on the constrained position components [m].
            rotation_tol: Success tolerance on the constrained rotation components [rad].
            every_roll: For an axis target on a closed-form arm: the branches of every roll of
                the grid (:data:`ROLL_GRID` rolls over a turn) too, not only of the seed's roll
                (when that gives a solution).

        Raises:
            TargetError: A seed of the wrong size or with a value that is not finite.
        """
        start = time.perf_counter()
        budget = DEFAULT_TIMEOUT if timeout is None else timeout
        if not budget >= 0.0:
            raise TargetError(f"timeout must be a number of seconds >= 0, got {timeout!r}")
        seed_q = self._seed(seed)
        if not target.finite:
            return IKResult(False, self.name, "invalid_target", f"target is not finite: {target}")
        task = PartialTask(target)
        if task.position_rows:  # the kept position components alone may be out of reach
            offset = (target.position - self._base).tolist()
            distance = math.hypot(*[offset[i] for i in task.position_rows])
            if distance > self.reach:
                return self._failure(
                    task,
                    "out_of_reach",
                    f"target is {distance - self.reach:.4g} m beyond the arm's reach "
                    f"({self.reach:.4g} m from its base); no search",
                    (),
                    start,
                    distance - self.reach,
                )
        with self._lock:
            return self._search(
                task,
                seed_q,
                start,
                start + budget,
                random_seed,
                position_tol,
                rotation_tol,
                every_roll,
            )

    def _search(
        self,
        task: PartialTask,
        seed: np.ndarray,
        start: float,
        deadline: float,
        random_seed: int,
        position_tol: float,
        rotation_tol: float,
        every_roll: bool,
    ) -> IKResult:
        found: list[IKSolution] = []
        outside: list[IKSolution] = []
        attempts: list[tuple[float, np.ndarray]] = []  # (weighted cost, q) of the off-target ones
        method = ""
        for grid in (False, True) if sweeps(task) else (False,):
            for group in self._candidates(task, seed, grid):
                for q, label in group:
                    verdict = self._judged(task, q, label, position_tol, rotation_tol)
                    if verdict is None:
                        attempts.append((self._cost(task, q), q))
                    elif verdict.within_limits:
                        _add(found, verdict)
                    else:
                        outside.append(verdict)
                if found and not every_roll:
                    break
            if found and not every_roll:
                break
        if found:
            method = "closed_form"
        else:
            attempts.sort(key=lambda item: item[0])
            inside = [
                attempt
                for attempt in attempts
                if np.all(attempt[1] >= self.lower) and np.all(attempt[1] <= self.upper)
            ]
            if inside and getattr(self.structure, "projects", False):
                # The closed form projected the target on the arm's poses: its nearest branch
                # inside the limits is the nearest pose (a SCARA's tool cannot tilt).
                return self._unreached(task, inside[0], outside, start, 0)
            target = task.target
            full = (
                self.samples is not None and isinstance(target, PoseTarget) and target.mask is None
            )
            samples: np.ndarray | None = None
            if full and not self.continuous.any():
                hit, samples = self._newton_starts(task, seed, deadline, position_tol, rotation_tol)
                if hit is not None:
                    found.append(hit)
                    method = "damped_newton"
        if not found:
            starts = [q for _, q in attempts]
            refined = len(starts)  # the first starts: the closed form's branches off target
            starts.append(seed)
            # The samples nearest the pose (a full one; a masked one's given rotation; an axis
            # target at the seed's roll), after the seed: looked up only when it is needed.
            lazy = self.samples is not None and samples is None
            if samples is not None:
                starts.extend(samples)
            rng = np.random.default_rng(random_seed)
            randoms = list(
                rng.uniform(self.search_lower, self.search_upper, (RANDOM_STARTS, self.nq))
            )
            best: tuple[float, np.ndarray] | None = None
            tried = 0
            capped = False
            while True:
                if not starts:
                    if lazy:
                        lazy = False
                        # A mask that frees a rotation on an arm of fewer than six joints: the
                        # samples nearest the position alone (the given rotation is one of many
                        # the target allows, and most of them are off the arm's thin set).
                        rotation = (
                            None
                            if self.nq < 6
                            and len(task.rotation_rows) < 3
                            and task.axis_column is None
                            else _sweep(task, self._fk(seed)[1], False)[0][0]
                        )
                        starts.extend(self.samples(target.position, rotation, deadline))  # type: ignore[misc]
                        continue
                    if not randoms:
                        break  # the work is done
                    starts.append(randoms.pop(0))
                if time.perf_counter() > deadline:
                    capped = True
                    break
                q, cost = self._least_squares(
                    task, starts.pop(0), 0.1 * position_tol, 0.1 * rotation_tol
                )
                tried += 1
                verdict = self._judged(task, q, "", position_tol, rotation_tol)
                if verdict is not None and verdict.within_limits:
                    _add(found, verdict)
                    method = "closed_form_refined" if tried <= refined else "weighted_newton"
                    break
                if verdict is not None:
                    outside.append(verdict)
                if best is None or cost < best[0]:
                    best = (cost, q)
            if not found:
                return self._unreached(task, best, outside, start, tried, capped)
        found.sort(key=lambda s: float(np.abs(s.q - seed).sum()))
        message = f"{len(found)} solution(s)"
        return IKResult(
            True,
            self.name,
            "ok",
            message,
            tuple(found),
            tuple(outside),
            time=time.perf_counter() - start,
            method=method,
            free=task.free,
        )

    # -- pieces ---------------------------------------------------------------------------------

    def _newton_starts(
        self,
        task: PartialTask,
        seed: np.ndarray,
        deadline: float,
        position_tol: float,
        rotation_tol: float,
    ) -> tuple[IKSolution | None, np.ndarray | None]:
        """Damped Newton on a full pose from the seed, then from the samples nearest it.

        The first answer the judge finds on the pose inside the limits, else None; and the
        samples when they were looked up (the least-squares starts take them next). Damped
        Newton's steps (its compiled twin) are several times cheaper than the least-squares
        ones, and a reachable full pose needs no weighing of components.
        """
        target = task.target
        assert isinstance(target, PoseTarget) and self.samples is not None
        starts: list[np.ndarray] = [seed]
        samples: np.ndarray | None = None
        while starts:
            outcome = damped_newton(
                self.model,
                self.data,
                self.frame_id,
                starts.pop(0),
                target.position,
                target.rotation,
                max_iterations=NEWTON_ITERATIONS,
                position_tol=0.1 * position_tol,
                rotation_tol=0.1 * rotation_tol,
                patience=NEWTON_PATIENCE,
            )
            if outcome.converged:
                verdict = self._judged(task, outcome.q, "", position_tol, rotation_tol)
                if verdict is not None and verdict.within_limits:
                    return verdict, samples
            if samples is None:
                samples = self.samples(target.position, target.rotation, deadline)
                starts.extend(samples)
            if time.perf_counter() > deadline:
                break
        return None, samples

    def _seed(self, seed: npt.ArrayLike | None) -> np.ndarray:
        """The seed checked and moved into the limits (None: :func:`kin.configuration.default_seed`)."""
        if seed is None:
            return default_seed(self.robot)
        try:
            return seed_inside(self.robot, as_joint_vector(self.robot, seed))  # type: ignore[no-any-return]
        except KinError as err:
            raise TargetError(f"seed of '{self.robot.name}': {err}") from err

    def _fk(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        pin.forwardKinematics(self.model, self.data, q)
        pose = pin.updateFramePlacement(self.model, self.data, self.frame_id)
        return pose.translation.copy(), pose.rotation.copy()

    def _cost(self, task: PartialTask, q: np.ndarray) -> float:
        p, rotation = self._fk(q)
        e = task.error(p, rotation)[task.rows] * task.weights
        return float(e @ e)

    def _wrapped(self, q: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray, bool]:
        """``q`` with each revolute angle moved by 2 pi into the limits, nearest the seed.

        The closed forms' choice of copy (:func:`~.limit_rule.wrap_into`); whether
        every joint is inside its limits is then judged without their slack.
        """
        out = q.copy()
        for i in np.flatnonzero(self.revolute).tolist():
            out[i] = wrap_into(float(out[i]), float(seed[i]), self.lower[i], self.upper[i])[0]
        inside = bool(np.all(out >= self.lower) and np.all(out <= self.upper))
        return out, inside

    def _judged(
        self, task: PartialTask, q: np.ndarray, label: str, position_tol: float, rotation_tol: float
    ) -> IKSolution | None:
        """The solution ``q`` measured by Pinocchio on the constrained components; None when off target."""
        if self.continuous.any():
            q = q.copy()
            q[self.continuous] = np.remainder(q[self.continuous] + math.pi, 2.0 * math.pi) - math.pi
        p, rotation = self._fk(q)
        position_error, rotation_error = task.errors(task.error(p, rotation))
        if not (position_error < position_tol and rotation_error < rotation_tol):
            return None
        inside = bool(np.all(q >= self.lower) and np.all(q <= self.upper))
        rotation_value = rotation_error if task.rotation_rows else None
        return IKSolution(q, label, inside, position_error, rotation_value)

    def _candidates(
        self, task: PartialTask, seed: np.ndarray, grid: bool = False
    ) -> Iterator[list[tuple[np.ndarray, str]]]:
        """The closed form's branches for the target (moved into the limits nearest the seed).

        One group of branches per tool rotation, computed when the caller asks for the next. A
        target with one free rotation (an axis target's roll, a mask that frees one rotation
        component) gives the branches of one rotation (``grid`` False: the seed's roll, or the
        mask's given rotation) or of the other :data:`ROLL_GRID` - 1 rotations of a turn about
        the free axis, nearest that one first (``grid`` True, :func:`_sweep`).
        """
        structure = self.structure
        if structure is None:
            return
        kinds = structure.target_kinds
        target = task.target
        labels = structure.branch_labels
        try:
            if PoseTarget in kinds and (isinstance(target, AxisTarget) or target.mask is not None):
                rotations, names = _sweep(task, self._fk(seed)[1], grid)
                if self.pose_candidates is None:  # the structure's batch, then one group each
                    positions = np.repeat(target.position[None, :], len(rotations), axis=0)
                    raw = np.asarray(structure.solve_batch(positions, rotations), dtype=float)
                    raw = raw.reshape(len(rotations), -1, raw.shape[-1])
                for k, name in enumerate(names):
                    if self.pose_candidates is not None:  # the closed form's own branches
                        branches = self.pose_candidates(target.position, rotations[k : k + 1], seed)
                        yield self._kept(
                            [q for q, _ in branches],
                            [f"{b}, {name}" for _, b in branches],
                            seed,
                            False,
                        )
                    else:
                        yield self._kept(
                            raw[k], [f"{label}, {name}" for label in labels], seed, True
                        )
                return
            if PoseTarget in kinds and isinstance(target, PoseTarget):
                raw = np.asarray(structure.solve(target.position, target.rotation), dtype=float)
            elif PositionTarget in kinds:  # the position's branches, judged on the rest
                raw = np.asarray(structure.solve(target.position, None), dtype=float)
            else:
                return
        except (ValueError, ArithmeticError, np.linalg.LinAlgError):
            return
        yield self._kept(raw, list(labels), seed, True)

    def _kept(
        self, raw: Any, names: list[str], seed: np.ndarray, forward: bool
    ) -> list[tuple[np.ndarray, str]]:
        """The finite joint vectors of ``raw`` moved into the limits nearest the seed, named.

        ``forward``: ``raw`` is in the structure's forward table (``q' = direction * q``).
        """
        out = []
        for q, name in zip(raw, names):
            q = np.asarray(q, dtype=float) * (self.directions if forward else 1.0)
            if q.shape == (self.nq,) and np.isfinite(q).all() and np.abs(q).max() < 1e9:
                out.append((self._wrapped(q, seed)[0], name))
        return out

    def _least_squares(
        self, task: PartialTask, q0: np.ndarray, position_tol: float, rotation_tol: float
    ) -> tuple[np.ndarray, float]:
        """Levenberg-Marquardt from ``q0`` inside the (search) limits; the last q and its weighted cost."""
        lower, upper = self.search_lower, self.search_upper
        q = np.minimum(np.maximum(q0, lower), upper)
        rows, weights = task.rows, task.weights[:, None]
        model, data, frame_id = self.model, self.data, self.frame_id
        identity = np.eye(self.nq)

        def evaluate(q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, bool]:
            frame_jacobian = pin.computeFrameJacobian(model, data, q, frame_id, _LWA)
            pose = data.oMf[frame_id]
            full = task.error(pose.translation, pose.rotation)
            position_error, rotation_error = task.errors(full)
            e = full[rows] * weights[:, 0]
            jacobian = task.jacobian(full, pose.rotation, frame_jacobian)[rows] * weights
            done = position_error < position_tol and rotation_error < rotation_tol
            return e, jacobian, float(e @ e), done

        e, jacobian, cost, done = evaluate(q)
        lam = 1e-3
        for _ in range(MAX_ITERATIONS):
            if done:
                break
            normal = jacobian.T @ jacobian
            gradient = jacobian.T @ e
            improved = False
            while lam < 1e10:
                try:
                    dq = np.linalg.solve(normal + lam * identity, gradient)
                    # A joint at a bound that the step pushes further out is held there and the
                    # step taken by the others (an active set): clamping alone bends the step.
                    held = ((q <= lower) & (dq < 0.0)) | ((q >= upper) & (dq > 0.0))
                    if held.any():
                        free = ~held
                        dq = np.zeros(self.nq)
                        dq[free] = np.linalg.solve(
                            normal[np.ix_(free, free)] + lam * identity[: free.sum(), : free.sum()],
                            gradient[free],
                        )
                except np.linalg.LinAlgError:
                    lam *= 10.0
                    continue
                scale = float(np.abs(dq).max())
                if scale > MAX_STEP:
                    dq *= MAX_STEP / scale
                stepped = np.minimum(np.maximum(q + dq, lower), upper)
                e_new, jacobian_new, cost_new, done_new = evaluate(stepped)
                if cost_new < cost:
                    improved = True
                    progress = cost - cost_new
                    q, e, jacobian, cost, done = stepped, e_new, jacobian_new, cost_new, done_new
                    lam = max(lam / 3.0, 1e-12)
                    break
                lam *= 4.0
            if not improved or progress <= 1e-15 * max(cost, 1e-300) + 1e-30:
                break  # a minimum of the weighted error (the nearest reachable pose, or stuck)
        return q, cost

    def _unreached(
        self,
        task: PartialTask,
        best: tuple[float, np.ndarray] | None,
        outside: list[IKSolution],
        start: float,
        tried: int,
        capped: bool = False,
    ) -> IKResult:
        """The failure, saying what is known.

        ``timeout`` when the time cap stopped the search before its starts were done;
        ``outside_limits`` when it found the target only outside the limits; ``out_of_reach``
        when the closed form projected the target on the arm's poses (``tried`` 0: nothing to
        search); else ``not_found``, with the nearest pose the starts found.
        """
        nearest: tuple[IKSolution, ...] = ()
        what = "no pose found"
        if best is not None:
            q = best[1]
            if self.continuous.any():
                q = q.copy()
                q[self.continuous] = (
                    np.remainder(q[self.continuous] + math.pi, 2.0 * math.pi) - math.pi
                )
            p, rotation = self._fk(q)
            position_error, rotation_error = task.errors(task.error(p, rotation))
            inside = bool(np.all(q >= self.lower) and np.all(q <= self.upper))
            rotation_value = rotation_error if task.rotation_rows else None
            nearest = (IKSolution(q, "nearest", inside, position_error, rotation_value),)
            what = f"the nearest pose found is {position_error:.4g} m" + (
                f" and {rotation_error:.4g} rad" if task.rotation_rows else ""
            )
            what += " away (position, rotation)"
        if capped:
            return self._failure(
                task,
                "timeout",
                f"the time cap stopped the search after {tried} start(s) (before its "
                f"{RANDOM_STARTS} random ones were done); {what}: raise the timeout (--timeout)",
                tuple(outside) + nearest,
                start,
            )
        if outside:
            return self._failure(
                task,
                "outside_limits",
                f"reachable only outside the joint limits ({len(outside)} joint vector(s))",
                tuple(outside),
                start,
            )
        hint = ""
        if self.nq < 6 and task.target.__class__ is PoseTarget and task.target.mask is None:  # type: ignore[attr-defined]
            hint = (
                f"; an arm of {self.nq} joints reaches only some orientations at a point: "
                "free the others with a mask (--mask)"
            )
        if not tried and nearest:  # the closed form's projection: the nearest pose the arm has
            return self._failure(
                task,
                "out_of_reach",
                f"no joint vector inside the limits reaches the target (the closed form's "
                f"branches): {what}{hint}",
                nearest,
                start,
            )
        return self._failure(
            task,
            "not_found",
            f"no joint vector inside the limits found on the target in {tried} start(s) "
            f"({RANDOM_STARTS} of them random); {what}{hint}",
            nearest,
            start,
        )

    def _failure(
        self,
        task: PartialTask,
        status: str,
        message: str,
        rejected: tuple[IKSolution, ...],
        start: float,
        gap: float | None = None,
    ) -> IKResult:
        return IKResult(
            False,
            self.name,
            status,  # type: ignore[arg-type]
            message,
            (),
            rejected,
            distance_to_workspace=gap,
            time=time.perf_counter() - start,
            free=task.free,
        )


def _add(found: list[IKSolution], solution: IKSolution) -> None:
    """Append ``solution`` unless one of ``found`` is the same joint vector."""
    for other in found:
        if float(np.abs(other.q - solution.q).max()) < SAME_SOLUTION:
            return
    found.append(solution)


def _free_rotation(task: PartialTask) -> np.ndarray | None:
    """The world axis of the one free rotation of a masked pose (unit (3,)), else None."""
    target = task.target
    if not isinstance(target, PoseTarget) or target.mask is None:
        return None
    free = [i for i in range(3) if not target.mask[3 + i]]
    if len(free) != 1:
        return None
    return np.eye(3)[free[0]]


def sweeps(task: PartialTask) -> bool:
    """Whether the target leaves one rotation free: a tool axis's roll, or one masked rotation."""
    return task.axis_column is not None or _free_rotation(task) is not None


def _sweep(
    task: PartialTask, seed_rotation: np.ndarray, grid: bool
) -> tuple[np.ndarray, list[str]]:
    """Tool rotations (K, 3, 3) that meet the target's constrained rotation, and their names.

    An axis target: the seed's tool turned onto the axis by the smallest rotation (``grid``
    False), or :data:`ROLL_GRID` rolls over a turn about the axis from there (True). A mask
    that frees one rotation component: the given rotation (False), or :data:`ROLL_GRID` turns
    of it over a turn about that world axis (True). Any other mask: the given rotation.
    """
    target = task.target
    # the grid's other turns, nearest the first rotation first: 1, -1, 2, -2, ... steps
    steps = sorted(range(1, ROLL_GRID), key=lambda k: (min(k, ROLL_GRID - k), k > ROLL_GRID // 2))
    turns = [2.0 * math.pi * k / ROLL_GRID for k in steps]
    degrees = [360.0 * (k if k <= ROLL_GRID // 2 else k - ROLL_GRID) / ROLL_GRID for k in steps]
    names = [f"roll {value:+g} deg" for value in degrees]
    if isinstance(target, AxisTarget):
        column = TOOL_AXES[target.tool_axis]
        axis = target.axis
        turned = pin.exp3(axis_turn(seed_rotation[:, column], axis)) @ seed_rotation
        if not grid:
            return turned[None], ["seed's roll"]
        return np.array([pin.exp3(axis * turn) @ turned for turn in turns]), names
    free = _free_rotation(task)
    if free is None or not grid:
        return target.rotation[None], ["given rotation"]
    turned = [pin.exp3(free * turn) @ target.rotation for turn in turns]
    return np.array(turned), [
        f"turn {value:+g} deg about world {'xyz'[int(np.argmax(free))]}" for value in degrees
    ]


def _structure(robot: RobotModel) -> Any:
    """The closed-form structure of the robot's table (or of its idealised table), or None."""
    from .analytic.idealised import idealise
    from .analytic.joint_directions import forward_table
    from .analytic.registry import recognise

    table = forward_table(robot.table)
    try:
        return recognise(table)
    except StructureError:
        ideal = idealise(table)
        if ideal is None:
            return None
        try:
            return recognise(ideal.table)
        except StructureError:
            return None
