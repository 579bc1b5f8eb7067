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
closed form where one fits, else numeric; ``mink`` (``kin ik --solver``) and ``differential``
(paths) are the front ends' names of the numeric row.

**Front ends** (:data:`FRONT_ENDS`): the choices each offers (its default first) and its
options. ``near_seed`` (:attr:`kin.ik.NumericIK.near_seed`): a seeded answer of the free-joint
closed form far from the seed is checked against damped Newton from the seed; the commands and
paths, whose users give or carry a seed, set it.

**Collisions**: given a checker (``collisions=``, :class:`~kin.collision.CollisionChecker`), the
chosen row's solver is wrapped in :class:`~.collision_aware.CollisionAwareSolver`: its colliding
answers are rejected and the search goes on where the arm has freedom left.

**Batches** take, before the rows, the vectorized closed form (:func:`vectorized_solver`:
:class:`~.analytic.batch.BatchSolver`, every target at once) when the structure itself takes the
target kind; else the ``batch`` front end's solver, target by target.
"""

from __future__ import annotations

import inspect
import threading
import weakref
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Protocol, TypeVar

import numpy as np
import numpy.typing as npt

from ..robot_model import RobotModel
from .analytic import registry
from .analytic.batch import BatchSolver
from .analytic.closed_form import ClosedFormSolver
from .exceptions import IKError, StructureError
from .numeric.newton_raphson_solver import NewtonRaphsonSolver
from .numeric.solver import NumericIK
from .result import IKResult
from .target import PoseTarget, PositionTarget


class Solver(Protocol):
    """What every IK solver offers (closed form, numeric, the composite of both).

    Attributes:
        name: The pipeline, as :attr:`IKResult.solver` reports it (``"closed_form:<structure>"``,
            ``"numeric"``).
        target_kinds: The target classes :meth:`solve` accepts.
    """

    name: str

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """The target classes :meth:`solve` accepts."""
        ...

    def solve(
        self, target: Any, seed: npt.ArrayLike | None = None, *, timeout: float | None = None
    ) -> IKResult:
        """Solve one target from a seed (joint vector [rad] / [m]) within ``timeout`` [s]."""
        ...


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
        choices: The names (keys of :data:`CHOICES`) it offers; the first is its default.
        near_seed: The numeric solver's :attr:`~kin.ik.NumericIK.near_seed`.
    """

    name: str
    choices: tuple[str, ...]
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
        "mink": ("numeric",),  # kin ik --solver mink
        "differential": ("numeric",),  # paths: the first sample numeric, then differential IK
        "nr": ("nr",),  # kin ik --solver nr
    }
)

#: Each front end's choices (default first) and options.
FRONT_ENDS: Mapping[str, FrontEnd] = MappingProxyType(
    {
        "library": FrontEnd("library", ("auto",), near_seed=False),  # get_solver, solve_ik
        "command": FrontEnd("command", ("auto", "mink", "nr"), near_seed=True),  # kin ik, preview
        "path": FrontEnd("path", ("auto", "closed_form", "differential"), near_seed=True),
        "batch": FrontEnd("batch", ("auto",), near_seed=False),  # after vectorized_solver
    }
)


def choose(
    robot: RobotModel,
    choice: str = "auto",
    *,
    near_seed: bool = False,
    collisions: Any = None,
) -> Solver:
    """The solver that ``choice`` gives ``robot``: the first of its rows that fits.

    Args:
        robot: The robot.
        choice: A key of :data:`CHOICES`.
        near_seed: The numeric solver's :attr:`~kin.ik.NumericIK.near_seed`.
        collisions: A :class:`~kin.collision.CollisionChecker` of ``robot``: the solver is
            wrapped in :class:`~.collision_aware.CollisionAwareSolver`; None: not.

    Raises:
        IKError: ``choice`` is not in :data:`CHOICES`; the message lists them.
        StructureError: No row of the choice fits (``"closed_form"`` on an arm no closed form
            fits); ``"auto"`` never raises it.
    """
    rows = CHOICES.get(choice)
    if rows is None:
        raise IKError(f"unknown solver {choice!r}; choose one of: {', '.join(CHOICES)}")
    solver = None
    for name in rows[:-1]:
        try:
            solver = SOLVERS[name].build(robot, near_seed)
            break
        except StructureError:
            continue
    if solver is None:
        solver = SOLVERS[rows[-1]].build(robot, near_seed)
    if collisions is None:
        return solver
    from .collision_aware import CollisionAwareSolver

    return CollisionAwareSolver(solver, collisions)


def front_end_solver(
    robot: RobotModel, front_end: str, choice: str | None = None, *, collisions: Any = None
) -> Solver:
    """:func:`choose` with the options of ``front_end`` (a key of :data:`FRONT_ENDS`).

    Args:
        robot: The robot.
        front_end: The caller.
        choice: One of the front end's choices; None: its default.
        collisions: A collision checker of ``robot`` (see :func:`choose`), or None.

    Raises:
        IKError: ``choice`` is not one ``front_end`` offers; the message lists them.
        StructureError: As :func:`choose`.
    """
    front = FRONT_ENDS[front_end]
    choice = front.choices[0] if choice is None else choice
    if choice not in front.choices:
        raise IKError(f"unknown solver {choice!r}; choose one of: {', '.join(front.choices)}")
    return choose(robot, choice, near_seed=front.near_seed, collisions=collisions)


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


def bind_timeout(solver: object, timeout: float | None) -> Callable[[Any, Any], IKResult]:
    """``solve(target, seed)`` of ``solver`` with the time budget ``timeout`` [s] bound.

    Every row's solver takes ``timeout``; a caller's own solver whose ``solve`` does not is
    called without it.
    """
    solve = solver.solve  # type: ignore[attr-defined]
    try:
        takes_timeout = "timeout" in inspect.signature(solve).parameters
    except (TypeError, ValueError):  # a compiled solve: assume the common interface
        takes_timeout = True
    if takes_timeout:
        return lambda target, seed: solve(target, seed, timeout=timeout)
    return lambda target, seed: solve(target, seed)
