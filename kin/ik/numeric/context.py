"""What the numeric stages read: the settings and the arm's model handles, frozen.

The stages (:mod:`.free_joint`, :mod:`.starts`, :mod:`.restarts`; :class:`~.search.Stage`) and
the shared :class:`~.search.Search` take a :class:`NumericContext` and the search, not the solver:
they import this module, which imports none of theirs, so ``kin/ik/numeric`` has no import circle.
:class:`~.solver.NumericIK` builds one context per solver (:func:`~.solver.build_context`); a
test may build its own.

Units: joint values [rad] (or [m] for prismatic joints), lengths [m], angles [rad].
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import KinError, RobotModel, as_joint_vector

from ..exceptions import TargetError
from ..judge import ToolJudge
from ..reach import Reach, arm_reach
from .differential_ik import DifferentialIK
from .numeric_target import NumericTarget
from .settings import NumericSettings

#: NumPy's (interned) float64 dtype: an identity check is the seed's cheapest test.
_FLOAT64 = np.dtype(np.float64)


@dataclass(frozen=True, eq=False)
class NumericContext:
    """One solver's settings and model handles, as its stages see them.

    Attributes:
        settings: The solver's settings (:class:`~.settings.NumericSettings`).
        robot: The robot.
        nq: Number of joints.
        judge: The judge of every answer (Pinocchio's FK of the tool, the limits), in ``data``.
        search_model: Pinocchio model whose limits clamp damped Newton (continuous joints:
            +-3 pi); ``data`` its data (the judge's too) and ``frame_id`` the tool frame's index.
        lower: Lower joint limits [rad] (or [m]), an array; ``upper`` the upper ones.
        lows: The lower limits as floats (the stages' checks run on Python floats); ``highs``
            the upper ones.
        draw_lower: Lower end of the box random starts are drawn from [rad] (or [m]): ``lower``
            but for a long rail's (:func:`.sampling_box.sampling_limits`); ``draw_upper`` the
            upper end.
        continuous: Indices of the continuous joints: damped Newton moves them freely and
            answers are wrapped back into [-pi, pi].
        reach: Upper bound of the tool's distance from the base origin [m] (triangle
            inequality).
        base_origin: The base origin in the world frame [m].
        closed_form: The free-joint closed form (:mod:`.free_joint`), or None.
        idealised: The idealised table the closed form fits when the true one misses it by
            rounding (its answers are polished on the true chain), else None.
        compiled: Whether the closed form runs its compiled twin (asked for and built).
        compiled_step: Whether damped Newton's steps run their compiled twin (asked for and
            built).
    """

    settings: NumericSettings
    robot: RobotModel
    nq: int
    judge: ToolJudge
    search_model: pin.Model
    data: pin.Data
    frame_id: int
    lower: np.ndarray
    upper: np.ndarray
    lows: tuple[float, ...]
    highs: tuple[float, ...]
    draw_lower: np.ndarray
    draw_upper: np.ndarray
    continuous: tuple[int, ...]
    reach: float
    base_origin: tuple[float, float, float]
    closed_form: Any
    idealised: Any
    compiled: bool
    compiled_step: bool

    @property
    def arm_reach(self) -> Reach:
        """The tool's largest distance from the base (sampled, :func:`kin.ik.reach.arm_reach`)."""
        return arm_reach(self.robot)

    @functools.cached_property
    def differential(self) -> DifferentialIK:
        """The mink differential IK (its MuJoCo model loaded on first use, then kept)."""
        return DifferentialIK(self.robot, solver=self.settings.qp_solver)

    @property
    def differential_loaded(self) -> bool:
        """Whether :attr:`differential` is loaded (a QP run costs no model load)."""
        return "differential" in self.__dict__

    def seed_vector(self, seed_q: npt.ArrayLike) -> np.ndarray:
        """The caller's seed as a finite joint vector (never written into).

        Raises:
            TargetError: Not one finite value per joint.
        """
        if (
            type(seed_q) is np.ndarray
            and seed_q.shape == (self.nq,)
            and seed_q.dtype is _FLOAT64
            and math.isfinite(sum(seed_q.tolist()))
        ):
            return seed_q  # already valid: no copy, no validation
        try:
            return as_joint_vector(self.robot, seed_q)
        except KinError as err:
            raise TargetError(f"seed of '{self.robot.name}': {err}") from err

    def posture_inside(self, target: NumericTarget, posture: np.ndarray) -> NumericTarget:
        """``target`` with its posture preference checked and moved into the limits.

        A preference outside the limits pulls toward the nearest joint vector inside.

        Raises:
            TargetError: The posture has not one value per joint.
        """
        if posture.shape != (self.nq,):
            raise TargetError(
                f"posture of '{self.robot.name}' must have {self.nq} values, got {posture.size}"
            )
        lower, upper = self.lower, self.upper
        if np.all(posture >= lower) and np.all(posture <= upper):
            return target
        clipped = np.minimum(np.maximum(posture, lower), upper)
        return NumericTarget(target.position, target.rotation, clipped)

    def distance_from_base(self, position: np.ndarray) -> float:
        """Distance of a world point from the base origin [m]."""
        x, y, z = position.tolist() if position.__class__ is np.ndarray else position
        bx, by, bz = self.base_origin
        return math.hypot(x - bx, y - by, z - bz)  # no overflow for 1e308
