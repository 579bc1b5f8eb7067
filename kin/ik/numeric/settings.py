"""The numeric solver's settings: one frozen value, each with its unit and default.

:class:`~.solver.NumericIK` builds a :class:`NumericSettings` from its keyword arguments (or takes
one); its stages read it through their :class:`~.context.NumericContext`. This module imports
none of the stages', so ``kin/ik/numeric`` keeps no import circle.

Units: joint values and angles [rad] (or [m] for prismatic joints), lengths [m].
"""

from __future__ import annotations

from dataclasses import dataclass

#: Damped Newton starts of one solve (the caller's seed, seed-table samples, random starts and
#: the polish of every mink QP run together, one QP run every ``random_between + 1`` starts): the
#: work of a search that finds nothing, 50-150 ms on one core of a 2-core machine. On 450 full
#: poses near the limits of humanoid7, Panda and puma560 (stages 1-3 alone) it finds 443, as the
#: former 50 ms budget did with a QP run every 4 starts at four times the cost.
MAX_ATTEMPTS = 200

#: Default free-joint scan steps of the closed form [rad], coarse to fine (with or without the
#: compiled twins: the same answers either way).
DEFAULT_CLOSED_FORM_STEPS = (0.05, 0.01)


@dataclass(frozen=True)
class NumericSettings:
    """How :class:`~.solver.NumericIK` searches: the work, the starts, the seed's pull, the twins.

    Attributes:
        table_size: Number of sampled poses in the seed table.
        qp_solver: QP solver of the mink fallback (``"daqp"`` or ``"osqp"``).
        nearest: Number of seed-table starts tried before the fallback.
        newton_iterations: Damped Newton steps per start.
        qp_iterations: mink QP steps per fallback run.
        patience: A nearest start is abandoned after this many damped Newton steps in a row
            that do not halve its error (None: always ``newton_iterations`` steps).
        random_starts: Random starts tried after the nearest ones and before the first mink
            QP run (a QP run costs as much as dozens of damped Newton starts).
        max_attempts: The work of one solve: damped Newton starts in all (seeded draws), after
            which a search without an answer says ``not_found``; a solve's own ``max_attempts``
            overrides it.
        random_between: Random starts between two mink QP runs (a QP run of ``qp_iterations``
            steps costs as much as about 20 random starts and finds as many answers near the
            limits).
        random_patience: ``patience`` of the random starts (a mink QP run is always followed
            by ``newton_iterations`` damped Newton steps).
        seed_radius: For a redundant target (more joints than it constrains), a caller's seed
            whose tool is within this of the target [m] (rotations weighed as in the seed
            table's pose embedding) is the first start of damped Newton, with the whole
            ``newton_iterations`` budget: the answer is the solution near the seed. A farther
            seed goes first only when its tool is at least as near as the nearest sample's.
        seed_reach: For a redundant target, a caller's seed whose tool is farther than
            ``seed_radius`` but within this [m] (and turned at most ``seed_turn``) is the first
            start of damped Newton too, on a ``seed_leash``; so is it in the closed-form stage
            when the closed form's answer from it is farther than ``seed_near`` from it (or there
            is none).
        seed_turn: The largest rotation angle between the seed's tool and a full-pose target for
            ``seed_reach`` [rad] (a seed turned farther has no solution near it).
        seed_leash: A damped Newton run from a seed beyond ``seed_radius`` gives up as soon as it
            has moved farther than this from the seed (largest joint change [rad]), or stalls
            (``patience``): the answer near the seed is not where it goes, and samples' starts
            are cheaper.
        seed_near: The closed form's answer from a seed near the target (within ``seed_reach``)
            is taken when no joint is farther than this from the seed's [rad]; else damped Newton
            from the seed runs first, and the nearer of the two answers is returned.
        near_seed: Whether the closed-form stage checks that its answer from the caller's seed
            is near the seed when the seed's tool is near the target (``seed_reach``,
            ``seed_near``). It costs one forward kinematics of the seed per seeded solve (about
            1.3 us, 10-20 % of a closed-form answer's time), hence off by default: without it,
            the closed form keeps the seed's free joint and its branch may be far.
        closed_form: Try the free-joint closed form first when the arm has one
            (:func:`~.free_joint.free_joint_closed_form`; False: damped Newton and mink only).
        closed_form_starts: Seed-table samples tried by the closed form before damped Newton.
        closed_form_steps: Free-joint scan steps of the first closed-form starts [rad], coarse
            to fine: when a start's free joint gives no branch inside the limits, it is scanned
            outward from there, on the coarse grid first (any sequence; kept as a tuple).
        compiled: Run the free-joint closed form's compiled twin (``_closed7`` for humanoid7's
            structure, ``_shoulder7`` for the spherical shoulder) when it is built (False: the
            Python module). Both return the same joint vectors; the twin is faster. Damped
            Newton's steps take their compiled twin too (``_damped_step``; False: NumPy's, the
            same joint vectors to rounding).
        prepare: Build (or load) the seed table when the solver is built (False: on the first
            solve that needs it, before its search, whatever its timeout).
    """

    table_size: int = 20000
    qp_solver: str = "daqp"
    nearest: int = 8
    newton_iterations: int = 20
    qp_iterations: int = 25
    patience: int | None = 3
    random_starts: int = 10
    max_attempts: int = MAX_ATTEMPTS
    random_between: int = 19
    random_patience: int | None = 3
    seed_radius: float = 0.1
    seed_reach: float = 0.45
    seed_turn: float = 1.2
    seed_leash: float = 0.75
    seed_near: float = 0.4
    near_seed: bool = False
    closed_form: bool = True
    closed_form_starts: int = 32
    closed_form_steps: tuple[float, ...] = DEFAULT_CLOSED_FORM_STEPS
    compiled: bool = True
    prepare: bool = True

    def __post_init__(self) -> None:
        """Keep ``closed_form_steps`` a tuple (a list given is copied: the value stays frozen)."""
        object.__setattr__(self, "closed_form_steps", tuple(self.closed_form_steps))
