"""The one interface of every IK solver (:class:`IKSolver`), and what a batch asks of it.

Every solver the solver table builds (:mod:`.solver_table`: the closed form, the numeric
pipeline, the paper's Newton-Raphson, and any of them wrapped by the collision-aware solver)
answers the same calls, as mink's and pink's solvers do: a ``name``, the ``robot`` it solves,
the ``target_kinds`` it takes, ``solve(target, seed=None, *, timeout=None, all_branches=False)``
and ``batch_route()``; ``route(target)``, the part of it that answers a target (decided once, by
the rules of :mod:`.routing`); and its parts: ``closed_form_kinds`` (every branch in one solve),
its ``numeric`` and ``partial`` solvers. No caller sniffs a signature, fishes an attribute out of
a solver or asks which class it is: what a batch of 7R poses reads of the numeric solver is its
:class:`FreeJointRoute`, asked through ``batch_route()`` (None: target by target); a path or the
collision search asks ``route``, ``closed_form_kinds``, ``numeric`` and ``partial``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy.typing as npt

from .result import IKResult
from .routing import Route

__all__ = ["FreeJointRoute", "IKSolver", "PartialSolver"]


@dataclass(frozen=True)
class FreeJointRoute:
    """What the batches' free-joint stage (:mod:`kin.ik.free_joint_batch`) reads of a solver.

    The numeric solver of an arm with a free-joint closed form (humanoid7, Panda, xArm7; not on
    an idealised table) gives it: its stage 0, every target's scan from its seed, runs for a whole
    batch at once.

    Attributes:
        closed: The free-joint closed form (:mod:`kin.ik.numeric.free_joint`).
        seeded_many: The compiled stage 0 of many targets
            (:func:`kin.ik.numeric.free_joint.compiled_seeded_many`), or None.
        compiled: Whether the compiled twin of the closed form is used.
        steps: The scan steps of the free joint [rad], coarse to fine.
        near_seed: The solver's ``near_seed`` (:attr:`kin.ik.numeric.settings.NumericSettings.near_seed`).
        seed_near: Largest joint move [rad] of a near seed's answer of its own free joint.
        seed_reach: A seed's tool within this [m] of the target is near it (with
            ``seed_radius``, the larger).
        seed_radius: See ``seed_reach`` [m].
        seed_turn: A near seed's tool is turned less than this [rad] from a pose.
    """

    closed: Any
    seeded_many: Any
    compiled: bool
    steps: tuple[float, ...]
    near_seed: bool
    seed_near: float
    seed_reach: float
    seed_radius: float
    seed_turn: float


class PartialSolver(Protocol):
    """What a solver of partial poses (:class:`kin.ik.partial_pose.PartialPoseIK`) answers."""

    def solve(
        self,
        target: Any,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        every_roll: bool = False,
    ) -> IKResult:
        """The answers inside the limits on the target's constrained components.

        ``every_roll``: the closed form's branches at every roll of its grid too.
        """
        ...


@runtime_checkable
class IKSolver(Protocol):
    """What every IK solver offers (closed form, numeric, Newton-Raphson, collision-aware).

    Attributes:
        name: The pipeline, as :attr:`IKResult.solver` reports it (``"closed_form:<structure>"``,
            ``"numeric"``, ``"nr"``).
        robot: The robot it solves.
    """

    name: str
    robot: Any

    @property
    def target_kinds(self) -> tuple[type, ...]:
        """The target classes :meth:`solve` accepts."""
        ...

    def solve(
        self,
        target: Any,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        all_branches: bool = False,
    ) -> IKResult:
        """Solve one target from a seed (joint vector [rad] / [m]) within ``timeout`` [s].

        ``all_branches``: every branch the solver can give (a 7R arm's free-joint grid); a
        solver that gives every branch anyway (a closed form) or only one ignores it.
        """
        ...

    def batch_route(self) -> FreeJointRoute | None:
        """The free-joint stage a batch of poses runs at once, or None (target by target)."""
        ...

    @property
    def closed_form_kinds(self) -> tuple[type, ...]:
        """The target classes one :meth:`solve` answers with every branch of a closed form.

        Empty for a search (numeric, Newton-Raphson): one answer near the seed.
        """
        ...

    @property
    def numeric(self) -> IKSolver | None:
        """The numeric solver that answers the targets the closed form does not take.

        The numeric solver itself; a closed form's numeric solver of the same robot (built on
        first use); None when the solver has none (Newton-Raphson).
        """
        ...

    def route(self, target: object) -> Route:
        """The part of the solver that answers ``target`` (:mod:`kin.ik.routing`).

        Decided when the solver is built, by the rule of its kind; ``REFUSED``: a kind it
        does not take.
        """
        ...

    @property
    def partial(self) -> PartialSolver | None:
        """The solver of partial poses (masked, axis, a pose on fewer than six joints), or None.

        A closed form's takes its branches as candidates (:mod:`kin.ik.partial_pose`).
        """
        ...
