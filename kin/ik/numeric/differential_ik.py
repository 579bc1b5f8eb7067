"""Differential IK on mink: a QP per step, with the joint limits as hard constraints.

The MuJoCo model comes from the same generated URDF as Pinocchio's (``kin.mujoco_model``, fixed
links kept, so the ``tool`` body exists). Each step solves, through qpsolvers,

    min_dq  sum_tasks |W (J dq + gain * e)|^2 + damping |dq|^2
    s.t.    q + dq inside the joint limits (mink ``ConfigurationLimit``)
            |dq / dt| <= joint velocity limits (mink ``VelocityLimit``, control loops only)

with a ``FrameTask`` on the tool (full pose, or position only with a zero orientation cost) and
a low-cost ``PostureTask`` that settles the redundancy. :meth:`DifferentialIK.step` is one
velocity-limited step for a control loop; :meth:`DifferentialIK.solve` iterates steps to the
tolerance, measured by Pinocchio.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from kin import RobotModel

from ..exceptions import IKError
from .numeric_target import POSITION_TOLERANCE, ROTATION_TOLERANCE, NumericTarget, measure

logger = logging.getLogger(__name__)

QP_SOLVERS = ("daqp", "osqp")


def import_mink() -> Any:
    """The mink module, imported once per process (about 0.3 s with MuJoCo, on this machine).

    :func:`~.build_context.build_context` calls it when a numeric solver is built, so that the
    import is paid there and not by the first call that falls back to a QP run.

    Raises:
        IKError: mink (or MuJoCo) is not installed.
    """
    try:
        import mink
    except ImportError as err:  # pragma: no cover
        raise IKError("mink is not installed: pip install mink") from err
    return mink


@dataclass(frozen=True)
class DifferentialOutcome:
    """Result of :meth:`DifferentialIK.solve`.

    Attributes:
        q: Final joint vector [rad] (inside the limits).
        converged: Pinocchio measures ``q`` on target within the tolerances.
        iterations: QP steps taken.
        position_error: [m], measured by Pinocchio.
        rotation_error: [rad], measured by Pinocchio (0 for position-only targets).
    """

    q: np.ndarray
    converged: bool
    iterations: int
    position_error: float
    rotation_error: float


class DifferentialIK:
    """mink differential IK of one robot's tool frame.

    Args:
        robot: The robot (its URDF is loaded into MuJoCo; its Pinocchio model judges).
        solver: QP solver name for qpsolvers: ``"daqp"`` or ``"osqp"``.
        position_cost: Frame task cost on the position [cost] / [m].
        orientation_cost: Frame task cost on the orientation [cost] / [rad] (ignored for
            position-only targets).
        posture_cost: Posture task cost [cost] / [rad]; small, so it only uses the redundancy.
        damping: Levenberg-Marquardt damping of the QP [cost] / [rad^2].
        velocity_limit: Joint velocity bound for :meth:`step` [rad/s], or None.

    Raises:
        IKError: Unknown QP solver, or mink / MuJoCo missing.
    """

    def __init__(
        self,
        robot: RobotModel,
        solver: str = "daqp",
        position_cost: float = 1.0,
        orientation_cost: float = 0.5,
        posture_cost: float = 1e-4,
        damping: float = 1e-6,
        velocity_limit: float | None = None,
    ):
        if solver not in QP_SOLVERS:
            raise IKError(f"unknown QP solver {solver!r}; choose one of: {', '.join(QP_SOLVERS)}")
        mink = import_mink()
        from kin.mujoco_model import load_mujoco_model

        self.robot = robot
        self.solver = solver
        self.damping = damping
        self._mink = mink
        self.mj_model = load_mujoco_model(robot)
        self.configuration = mink.Configuration(self.mj_model)
        self._orientation_cost = orientation_cost
        self.frame_task = mink.FrameTask(
            frame_name=robot.tool_frame,
            frame_type="body",
            position_cost=position_cost,
            orientation_cost=orientation_cost,
            lm_damping=1e-6,
        )
        self.posture_task = mink.PostureTask(self.mj_model, cost=posture_cost)
        self.posture_task.set_target(np.zeros(robot.nq))
        self.configuration_limit = mink.ConfigurationLimit(self.mj_model, gain=1.0)
        self.velocity_limit = None
        if velocity_limit is not None:
            self.velocity_limit = mink.VelocityLimit(
                self.mj_model, {name: velocity_limit for name in robot.joint_names}
            )
        self._data = robot.model.createData()
        self._target: NumericTarget | None = None

    def set_target(self, target: NumericTarget) -> None:
        """Set the tool target (and the posture preference when the target has one)."""
        rotation = np.eye(3) if target.rotation is None else target.rotation
        self.frame_task.set_orientation_cost(
            0.0 if target.position_only else self._orientation_cost
        )
        self.frame_task.set_target(
            self._mink.SE3.from_rotation_and_translation(
                self._mink.SO3.from_matrix(rotation), np.asarray(target.position, dtype=float)
            )
        )
        if target.posture is not None:
            self.posture_task.set_target(target.posture)
        self._target = target

    def step(self, q: npt.ArrayLike, dt: float) -> np.ndarray:
        """One QP step from ``q`` toward the target: the next joint vector after ``dt``.

        With ``velocity_limit`` set, every joint moves at most ``velocity_limit * dt``, which
        makes this the step of a control loop (e.g. along a Cartesian path).

        Args:
            q: Current joint vector [rad], inside the limits.
            dt: Control period [s].

        Raises:
            IKError: No target set, or the QP solver fails.
        """
        if self._target is None:
            raise IKError("no target: call set_target() first")
        self.configuration.update(np.asarray(q, dtype=float))
        limits: list[Any] = [self.configuration_limit]
        if self.velocity_limit is not None:
            limits.append(self.velocity_limit)
        try:
            velocity = self._mink.solve_ik(
                self.configuration,
                [self.frame_task, self.posture_task],
                dt,
                self.solver,
                damping=self.damping,
                limits=limits,
            )
        except self._mink.NoSolutionFound as err:
            raise IKError(
                f"QP solver {self.solver!r} found no step at q={np.asarray(q).tolist()}"
            ) from err
        self.configuration.integrate_inplace(velocity, dt)
        return self.configuration.q.copy()

    def solve(
        self,
        q0: npt.ArrayLike,
        max_iterations: int = 100,
        position_tol: float = POSITION_TOLERANCE,
        rotation_tol: float = ROTATION_TOLERANCE,
        deadline: float | None = None,
    ) -> DifferentialOutcome:
        """Iterate full QP steps (``dt = 1``) from ``q0`` until Pinocchio measures the target.

        Args:
            q0: Start joint vector [rad] (clipped into the limits).
            max_iterations: Maximum number of QP steps.
            position_tol: Position tolerance [m].
            rotation_tol: Rotation tolerance [rad].
            deadline: Stop after this ``time.perf_counter()`` value [s], or None.
        """
        if self._target is None:
            raise IKError("no target: call set_target() first")
        model = self.robot.model
        q = np.clip(np.asarray(q0, dtype=float), model.lowerPositionLimit, model.upperPositionLimit)
        iterations = 0
        while True:
            result = measure(self.robot, self._data, q, self._target)
            if result.on_target(position_tol, rotation_tol) or iterations >= max_iterations:
                break
            if deadline is not None and time.perf_counter() > deadline:
                break
            q_next = self.step(q, 1.0)
            # The integration may overshoot a limit by rounding: keep q inside.
            q = np.clip(q_next, model.lowerPositionLimit, model.upperPositionLimit)
            iterations += 1
        return DifferentialOutcome(
            q=q,
            converged=result.on_target(position_tol, rotation_tol),
            iterations=iterations,
            position_error=result.position_error,
            rotation_error=result.rotation_error,
        )


def tool_pose_mujoco(ik: DifferentialIK, q: npt.ArrayLike) -> pin.SE3:
    """``T_world_tool`` computed by MuJoCo (for comparison with Pinocchio) [m]."""
    ik.configuration.update(np.asarray(q, dtype=float))
    matrix = ik.configuration.get_transform_frame_to_world(ik.robot.tool_frame, "body").as_matrix()
    return pin.SE3(matrix[:3, :3], matrix[:3, 3])
