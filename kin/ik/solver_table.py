"""The solver table: which IK solver answers which robot and target kind, with its options.

Every front end reads this one module: :func:`kin.ik.get_solver` and :func:`kin.ik.solve_ik`,
``kin ik`` and ``kin preview --ik`` (:mod:`kin.commands.solver_choice`), paths
(:func:`kin.path.path_solver`) and batches (:func:`kin.ik.solve_batch`).

**Rows** (:data:`SOLVERS`), one per solver:

============  ===========================================  ======================================
row           answers                                      target kinds
============  ===========================================  ======================================
closed_form   a table a registered structure fits          the structure's; the numeric solver
              (:mod:`.analytic.registry`, by precedence)   takes the rest (a position on 5R/6R)
numeric       any chain (seed table, free-joint closed     positions, poses, axes, numeric
              form of 7R arms, damped Newton, mink QP)     targets
nr            any chain; the paper's Newton-Raphson,       positions
              no limits
============  ===========================================  ======================================

**Choices** (:data:`CHOICES`): a name and the rows it tries in turn; the first whose solver
builds answers (a ``closed_form`` row refuses a table no structure fits). ``auto`` is the
closed form where one fits, else numeric.

**Front ends** (:class:`FrontEnd`): the choices each offers (its default first, each a name and
its rows) and its options. The library's are here (:data:`FRONT_ENDS`: ``library``, ``batch``,
``path``); the commands' (``kin ik --solver mink``, ``nr``) is theirs
(:data:`kin.commands.solver_choice.COMMAND`). ``near_seed`` (:attr:`kin.ik.NumericIK.near_seed`):
a seeded answer of the free-joint closed form far from the seed is checked against damped
Newton from the seed; the commands and paths, whose users give or carry a seed, set it.

**Collisions** are decided here alone: given a checker (``collisions=``,
:class:`~kin.collision.CollisionChecker`), the chosen row's solver is wrapped in
:class:`~.collision.collision_aware.CollisionAwareSolver` (:func:`with_collisions`): its colliding answers
are rejected and the search goes on where the arm has freedom left.

Every solver answers one interface, :class:`kin.ik.solver.IKSolver` (``Solver`` here): no
caller sniffs a signature or asks which class a solver is.

**Routes**: which part of a row's solver answers each target kind (the closed form, its compiled
twin, the partial-pose solver, the numeric search) is the table's too, decided in
:mod:`.routing` by one rule per row (a module apart because the solvers read it when built) and
stated by each solver as ``route(target)``.

**Batches** take, before the rows, the vectorized closed form (:func:`vectorized_solver`:
:class:`~.analytic.batch.BatchSolver`, every target at once) when the structure itself takes the
target kind; else the ``batch`` front end's solver, target by target.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, TypeVar

import numpy as np

from ..robot_model import RobotModel
from .analytic import registry
from .analytic.batch import BatchSolver
from .analytic.closed_form import ClosedFormSolver
from .exceptions import IKError, StructureError
from .numeric.newton_raphson_solver import NewtonRaphsonSolver
from .numeric.solver import NumericIK
from .result import IKResult
from .solver import IKSolver
from .targets.target import PoseTarget, PositionTarget

#: The interface every solver of the table answers (:class:`kin.ik.solver.IKSolver`).
Solver = IKSolver


@dataclass(frozen=True)
class SolverRow:
    """One solver of the table.

    Attributes:
        name: The row's name (a key of :data:`SOLVERS`).
        answers: One line: which robots it answers.
        build: ``build(robot, near_seed)``, the solver of ``robot``; raises
            :class:`~kin.ik.StructureError` when the row does not fit the robot.
    """

    name: str
    answers: str
    build: Callable[[RobotModel, bool], Solver]


@dataclass(frozen=True)
class FrontEnd:
    """How one caller chooses its solver.

    Attributes:
        name: The caller.
        choices: The names it offers, each with the rows (keys of :data:`SOLVERS`) it tries in
            turn; the first name is its default.
        near_seed: The numeric solver's :attr:`~kin.ik.NumericIK.near_seed`.
    """

    name: str
    choices: Mapping[str, tuple[str, ...]]
    near_seed: bool


#: The solvers, by row name.
SOLVERS: Mapping[str, SolverRow] = MappingProxyType(
    {
        "closed_form": SolverRow(
            "closed_form",
            "a table a registered closed-form structure fits (kin.ik.analytic.registry)",
            lambda robot, near_seed: ClosedFormSolver(robot),
        ),
        "numeric": SolverRow(
            "numeric",
            "any chain: seed table, free-joint closed form, damped Newton, mink QP",
            lambda robot, near_seed: NumericIK(robot, near_seed=near_seed),
        ),
        "nr": SolverRow(
            "nr",
            "any chain, positions only, no limits: the paper's Newton-Raphson",
            lambda robot, near_seed: NewtonRaphsonSolver(robot),
        ),
    }
)

#: Each choice and the rows it tries in turn (the first that fits the robot answers).
CHOICES: Mapping[str, tuple[str, ...]] = MappingProxyType(
    {
        "auto": ("closed_form", "numeric"),
        "closed_form": ("closed_form",),
        "numeric": ("numeric",),
        "nr": ("nr",),
    }
)

#: The library's front ends: their choices (default first) and options.
FRONT_ENDS: Mapping[str, FrontEnd] = MappingProxyType(
    {
        "library": FrontEnd("library", {"auto": CHOICES["auto"]}, near_seed=False),  # get_solver
        "path": FrontEnd(
            "path",
            {
                "auto": CHOICES["auto"],
                "closed_form": CHOICES["closed_form"],
                "differential": CHOICES["numeric"],  # the first sample numeric, then differential
            },
            near_seed=True,
        ),
        "batch": FrontEnd("batch", {"auto": CHOICES["auto"]}, near_seed=False),
    }
)


def choose(
    robot: RobotModel,
    choice: str = "auto",
    *,
    near_seed: bool = False,
    collisions: Any = None,
    every: bool = False,
    choices: Mapping[str, tuple[str, ...]] = CHOICES,
) -> Solver:
    """The solver that ``choice`` gives ``robot``: the first of its rows that fits.

    Args:
        robot: The robot.
        choice: A key of ``choices``.
        near_seed: The numeric solver's :attr:`~kin.ik.NumericIK.near_seed`.
        collisions: A :class:`~kin.collision.CollisionChecker` of ``robot``: the solver is
            wrapped in :class:`~.collision.collision_aware.CollisionAwareSolver` (:func:`with_collisions`);
            None: not.
        every: With ``collisions``: judge every answer and keep every free one.
        choices: The names and their rows (:data:`CHOICES`, or a front end's).

    Raises:
        IKError: ``choice`` is not in ``choices``; the message lists them.
        StructureError: No row of the choice fits (``"closed_form"`` on an arm no closed form
            fits); ``"auto"`` never raises it.
    """
    rows = choices.get(choice)
    if rows is None:
        raise IKError(f"unknown solver {choice!r}; choose one of: {', '.join(choices)}")
    solver = None
    for name in rows[:-1]:
        try:
            solver = SOLVERS[name].build(robot, near_seed)
            break
        except StructureError:
            continue
    if solver is None:
        solver = SOLVERS[rows[-1]].build(robot, near_seed)
    return solver if collisions is None else with_collisions(solver, collisions, every=every)


def with_collisions(solver: Solver, checker: Any, *, every: bool = False) -> Solver:
    """``solver`` whose answers are judged by ``checker`` (the one place the wrapper is applied).

    Args:
        solver: A solver of the table.
        checker: A :class:`~kin.collision.CollisionChecker` of the same robot.
        every: Judge every answer and keep every free one (default: up to the first free one).
    """
    from .collision.collision_aware import CollisionAwareSolver

    return CollisionAwareSolver(solver, checker, every=every)


def front_end_solver(
    robot: RobotModel,
    front_end: str | FrontEnd,
    choice: str | None = None,
    *,
    collisions: Any = None,
    every: bool = False,
) -> Solver:
    """:func:`choose` with the options of ``front_end``.

    ``front_end``: a :class:`FrontEnd`, or a key of :data:`FRONT_ENDS`.

    Args:
        robot: The robot.
        front_end: The caller.
        choice: One of the front end's choices; None: its default.
        collisions: A collision checker of ``robot`` (see :func:`choose`), or None.
        every: With ``collisions``: judge every answer (see :func:`with_collisions`).

    Raises:
        IKError: ``choice`` is not one ``front_end`` offers; the message lists them.
        StructureError: As :func:`choose`.
    """
    front = FRONT_ENDS[front_end] if isinstance(front_end, str) else front_end
    choice = next(iter(front.choices)) if choice is None else choice
    return choose(
        robot,
        choice,
        near_seed=front.near_seed,
        collisions=collisions,
        every=every,
        choices=front.choices,
    )


def vectorized_solver(robot: RobotModel, kind: type) -> BatchSolver | None:
    """The batches' first row: the vectorized closed form when its structure takes ``kind``.

    Built on the robot's first call (recognising the arm: up to 0.5 s for a general 6R arm) and
    kept while the robot lives, rebuilt when its joint limits or the registered closed forms
    change (:func:`kept_for`); a
    :class:`~.analytic.batch.BatchSolver` keeps no state between solves, so threads share it.

    Args:
        robot: The robot.
        kind: :class:`~kin.ik.PoseTarget` or :class:`~kin.ik.PositionTarget`.

    Returns:
        The :class:`~.analytic.batch.BatchSolver`, or None (no structure fits, or it leaves
        ``kind`` to the numeric solver).
    """
    if kind not in (PoseTarget, PositionTarget):
        return None
    # Registering a closed form (registry.register) changes which structure fits: a new key.
    structures = tuple(registry.CLOSED_FORMS)
    solver = kept_for(_BATCH_SOLVERS, robot, _batch_solver, structures)
    return solver if solver is not None and kind in solver.structure.target_kinds else None


def _batch_solver(robot: RobotModel) -> BatchSolver | None:
    """The vectorized closed form of ``robot``, or None when no structure fits."""
    try:
        return BatchSolver(robot)
    except StructureError:
        return None


_Built = TypeVar("_Built")
#: Per robot: the joint limits [rad, m] a value was built with, the value, and its other key.
Kept = weakref.WeakKeyDictionary[RobotModel, tuple[np.ndarray, np.ndarray, Any, Any]]
#: The vectorized closed form of each robot :func:`vectorized_solver` was asked about.
_BATCH_SOLVERS: Kept = weakref.WeakKeyDictionary()
#: One lock per robot (a robot's build does not hold up another's batches), made under this one.
_LOCKS: weakref.WeakKeyDictionary[RobotModel, Any] = weakref.WeakKeyDictionary()
_LOCKS_LOCK = threading.Lock()


def kept_for(
    cache: Kept, robot: RobotModel, build: Callable[[RobotModel], _Built], key: Any = None
) -> _Built:
    """``build(robot)``, kept in ``cache`` while the robot lives, its joint limits and ``key`` stay.

    A robot is a frozen value except its model's joint limits (a user may narrow them): a kept
    value built with other limits, or another ``key`` (compared by ``==``), is built again.
    One thread builds a robot's value at a time (the robot's lock, reentrant: a build may ask
    for another kept value of it); the others then find it.
    """
    with _LOCKS_LOCK:
        lock = _LOCKS.get(robot)
        if lock is None:
            lock = _LOCKS[robot] = threading.RLock()
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    with lock:
        kept = cache.get(robot)
        if (
            kept is None
            or kept[3] != key
            or not (np.array_equal(kept[0], lower) and np.array_equal(kept[1], upper))
        ):
            kept = cache[robot] = (lower.copy(), upper.copy(), build(robot), key)
    return kept[2]


def bind_timeout(
    solver: Solver, timeout: float | None, *, all_branches: bool = False
) -> Callable[[Any, Any], IKResult]:
    """``solve(target, seed)`` of ``solver`` with the time budget ``timeout`` [s] bound.

    Every solver takes ``timeout`` and ``all_branches`` (:class:`kin.ik.solver.IKSolver`).
    """
    solve = solver.solve
    if all_branches:
        return lambda target, seed: solve(target, seed, timeout=timeout, all_branches=True)
    return lambda target, seed: solve(target, seed, timeout=timeout)
