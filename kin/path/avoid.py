"""Follow a Cartesian path collision-free: every sample, and the motion between samples.

:func:`follow_path_avoiding` follows the path as :func:`~kin.path.follow.follow_path` does and
checks it (:func:`~kin.path.collision_check.check_path_collisions`): a free path is the answer.
Otherwise it searches the answers of every sample for a free and continuous path:

- the answers of a sample: the free ones of the collision-aware solver
  (:class:`kin.ik.collision.collision_aware.CollisionAwareSolver`, every free answer kept; the solver
  table's :func:`~kin.ik.solver_table.with_collisions` wraps it): every branch of
  a closed form, each revolute joint turned by whole turns toward the previous sample's answers;
  on a 7R arm with a free-joint closed form and a full pose, every branch at a grid of free-joint
  values (``all_branches``); else the numeric solver seeded from the previous sample's best
  answers (and its extra starts when those collide);
- two answers of consecutive samples are joined when no joint moves more than
  ``max_joint_step`` between them (a branch change may not jump) and the straight joint motion
  between them is shown free by the step bound (:class:`~kin.path.collision_check.MotionCheck`);
- of the joined chains, the one with the least motion is kept: the sum over the samples of the
  largest joint step [rad] / [m], from the seed (or the plain path's first sample), plus
  :data:`BRANCH_CHANGE_COST` per change of branch label (a dynamic program, sample by sample).
  The motions are checked lazily: the cheapest chain by the step bound alone first, its motions
  checked start first, a colliding one left out and the chain found again, so only the motions
  the answer may use are checked (the least cost is the same as with every motion checked).

When a sample has no free answer, or none joined to the previous sample's, the search fails
there: :class:`AvoidFailure` names the sample (index, arc length, pose) and why.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from ..configuration import as_joint_vector
from ..robot_model import RobotModel
from .avoid_result import AvoidedPath, AvoidFailure, failure_at
from .branch_follow import TurnUnwrapper
from .cartesian import CartesianPath
from .collision_check import MotionCheck, PathCollision, check_path_collisions
from .follow import MAX_JOINT_STEP, follow_path, path_solver
from .result import PathResult, measure_path

__all__ = ["BRANCH_CHANGE_COST", "SEEDS_PER_SAMPLE", "follow_path_avoiding"]

#: Cost of a change of branch label, against joint motion [rad]: equal motions keep the branch.
BRANCH_CHANGE_COST = 1e-3
#: Best answers of a sample that seed the next sample's numeric solves.
SEEDS_PER_SAMPLE = 3
#: Most answers kept per sample (the cheapest).
MAX_ANSWERS = 64


def follow_path_avoiding(
    robot: RobotModel,
    path: CartesianPath,
    checker: Any,
    seed: npt.ArrayLike | None = None,
    *,
    branch: str | None = None,
    max_joint_step: float = MAX_JOINT_STEP,
    timeout: float = 0.5,
    progress: Callable[[int, int], None] | None = None,
) -> AvoidedPath:
    """A joint path along ``path`` whose samples and motions are all collision-free.

    Args:
        robot: The robot.
        path: The Cartesian path.
        checker: The collision checker of ``robot`` (:class:`kin.collision.CollisionChecker`).
        seed: Joint vector the first sample should be near [rad] / [m], or None.
        branch: Closed form: branch label of the first sample, or None.
        max_joint_step: Largest change of one joint between samples [rad] / [m].
        timeout: Time cap of one sample's collision-aware solve [s].
        progress: Called with (samples done, samples), or None.

    Returns:
        The path (the plain one when it is free), or the failure naming the sample.

    Raises:
        PathError: ``branch`` is not a branch of the first sample.
        kin.JointVectorError: ``seed`` is not one finite value per joint.
    """
    seed_q = None if seed is None else as_joint_vector(robot, seed)
    solver = path_solver(robot)
    plain = follow_path(
        robot,
        path,
        seed_q,
        solver=solver,
        branch=branch,
        max_joint_step=max_joint_step,
        timeout=timeout,
        progress=progress,
    )
    check = check_path_collisions(checker, plain.q)
    if plain.success and check.free:
        return AvoidedPath(True, plain, check, None, None, False)
    start = seed_q if seed_q is not None else (plain.q[0] if len(plain.q) else None)
    search = _Search(robot, solver, checker, path, max_joint_step, timeout)
    q, labels, failure = search.run(start, branch, progress)
    if failure is not None:
        return AvoidedPath(False, None, None, check.first, failure, True)
    final = check_path_collisions(checker, q)
    if not final.free:  # the search joins only motions this check calls free
        assert final.first is not None
        place = failure_at(path, final.first.segment + 1, f"collides: {final.first.describe()}")
        return AvoidedPath(False, None, final, check.first, place, True)
    return AvoidedPath(True, _result(robot, path, q, labels, plain.method), final, check.first)


def _result(
    robot: RobotModel, path: CartesianPath, q: np.ndarray, labels: list[str], method: str
) -> PathResult:
    measured = measure_path(robot, path, q)
    changes = tuple(i for i in range(1, len(labels)) if labels[i] != labels[i - 1])
    return PathResult(
        success=True,
        q=q,
        path=path,
        method=method,
        branches=tuple(labels),
        branch_changes=changes,
        stopped_at=None,
        message="",
        max_deviation=measured.max_deviation,
        max_rotation_error=measured.max_rotation_error,
        max_joint_step=measured.max_joint_step,
        max_step_joint=measured.max_step_joint,
    )


@dataclass
class _Layer:
    """The free answers of one sample joined to the path so far (mutable, search only)."""

    q: np.ndarray  # (K, nq) [rad] / [m]
    labels: list[str]
    cost: np.ndarray  # (K,) least motion to reach each answer
    previous: np.ndarray  # (K,) index of the answer it comes from in the previous layer
    distances: list[np.ndarray | None]  # per answer, MotionCheck.distances (computed lazily)


class _Search:
    """The dynamic program of the module over the samples' free answers."""

    def __init__(
        self,
        robot: RobotModel,
        solver: Any,
        checker: Any,
        path: CartesianPath,
        bound: float,
        timeout: float,
    ):
        from ..ik import PoseTarget
        from ..ik.routing import PARTIAL
        from ..ik.solver_table import with_collisions

        self.robot, self.path, self.bound, self.timeout = robot, path, bound, timeout
        self.aware = with_collisions(solver, checker, every=True)
        partial = solver.route(path.target(0)) is PARTIAL  # components left free
        closed = bool(solver.closed_form_kinds)
        #: Revolute joints turned toward the previous answers (the closed-form rule); the
        #: answers' labels are branches only then (a numeric answer's names its method).
        self.unwrap = TurnUnwrapper(robot) if closed or partial else None
        # a search of its own (the numeric solver): asked for all branches, a 7R pose's grid
        search = not closed and solver.numeric is solver
        grid = search and path.kind is PoseTarget and not partial
        #: One solve per sample gives every branch (its seed orders them, adds one grid value).
        self.once = (closed and not partial) or grid
        self.options = {"all_branches": True} if grid else {}
        self.motion = MotionCheck(checker)
        #: Per sample, the last colliding motion met into it.
        self.blocked: dict[int, PathCollision] = {}
        #: Motions (sample, answer before, answer) shown free, and shown colliding.
        self.free: set[tuple[int, int, int]] = set()
        self.colliding: set[tuple[int, int, int]] = set()

    def run(
        self,
        start: np.ndarray | None,
        branch: str | None,
        progress: Callable[[int, int], None] | None,
    ) -> tuple[np.ndarray, list[str], AvoidFailure | None]:
        """(joint path (M, nq), branch labels, None) or (empty, [], the failure).

        The samples' answers are joined by the step bound alone first (an optimistic chain);
        then the motions of the cheapest chain are checked, start first, and a colliding one
        removed and the chain found again (:meth:`_verify`): only the motions the answer may
        use are checked.
        """
        layers: list[_Layer] = []
        stop: tuple[int, str] | None = None
        for index in range(len(self.path)):
            if progress is not None:
                progress(index, len(self.path))
            refs = [start] if not layers else list(_cheapest(layers[-1], SEEDS_PER_SAMPLE))
            answers, labels, why = self._answers(index, refs)
            if not layers and branch is not None:  # a branch of sample 0 (follow_path checked)
                keep = [i for i, label in enumerate(labels) if label == branch]
                answers, labels = answers[keep], [labels[i] for i in keep]
            if not len(answers):
                stop = (index, why)
                break
            count = len(answers)
            layer = _Layer(answers, labels, np.zeros(count), np.full(count, -1), [None] * count)
            if layers:
                self._relax(layers[-1], layer, index)
            elif start is not None:
                layer.cost = np.abs(answers - start).max(axis=1)
            if not np.isfinite(layer.cost).any():
                stop = (index, self._why_not(layers[-1], answers, index))
                break
            layers.append(_pruned(layer))
        blocked = self._verify(layers)  # an earlier sample may be cut off by the motions
        if blocked is not None:
            return _fail(
                self.path, blocked, self._why_not(layers[blocked - 1], layers[blocked].q, blocked)
            )
        if stop is not None:
            return _fail(self.path, *stop)
        if progress is not None:
            progress(len(self.path), len(self.path))
        return _backtrack(layers)

    def _answers(self, index: int, refs: list[Any]) -> tuple[np.ndarray, list[str], str]:
        """(free answers (K, nq), their labels, why none / ``"branches: ..."``) of a sample."""
        target = self.path.target(index)
        answers: list[np.ndarray] = []
        labels: list[str] = []
        why = ""
        for ref in refs[:1] if self.once else refs:
            result = self.aware.solve(target, ref, timeout=self.timeout, **self.options)
            if not result.solutions:
                why = f"{result.status}: {result.message}"
            for solution in result.solutions:
                for copy in self._copies(np.asarray(solution.q, dtype=float), refs):
                    if not any(np.abs(copy - a).max() < 1e-9 for a in answers):
                        answers.append(copy)
                        labels.append(solution.branch if self.unwrap is not None else "")
        if answers:
            why = "branches: " + "; ".join(sorted(map(repr, set(labels))))
        return np.array(answers, dtype=float).reshape(-1, self.robot.nq), labels, why

    def _copies(self, q: np.ndarray, refs: list[Any]) -> list[np.ndarray]:
        if self.unwrap is None:
            return [q]
        return [self.unwrap(q, ref) for ref in refs]

    def _relax(self, last: _Layer, layer: _Layer, index: int) -> None:
        """Join ``layer`` (sample ``index``) to ``last``: the cheapest answer within the bound.

        Motions shown colliding are left out; the others count as free until checked.
        """
        steps = np.abs(layer.q[:, None, :] - last.q[None, :, :]).max(axis=2)  # (K, K_last)
        change = np.array(layer.labels)[:, None] != np.array(last.labels)[None, :]
        total = last.cost[None, :] + steps + BRANCH_CHANGE_COST * change
        total[steps > self.bound] = np.inf
        for sample, j, k in self.colliding:
            if sample == index:
                total[k, j] = np.inf
        layer.previous = np.argmin(total, axis=1)
        layer.cost = total[np.arange(len(total)), layer.previous]

    def _verify(self, layers: list[_Layer]) -> int | None:
        """Check the cheapest chain's motions; the first sample no free chain reaches, or None."""
        while layers:
            chain = _chain(layers)
            for index in range(1, len(layers)):
                j, k = chain[index - 1], chain[index]
                if (index, j, k) in self.free:
                    continue
                last, layer = layers[index - 1], layers[index]
                ends = _distances(self.motion, last, j), _distances(self.motion, layer, k)
                hit = self.motion.between(last.q[j], layer.q[k], *ends)
                if hit is None:
                    self.free.add((index, j, k))
                    continue
                self.colliding.add((index, j, k))
                self.blocked[index] = hit
                for later in range(index, len(layers)):
                    self._relax(layers[later - 1], layers[later], later)
                    if not np.isfinite(layers[later].cost).any():
                        # the samples before it may be cut off too (motions not yet checked
                        # join them): the first one no checked chain reaches is named
                        earlier = self._verify(layers[:later])
                        return later if earlier is None else earlier
                break
            else:
                return None
        return None

    def _why_not(self, last: _Layer, answers: np.ndarray, index: int) -> str:
        """Why no free answer of sample ``index`` joins the previous sample's."""
        reached = last.q[np.isfinite(last.cost)]
        steps = np.abs(answers[:, None, :] - reached[None, :, :])  # (K, K_last, nq)
        gap = steps.max(axis=2)
        k, j = np.unravel_index(int(np.argmin(gap)), gap.shape)
        if gap[k, j] > self.bound:
            joint = int(np.argmax(steps[k, j]))
            row = self.robot.table.rows[joint]
            unit = "rad" if row.joint_type == "revolute" else "m"
            return (
                f"the nearest collision-free answer is {gap[k, j]:.3g} {unit} "
                f"('{self.robot.joint_names[joint]}') from sample {index - 1}'s, more than the "
                f"step bound {self.bound:.3g}: the branch change would jump"
            )
        hit = self.blocked.get(index)
        pair = "" if hit is None else f" ({hit.a} / {hit.b}, {hit.kind})"
        return (
            f"every collision-free answer within {self.bound:.3g} of sample {index - 1}'s "
            f"collides on the way there{pair}"
        )


def _distances(motion: MotionCheck, layer: _Layer, j: int) -> np.ndarray:
    cached = layer.distances[j]
    if cached is None:
        cached = layer.distances[j] = motion.distances(layer.q[j])
    return cached


def _cheapest(layer: _Layer, count: int) -> np.ndarray:
    return layer.q[np.argsort(layer.cost)[:count]]


def _pruned(layer: _Layer) -> _Layer:
    """The joined answers only, at most :data:`MAX_ANSWERS`, cheapest first."""
    keep = [int(k) for k in np.argsort(layer.cost) if np.isfinite(layer.cost[k])][:MAX_ANSWERS]
    return _Layer(
        layer.q[keep],
        [layer.labels[k] for k in keep],
        layer.cost[keep],
        layer.previous[keep],
        [layer.distances[k] for k in keep],
    )


def _chain(layers: list[_Layer]) -> list[int]:
    """Per sample, the index of its answer on the cheapest chain to the last sample."""
    k = int(np.argmin(layers[-1].cost))
    chain = []
    for layer in reversed(layers):
        chain.append(k)
        k = int(layer.previous[k])
    return chain[::-1]


def _backtrack(layers: list[_Layer]) -> tuple[np.ndarray, list[str], None]:
    chain = _chain(layers)
    q = np.array([layer.q[k] for layer, k in zip(layers, chain)])
    return q, [layer.labels[k] for layer, k in zip(layers, chain)], None


def _fail(path: CartesianPath, index: int, why: str) -> tuple[np.ndarray, list[str], AvoidFailure]:
    if why.startswith("branches: "):  # free answers there, none on the asked branch
        why = f"the asked branch collides; the free ones: {why[len('branches: ') :]}"
    return np.zeros((0, 0)), [], failure_at(path, index, why)
