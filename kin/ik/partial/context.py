"""What the partial-pose stages read: the arm's model handles and one call's inputs, frozen.

:func:`partial_context` builds a :class:`PartialContext` once per solver
(:class:`~kin.ik.partial_pose.PartialPoseIK`); each call adds a :class:`PartialCall`. The stages
(:mod:`.candidates`, :mod:`.least_squares`, :mod:`.starts`, :mod:`.search`, :mod:`.outcome`) take
them, not the solver, and measure joint vectors through the context's methods.

Units: joint values [rad] (or [m] for prismatic joints), lengths [m], angles [rad].
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import KinError, RobotModel, as_joint_vector
from kin.configuration import default_seed, seed_inside

from ..exceptions import StructureError, TargetError
from ..limit_rule import wrap_into
from ..reach import reach_bound
from ..result import IKSolution
from .task import PartialTask

__all__ = ["PartialCall", "PartialContext", "closed_form_structure", "partial_context"]

#: ``samples(position, rotation, end)``: joint vectors of the seed-table samples nearest a pose.
Samples = Callable[[np.ndarray, "np.ndarray | None", float], np.ndarray]
#: ``pose_candidates(position, rotations, seed)``: a closed form's named branches of full poses.
PoseCandidates = Callable[[np.ndarray, np.ndarray, np.ndarray], "list[tuple[np.ndarray, str]]"]


@dataclass(frozen=True, eq=False)
class PartialContext:
    """One partial-pose solver's model handles and hooks, as its stages see them.

    Attributes:
        robot: The robot.
        name: The pipeline reported in :attr:`~kin.ik.IKResult.solver`.
        samples: The seed-table samples nearest a pose, or None
            (:class:`~kin.ik.partial_pose.PartialPoseIK`'s ``samples``).
        pose_candidates: The closed form's branches of full poses, or None (the structure's own).
        structure: The closed-form structure of the forward table, or None.
        model: Pinocchio model; ``data`` its data and ``frame_id`` the tool frame's index.
        nq: Number of joints.
        lower: Lower joint limits [rad] (or [m]); ``upper`` the upper ones.
        revolute: Which joints are revolute (bool (nq,)); ``continuous`` which are continuous.
        search_lower: Limits of the least squares: continuous joints move through pi (+-3 pi,
            wrapped back after); ``search_upper`` the upper ones.
        directions: The table's joint directions: the structure's ``q'`` is ``direction * q``
            (:mod:`kin.ik.analytic.joint_directions`).
        reach: Upper bound of the tool's distance from the base origin [m].
        base: The base origin in the world frame [m] (3,).
    """

    robot: RobotModel
    name: str
    samples: Samples | None
    pose_candidates: PoseCandidates | None
    structure: Any
    model: pin.Model
    data: pin.Data
    frame_id: int
    nq: int
    lower: np.ndarray
    upper: np.ndarray
    revolute: np.ndarray
    continuous: np.ndarray
    search_lower: np.ndarray
    search_upper: np.ndarray
    directions: Any
    reach: float
    base: np.ndarray

    def seed(self, seed: npt.ArrayLike | None) -> np.ndarray:
        """The seed checked and moved into the limits (None: :func:`kin.configuration.default_seed`).

        Raises:
            TargetError: A seed of the wrong size or with a value that is not finite.
        """
        if seed is None:
            return default_seed(self.robot)
        try:
            return seed_inside(self.robot, as_joint_vector(self.robot, seed))  # type: ignore[no-any-return]
        except KinError as err:
            raise TargetError(f"seed of '{self.robot.name}': {err}") from err

    def fk(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The tool's position [m] (3,) and rotation (3, 3) in the world frame at ``q``."""
        pin.forwardKinematics(self.model, self.data, q)
        pose = pin.updateFramePlacement(self.model, self.data, self.frame_id)
        return pose.translation.copy(), pose.rotation.copy()

    def cost(self, task: PartialTask, q: np.ndarray) -> float:
        """The weighted squared error of ``q`` on the constrained rows ([m^2])."""
        p, rotation = self.fk(q)
        e = task.error(p, rotation)[task.rows] * task.weights
        return float(e @ e)

    def inside(self, q: np.ndarray) -> bool:
        """Whether every joint of ``q`` is inside its limits (no slack)."""
        return bool(np.all(q >= self.lower) and np.all(q <= self.upper))

    def wrapped(self, q: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray, bool]:
        """``q`` with each revolute angle moved by 2 pi into the limits, nearest the seed.

        The closed forms' choice of copy (:func:`~kin.ik.limit_rule.wrap_into`); whether
        every joint is inside its limits is then judged without their slack.
        """
        out = q.copy()
        for i in np.flatnonzero(self.revolute).tolist():
            out[i] = wrap_into(float(out[i]), float(seed[i]), self.lower[i], self.upper[i])[0]
        return out, self.inside(out)

    def measured(
        self, task: PartialTask, q: np.ndarray, label: str
    ) -> tuple[IKSolution, float, float]:
        """``q`` measured by Pinocchio on the constrained components.

        Continuous joints are wrapped into [-pi, pi] first. Returns the solution and its
        position and rotation errors [m], [rad].
        """
        if self.continuous.any():
            q = q.copy()
            q[self.continuous] = np.remainder(q[self.continuous] + math.pi, 2.0 * math.pi) - math.pi
        p, rotation = self.fk(q)
        position_error, rotation_error = task.errors(task.error(p, rotation))
        rotation_value = rotation_error if task.rotation_rows else None
        solution = IKSolution(q, label, self.inside(q), position_error, rotation_value)
        return solution, position_error, rotation_error

    def judged(
        self, task: PartialTask, q: np.ndarray, label: str, position_tol: float, rotation_tol: float
    ) -> IKSolution | None:
        """The solution ``q`` measured on the constrained components; None when off target."""
        solution, position_error, rotation_error = self.measured(task, q, label)
        if not (position_error < position_tol and rotation_error < rotation_tol):
            return None
        return solution


@dataclass(frozen=True)
class PartialCall:
    """One call's inputs (:meth:`~kin.ik.partial_pose.PartialPoseIK.solve`).

    Attributes:
        seed: The checked seed inside the limits [rad] (or [m]).
        start: ``time.perf_counter()`` when the call began [s].
        deadline: ``time.perf_counter()`` value of the time cap [s].
        random_seed: Seed of the random starts.
        position_tol: Success tolerance on the constrained position components [m].
        rotation_tol: Success tolerance on the constrained rotation components [rad].
        every_roll: The branches of every roll of the grid too.
    """

    seed: np.ndarray
    start: float
    deadline: float
    random_seed: int
    position_tol: float
    rotation_tol: float
    every_roll: bool


def partial_context(
    robot: RobotModel,
    structure: Any,
    name: str,
    samples: Samples | None,
    pose_candidates: PoseCandidates | None,
) -> PartialContext:
    """The context of ``robot``'s solver (``structure`` None: :func:`closed_form_structure`)."""
    model = robot.model
    lower = model.lowerPositionLimit.copy()
    upper = model.upperPositionLimit.copy()
    continuous = np.array([row.continuous for row in robot.table.rows], dtype=bool)
    return PartialContext(
        robot=robot,
        name=name,
        samples=samples,
        pose_candidates=pose_candidates,
        structure=structure if structure is not None else closed_form_structure(robot),
        model=model,
        data=model.createData(),
        frame_id=model.getFrameId(robot.tool_frame),
        nq=model.nq,
        lower=lower,
        upper=upper,
        revolute=np.array([row.joint_type == "revolute" for row in robot.table.rows]),
        continuous=continuous,
        search_lower=np.where(continuous, -3.0 * math.pi, lower),
        search_upper=np.where(continuous, 3.0 * math.pi, upper),
        directions=robot.table.directions,
        reach=reach_bound(robot),
        base=np.asarray(robot.table.T_world_base, dtype=float)[:3, 3].copy(),
    )


def closed_form_structure(robot: RobotModel) -> Any:
    """The closed-form structure of the robot's table (or of its idealised table), or None."""
    from ..analytic.idealised import idealise
    from ..analytic.joint_directions import forward_table
    from ..analytic.registry import recognise

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
