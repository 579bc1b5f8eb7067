"""IK of the redundant 7-DOF arm (humanoid7): fast, inside the limits, verified by Pinocchio.

The solve loop, until a solution is verified or the time budget runs out:

0. Closed form, for an arm of the :class:`~ik.structure.SevenDof` structure (humanoid7) and a
   target without posture preference: joint 1 (and, for a position target, joints 5-7) from a
   start, the other joints in closed form (:mod:`ik.seven_dof`), joint 1 scanned outward when it
   gives no branch inside the limits. Starts: the caller's seed, then the seed-table samples
   near the target. Most targets end here, in tens of microseconds.
1. Starts: the seed-table samples whose tool poses are nearest to the target (and the caller's
   ``seed_q`` / posture preference first when its tool pose is at least as near).
2. From each start, clamped damped Newton steps on Pinocchio (:mod:`ik.damped_newton`).
3. When the nearest starts fail, mink QP steps with hard limits (:mod:`ik.differential_ik`) from
   the best configuration so far, then a damped Newton polish; then random starts inside the
   limits, alternating both, until the deadline.

Pinocchio is the judge: a configuration is a solution only when Pinocchio's forward kinematics
at it finds it within ``1e-5 m`` and ``1e-4 rad`` of the target and inside the limits. The
damped Newton run's last evaluation is that forward kinematics at the returned ``q`` (the numbers
:func:`ik.numeric_target.measure` would recompute), so a success costs no extra evaluation.
Otherwise the result says so (``success=False``) and carries the best configuration found and its
errors (measured by :func:`ik.numeric_target.measure`).
"""

from __future__ import annotations

import functools
import logging
import math
import time
from collections.abc import Iterator
from operator import le

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import KinError, RobotModel, as_joint_vector, load_robot

from ..analytic.seven_dof import COMPILED, SevenDofIK
from ..analytic.structure import seven_dof
from ..exceptions import StructureError, TargetError
from ..result import IKResult, IKSolution
from .damped_newton import NewtonOutcome, damped_newton
from .differential_ik import DifferentialIK
from .numeric_target import POSITION_TOLERANCE, ROTATION_TOLERANCE, NumericTarget, measure
from .seed_table import SeedTable, build_seed_table, seed_table_for

logger = logging.getLogger(__name__)

#: Weight of the rotation error when ranking failed attempts [m/rad].
_RANK_WEIGHT = 0.1


class NumericIK:
    """Numeric IK of one robot: seed table, damped Newton fast path, mink QP fallback.

    Args:
        robot: The robot.
        table_size: Number of sampled poses in the seed table.
        qp_solver: QP solver of the mink fallback (``"daqp"`` or ``"osqp"``).
        nearest: Number of seed-table starts tried before the fallback.
        newton_iterations: Damped Newton steps per start.
        qp_iterations: mink QP steps per fallback run.
        patience: A nearest start is abandoned after this many damped Newton steps in a row
            that do not halve its error (None: always ``newton_iterations`` steps).
        random_starts: Random starts tried after the nearest ones and before the first mink
            QP run (a QP run costs as much as dozens of damped Newton starts).
        random_between: Random starts between two mink QP runs.
        random_patience: ``patience`` of the random starts (a mink QP run is always followed
            by ``newton_iterations`` damped Newton steps).
        closed_form: Try the closed form first when the arm has the
            :class:`~ik.structure.SevenDof` structure (False: damped Newton and mink only).
        closed_form_starts: Seed-table samples tried by the closed form before damped Newton.
        closed_form_steps: Joint-1 scan steps of the first closed-form starts [rad], coarse to
            fine: when a start's joint 1 gives no branch inside the limits, joint 1 is scanned
            outward from there, on the coarse grid first (None: 0.05 then 0.01 rad with the
            compiled twin of :mod:`ik.seven_dof`, 0.05 rad without).
    """

    #: Solver name reported in :class:`IKResult` (the scripts' dispatch protocol).
    name = "mink"

    def __init__(
        self,
        robot: RobotModel,
        table_size: int = 20000,
        qp_solver: str = "daqp",
        nearest: int = 8,
        newton_iterations: int = 20,
        qp_iterations: int = 25,
        patience: int | None = 3,
        random_starts: int = 10,
        random_between: int = 3,
        random_patience: int | None = 3,
        closed_form: bool = True,
        closed_form_starts: int = 32,
        closed_form_steps: tuple[float, ...] | None = None,
    ):
        self.robot = robot
        self.model = robot.model
        self.data = robot.model.createData()
        self.frame_id = robot.model.getFrameId(robot.tool_frame)
        self.table_size = table_size
        self.qp_solver = qp_solver
        self.nearest = nearest
        self.newton_iterations = newton_iterations
        self.qp_iterations = qp_iterations
        self.patience = patience
        self.random_starts = random_starts
        self.random_between = random_between
        self.random_patience = random_patience
        self.lower = robot.model.lowerPositionLimit.copy()
        self.upper = robot.model.upperPositionLimit.copy()
        self._lows, self._highs = self.lower.tolist(), self.upper.tolist()
        rows = robot.table.rows
        #: Upper bound of the tool's distance from the base origin [m] (triangle inequality).
        self.reach = float(sum(abs(row.a) + abs(row.d) for row in rows))
        self._shape = (robot.model.nq,)
        self._table: SeedTable | None = None
        self._differential: DifferentialIK | None = None
        #: Closed form for chosen free joints, or None (the arm does not have the structure).
        self.closed_form: SevenDofIK | None = None
        if closed_form:
            try:
                self.closed_form = SevenDofIK(seven_dof(robot.table), self.lower, self.upper)
            except StructureError:
                pass
        self.closed_form_starts = closed_form_starts
        if closed_form_steps is None:
            closed_form_steps = (0.05, 0.01) if COMPILED else (0.05,)
        self.closed_form_steps = tuple(closed_form_steps)

    @property
    def table(self) -> SeedTable:
        """The seed table (built on first use, cached per shipped robot)."""
        if self._table is None:
            if _is_shipped(self.robot):
                self._table = seed_table_for(self.robot.name, self.table_size)
            else:  # a robot loaded from a table file: its own table
                self._table = build_seed_table(self.robot, self.table_size)
        return self._table

    @property
    def differential(self) -> DifferentialIK:
        """The mink differential IK (MuJoCo model loaded on first use)."""
        if self._differential is None:
            self._differential = DifferentialIK(self.robot, solver=self.qp_solver)
        return self._differential

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """Target types :meth:`solve` accepts."""
        from ..target import PoseTarget, PositionTarget

        return (NumericTarget, PoseTarget, PositionTarget)

    def solve(
        self,
        target: object,
        seed: npt.ArrayLike | None = None,
        timeout: float = 0.05,
        random_seed: int = 0,
        position_tol: float = POSITION_TOLERANCE,
        rotation_tol: float = ROTATION_TOLERANCE,
        max_attempts: int | None = None,
    ) -> IKResult:
        """Find a joint vector inside the limits that puts the tool on ``target``.

        Args:
            target: Tool target (full pose or position only, optional posture preference).
            seed: Start joint vector [rad]. The closed form (an arm of the
                :class:`~ik.structure.SevenDof` structure) starts from it first: the answer
                keeps its joint 1 as nearly as the target allows and takes the branch nearest
                it. Damped Newton tries it first when its tool pose is at least as near to the
                target as the nearest seed-table sample's.
            timeout: Time budget [s]; the first verified solution returns earlier. Building the
                seed table and loading the MuJoCo model (once per solver) do not count.
            random_seed: Seed of the random restarts (results are reproducible).
            position_tol: Success tolerance on the position [m].
            rotation_tol: Success tolerance on the rotation [rad].
            max_attempts: Stop after this many starts even before the deadline (with a long
                timeout, a result that does not depend on the machine's speed), or None.

        Returns:
            ``IKResult(solver="mink")``; on failure ``rejected`` holds the best configuration.
            A non-finite ``ik.target`` value gives ``status="invalid_target"``.

        Raises:
            TargetError: A target of another kind (e.g. ``PitchTarget``), a malformed one, or a
                seed of the wrong size.
        """
        _ = self.table  # built once, outside the budget
        start = time.perf_counter()
        deadline = start + timeout
        if not getattr(target, "finite", True):  # ik.target values accept NaN; report it
            return IKResult(False, "mink", "invalid_target", f"target is not finite: {target}")
        target = NumericTarget.from_target(target)
        # 0: the closed form from the seed's or samples' free joints (no posture preference).
        if target.posture is None and self.closed_form is not None:
            done = self._closed_form(target, seed, position_tol, rotation_tol, start)
            if done is not None:
                return done
        position, rotation = target.position, target.rotation
        inner_p, inner_r = 0.1 * position_tol, 0.1 * rotation_tol
        best: NewtonOutcome | None = None
        iterations = 0
        attempts = 0
        lows, highs = self._lows, self._highs
        newton_kwargs = dict(
            max_iterations=self.newton_iterations,
            position_tol=inner_p,
            rotation_tol=inner_r,
            posture=target.posture,
        )
        # The nearest starts give up early when stuck: the next start is cheaper than the
        # remaining steps (the fallback below always runs its full steps).
        start_kwargs = dict(newton_kwargs, patience=self.patience)
        random_kwargs = dict(newton_kwargs, patience=self.random_patience)

        def finish(outcome: NewtonOutcome, how: str) -> IKResult | None:
            # The last Newton evaluation ran Pinocchio's forward kinematics at ``outcome.q``
            # itself: its errors are the judge's measurement (``measure`` would recompute the
            # same numbers), the limits are checked on the returned values.
            q = outcome.q
            values = q.tolist()
            if not (
                outcome.position_error < position_tol
                and outcome.rotation_error < rotation_tol
                and all(map(le, lows, values))
                and all(map(le, values, highs))
            ):
                return None
            solution = IKSolution(
                q.copy(), "", True, outcome.position_error, outcome.rotation_error
            )
            return IKResult(
                True,
                "mink",
                "ok",
                how,
                (solution,),
                iterations=iterations,
                time=time.perf_counter() - start,
            )

        def better(outcome: NewtonOutcome) -> bool:
            if best is None:
                return True
            return (
                outcome.position_error + _RANK_WEIGHT * outcome.rotation_error
                < best.position_error + _RANK_WEIGHT * best.rotation_error
            )

        # 1-2: nearest starts, damped Newton.
        for label, q0, _ in self._starts(target, seed):
            outcome = damped_newton(
                self.model, self.data, self.frame_id, q0, position, rotation, **start_kwargs
            )
            iterations += outcome.iterations
            attempts += 1
            if outcome.converged:
                done = finish(outcome, f"damped Newton from {label}, {outcome.iterations} steps")
                if done is not None:
                    return done
            if better(outcome):
                best = outcome
            if time.perf_counter() > deadline:
                break
        # 3: random restarts and mink QP runs (the first from the best so far), until the deadline.
        rng = np.random.default_rng(random_seed)
        fallback = qp_runs = 0
        nearest_best = best
        best_from_qp = False
        out_of_reach = float(np.linalg.norm(position)) > self.reach
        while time.perf_counter() < deadline:
            label = "mink QP"
            # Out of reach: mink QP from the best so far first (the closest configuration);
            # else ``random_starts`` cheap random starts first. Then mink QP runs with
            # ``random_between`` random starts between them.
            k = fallback if out_of_reach else fallback - self.random_starts
            use_qp = k >= 0 and k % (self.random_between + 1) == 0
            fallback += 1
            if use_qp and not qp_runs and nearest_best is not None:
                q_next = nearest_best.q  # the first run: from the nearest starts' best
            else:
                q_next = rng.uniform(self.lower, self.upper)
            if use_qp:
                qp_runs += 1
                if self._differential is None:  # loaded once, outside the budget
                    loading = time.perf_counter()
                    _ = self.differential
                    deadline += time.perf_counter() - loading
                self.differential.set_target(target)
                qp = self.differential.solve(q_next, self.qp_iterations, inner_p, inner_r, deadline)
                iterations += qp.iterations
                q_next = qp.q
                label = f"mink QP ({qp.iterations} steps) + damped Newton"
            else:
                label = "damped Newton from a random start"
            outcome = damped_newton(
                self.model,
                self.data,
                self.frame_id,
                q_next,
                position,
                rotation,
                **(newton_kwargs if use_qp else random_kwargs),
            )
            iterations += outcome.iterations
            attempts += 1
            if outcome.converged:
                done = finish(outcome, f"{label}, attempt {attempts}")
                if done is not None:
                    return done
            if better(outcome):
                best = outcome
                best_from_qp = use_qp
            if out_of_reach and attempts > self.nearest + 2:
                break
            if max_attempts is not None and attempts >= max_attempts:
                break
        if best is not None and not best_from_qp and time.perf_counter() < deadline:
            # No solution, stopped by ``max_attempts``: a last mink QP run from the best
            # configuration (a random start's, stopped early) tightens it.
            self.differential.set_target(target)
            qp = self.differential.solve(best.q, self.qp_iterations, inner_p, inner_r, deadline)
            outcome = damped_newton(
                self.model, self.data, self.frame_id, qp.q, position, rotation, **newton_kwargs
            )
            iterations += qp.iterations + outcome.iterations
            if outcome.converged and (done := finish(outcome, "mink QP from the best")):
                return done
            if better(outcome):
                best = outcome
        return self._failure(
            target, best, iterations, attempts, time.perf_counter() - start, out_of_reach
        )

    def _starts(
        self, target: NumericTarget, seed_q: npt.ArrayLike | None
    ) -> Iterator[tuple[str, np.ndarray, int]]:
        """Start joint vectors, most promising first (ranked lazily: most targets need one).

        Yields ``(label, q0, index)``: ``index`` is the seed-table sample's, -1 for the caller's.
        """
        table = self.table
        extra = []
        if target.posture is not None:
            extra.append(("the preferred posture", np.asarray(target.posture, dtype=float), -1))
        if seed_q is not None:
            extra.append(("the given seed", self._seed_vector(seed_q), -1))
        found = table.ranked(target.position, target.rotation)
        if found is None or found[0].size < self.nearest:  # outside the grid: the KD-tree
            order = table.nearest(target.position, target.rotation, k=self.nearest)
            candidates, distances = order, None
            first = 0
        else:
            candidates, distances = found
            first = int(distances.argmin())
        # A caller's start goes first when its tool pose is at least as near as the nearest
        # sample's (in the table's pose embedding), else second.
        ahead, behind = [], []
        if extra:
            nearest = (
                self._embedding_distance(table.q[candidates[first]], target)
                if distances is None
                else float(distances[first])
            )
            for start in extra:
                near = self._embedding_distance(start[1], target) <= nearest
                (ahead if near else behind).append(start)
        yield from ahead
        index = int(candidates[first])
        yield f"seed-table sample {index}", table.q[index], index
        yield from behind
        if distances is None:
            rest = candidates[1:]
        else:
            ranked = np.argsort(distances, kind="stable")[: self.nearest]
            rest = [candidates[i] for i in ranked if i != first][: self.nearest - 1]
        for i in rest:
            index = int(i)
            yield f"seed-table sample {index}", table.q[index], index

    def _closed_form(
        self,
        target: NumericTarget,
        seed_q: npt.ArrayLike | None,
        position_tol: float,
        rotation_tol: float,
        start: float,
    ) -> IKResult | None:
        """The closed form from the caller's seed, then from seed-table samples; None if none verifies.

        From a start: joint 1 (and, for a position target, joints 5-7) as the start has them, the
        other joints in closed form, the branch nearest the start
        (:meth:`~ik.seven_dof.SevenDofIK.first`). When that joint 1 gives no branch inside the
        limits, the seed and the first sample scan joint 1 outward from there (by
        ``closed_form_steps``, coarse to fine): the answer keeps the start's joint 1 as nearly as the target
        allows. Pinocchio measures the answer.
        """
        closed = self.closed_form
        prepared = closed.prepare(target.position, target.rotation)
        out = np.empty(7)
        for label, starts, indices, step in self._closed_form_starts(target, seed_q):
            offset = 0
            while offset < len(starts):
                index = closed.first(prepared, starts[offset:], out, step)
                if index < 0:
                    break
                offset += index + 1
                solution = self._verified(out, target, position_tol, rotation_tol)
                if solution is not None:
                    if label is None:
                        label = f"seed-table sample {int(indices[offset - 1])}"
                    return IKResult(
                        True,
                        "mink",
                        "ok",
                        f"closed form with the free joints of {label}",
                        (solution,),
                        iterations=0,
                        time=time.perf_counter() - start,
                    )
        return None

    def _closed_form_starts(
        self, target: NumericTarget, seed_q: npt.ArrayLike | None
    ) -> Iterator[tuple[str | None, np.ndarray, np.ndarray | None, float]]:
        """Blocks of closed-form starts, in order: ``(label, starts, sample indices, step)``.

        The caller's seed (scanned, coarse then fine); the seed-table sample nearest the target
        (scanned likewise; for a
        full pose by pose distance, for a position the nearest to the target's grid cell centre);
        the next ``closed_form_starts`` samples (not scanned). Looked up lazily: most targets need
        the first block only.
        """
        steps = self.closed_form_steps
        if seed_q is not None:
            seed = self._seed_vector(seed_q)[None]
            for step in steps:
                yield "the given seed", seed, None, step
        table = self.table
        position, rotation = target.position, target.rotation
        if rotation is None:
            candidates = table.cell_samples(position)
            if candidates is None:
                return
            for step in steps:
                yield None, table.q[candidates[:1]], candidates, step
            rest = candidates[1 : self.closed_form_starts]
        else:
            found = table.ranked(position, rotation)
            if found is None or not found[0].size:
                return
            candidates, distances = found
            first = int(distances.argmin())
            for step in steps:
                yield None, table.q[candidates[first : first + 1]], candidates[first:], step
            order = np.argsort(distances, kind="stable")[: self.closed_form_starts]
            rest = candidates[order[order != first]]
        if rest.size:
            yield None, table.q[rest], rest, 0.0

    def _verified(
        self, q: np.ndarray, target: NumericTarget, position_tol: float, rotation_tol: float
    ) -> IKSolution | None:
        """``q`` as a solution if Pinocchio finds it on target (limits: the caller's business)."""
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q)
        pose = pin.updateFramePlacement(model, data, self.frame_id)
        x, y, z = np.subtract(pose.translation, target.position).tolist()
        position_error = math.sqrt(x * x + y * y + z * z)
        if position_error >= position_tol:
            return None
        rotation_error = 0.0
        if target.rotation is not None:
            x, y, z = pin.log3(np.dot(pose.rotation.T, target.rotation)).tolist()
            rotation_error = math.sqrt(x * x + y * y + z * z)
            if rotation_error >= rotation_tol:
                return None
        return IKSolution(q.copy(), "", True, position_error, rotation_error)

    def _seed_vector(self, seed_q: npt.ArrayLike) -> np.ndarray:
        """The caller's seed as a finite joint vector (the solver never writes into it)."""
        if (
            type(seed_q) is np.ndarray
            and seed_q.shape == self._shape
            and seed_q.dtype == np.float64
            and math.isfinite(sum(seed_q.tolist()))
        ):
            return seed_q  # already valid: no copy, no validation
        try:
            return as_joint_vector(self.robot, seed_q)
        except KinError as err:
            raise TargetError(f"seed of '{self.robot.name}': {err}") from err

    def _embedding_distance(self, q: np.ndarray, target: NumericTarget) -> float:
        """Squared distance of ``q``'s tool pose to the target in the seed table's embedding."""
        model, data = self.model, self.data
        values = q.tolist()
        if not (all(map(le, self._lows, values)) and all(map(le, values, self._highs))):
            q = np.minimum(np.maximum(q, self.lower), self.upper)
        pin.forwardKinematics(model, data, q)
        pose = pin.updateFramePlacement(model, data, self.frame_id)
        x, y, z = np.subtract(pose.translation, target.position).tolist()
        distance = x * x + y * y + z * z
        if target.rotation is not None:  # |R - R_t|_F^2 = 6 - 2 <R, R_t> for rotations
            inner = float(np.vdot(pose.rotation, target.rotation))
            distance += self.table.rotation_weight**2 * (6.0 - 2.0 * inner)
        return distance

    def _failure(
        self,
        target: NumericTarget,
        best: NewtonOutcome | None,
        iterations: int,
        attempts: int,
        elapsed: float,
        out_of_reach: bool,
    ) -> IKResult:
        rejected: tuple[IKSolution, ...] = ()
        detail = "no configuration"
        if best is not None:
            verdict = measure(self.robot, self.data, best.q, target)
            rejected = (
                IKSolution(
                    best.q.copy(),
                    "",
                    verdict.within_limits,
                    verdict.position_error,
                    verdict.rotation_error,
                ),
            )
            detail = f"best configuration misses by {verdict.position_error:.3g} m" + (
                "" if target.position_only else f" and {verdict.rotation_error:.3g} rad"
            )
        if out_of_reach:
            distance = float(np.linalg.norm(target.position)) - self.reach
            return IKResult(
                False,
                "mink",
                "out_of_reach",
                f"target is {distance:.4g} m beyond the arm's reach ({self.reach:.4g} m); {detail}",
                (),
                rejected,
                distance_to_workspace=distance,
                iterations=iterations,
                time=elapsed,
            )
        return IKResult(
            False,
            "mink",
            "not_converged",
            f"no solution inside the joint limits found in {elapsed * 1e3:.0f} ms "
            f"({attempts} starts); {detail}",
            (),
            rejected,
            iterations=iterations,
            time=elapsed,
        )


def _is_shipped(robot: RobotModel) -> bool:
    """Whether ``robot`` is the registry's (cached) model of its name."""
    try:
        return load_robot(robot.name) is robot
    except Exception:  # noqa: BLE001 - any name the registry does not know
        return False


@functools.lru_cache(maxsize=8)
def numeric_ik_for(robot_name: str) -> NumericIK:
    """The (cached) numeric IK of a shipped robot."""
    return NumericIK(load_robot(robot_name))


def solve_numeric(
    robot: RobotModel | str,
    position: npt.ArrayLike,
    rotation: npt.ArrayLike | None = None,
    posture: npt.ArrayLike | None = None,
    seed_q: npt.ArrayLike | None = None,
    timeout: float = 0.05,
) -> IKResult:
    """Numeric IK in one call: position [m], optional rotation ``R_world_tool`` and posture.

    Args:
        robot: A loaded robot or a shipped robot's name.
        position: Tool position in the world frame [m].
        rotation: Tool rotation (3 x 3), or None for a position-only target.
        posture: Preferred joint vector [rad] for the redundancy, or None.
        seed_q: Start joint vector [rad], or None.
        timeout: Time budget [s].
    """
    solver = numeric_ik_for(robot) if isinstance(robot, str) else NumericIK(robot)
    target = NumericTarget.from_arrays(position, rotation, posture)
    return solver.solve(target, seed=seed_q, timeout=timeout)
