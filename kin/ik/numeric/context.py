"""What the numeric stages read of the solver: the arm, its judge and limits, the settings.

The stages (:mod:`.free_joint`, :mod:`.starts`, :mod:`.restarts`; :class:`~.search.Stage`) and
the shared :class:`~.search.Search` take a :class:`NumericContext` and the search, not the solver
class: they import this module, which imports none of theirs, so ``kin/ik/numeric`` has no
import circle. :class:`~.solver.NumericIK` is the context (it meets the protocol); a test may hand a
stage any object that does.

Units: joint values [rad] (or [m] for prismatic joints), lengths [m], angles [rad].
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import pinocchio as pin

if TYPE_CHECKING:
    from kin import RobotModel

    from ..judge import ToolJudge
    from ..reach import Reach
    from .differential_ik import DifferentialIK


class NumericContext(Protocol):
    """The solver as its stages see it (see :class:`~.solver.NumericIK` for each setting)."""

    robot: RobotModel
    nq: int
    #: The judge of every answer (Pinocchio's FK of the tool, the limits), in :attr:`data`.
    judge: ToolJudge
    #: Pinocchio model whose limits clamp damped Newton (continuous joints: +-3 pi), its data
    #: and the tool frame's index.
    search_model: pin.Model
    data: pin.Data
    frame_id: int
    #: Joint limits, as arrays and as lists of floats.
    lower: np.ndarray
    upper: np.ndarray
    lows: list[float]
    highs: list[float]
    #: Indices of the continuous joints (answers wrapped into [-pi, pi]).
    continuous: tuple[int, ...]
    #: Upper bound of the tool's distance from the base origin [m].
    reach: float
    #: The free-joint closed form (:mod:`.free_joint`), or None; the idealised table it fits.
    closed_form: Any
    idealised: Any
    compiled: bool
    compiled_step: bool
    closed_form_starts: int
    closed_form_steps: tuple[float, ...]
    near_seed: bool
    seed_near: float
    seed_radius: float
    seed_reach: float
    seed_turn: float
    seed_leash: float
    patience: int | None
    nearest: int
    newton_iterations: int
    random_starts: int
    random_between: int
    random_patience: int | None
    qp_iterations: int

    @property
    def arm_reach(self) -> Reach:
        """The tool's largest distance from the base (sampled)."""
        ...

    @property
    def differential(self) -> DifferentialIK:
        """The mink differential IK (its MuJoCo model loaded on first use)."""
        ...

    @property
    def differential_loaded(self) -> bool:
        """Whether :attr:`differential` is loaded (no load to pay)."""
        ...

    def distance_from_base(self, position: np.ndarray) -> float:
        """Distance of a world point from the base origin [m]."""
        ...
