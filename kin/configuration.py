"""A robot configuration: Pinocchio model and data with a joint vector, and frame getters.

Frames: ``world`` is the URDF root (``base_link``). Poses are ``T_world_frame`` (the frame's pose
expressed in the world frame, meters). Jacobians map joint velocities [rad/s] or [m/s] to the
frame's spatial velocity ``(v [m/s], omega [rad/s])``, expressed in the frame itself (``LOCAL``) or
in axes aligned with the world at the frame's origin (``LOCAL_WORLD_ALIGNED``).
"""

from __future__ import annotations

import math
from typing import Any, Literal, Protocol

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from .exceptions import FrameError, JointVectorError, NotWithinLimitsError
from .robot_model import RobotModel


class CollisionQueries(Protocol):
    """What :meth:`Configuration.collisions` asks: a :class:`kin.collision.CollisionChecker`."""

    def collisions(self, q: np.ndarray) -> tuple[Any, ...]:
        """The pairs in contact at ``q``."""

    def distance(self, q: np.ndarray) -> Any:
        """The closest pair at ``q``."""


_FLOAT64 = np.dtype(np.float64)

Reference = Literal["local", "local_world_aligned", "world"]

_REFERENCES = {
    "local": pin.ReferenceFrame.LOCAL,
    "local_world_aligned": pin.ReferenceFrame.LOCAL_WORLD_ALIGNED,
    "world": pin.ReferenceFrame.WORLD,
}


def as_joint_vector(robot: RobotModel, q: npt.ArrayLike) -> np.ndarray:
    """Validate and convert a joint vector (size and finiteness).

    Raises:
        JointVectorError: Wrong number of values, non-numeric or non-finite values.
    """
    try:
        array = np.array(q, dtype=float)
    except (TypeError, ValueError) as err:
        raise JointVectorError(f"joint values must be numbers, got {q!r}", robot.nq, -1) from err
    if array.ndim != 1:
        raise JointVectorError(
            f"joint values must be a flat vector of {robot.nq} numbers, got shape {array.shape}",
            robot.nq,
            array.size,
        )
    if array.size != robot.nq:
        raise JointVectorError(
            f"'{robot.name}' has {robot.nq} joints ({', '.join(robot.joint_names)}), "
            f"got {array.size} joint values",
            robot.nq,
            array.size,
        )
    if not np.isfinite(array).all():
        raise JointVectorError(
            f"joint values must be finite, got {array.tolist()}", robot.nq, array.size
        )
    return array


def limit_violations(
    robot: RobotModel, q: np.ndarray, tol: float = 0.0
) -> list[NotWithinLimitsError]:
    """The joints of ``q`` outside their limits (widened by ``tol`` [rad] or [m]), as errors."""
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    units = ["rad" if row.joint_type == "revolute" else "m" for row in robot.table.rows]
    return [
        NotWithinLimitsError(
            robot.joint_names[i], float(q[i]), float(lower[i]), float(upper[i]), units[i]
        )
        for i in range(robot.nq)
        if q[i] < lower[i] - tol or q[i] > upper[i] + tol
    ]


def seed_inside(robot: RobotModel, q: Any) -> Any:
    """The seed ``q`` moved into the joint limits: each joint clipped to its range.

    Continuous joints (:attr:`dh2urdf.DHRow.continuous`) are kept as given. A seed already inside
    is returned as it is (no copy); so is one that is not finite joint vectors (shape ``(nq,)``
    or ``(N, nq)``), for the caller's check to name.

    Args:
        robot: The robot.
        q: Joint vector (nq,) or vectors (N, nq) [rad] or [m].

    Returns:
        The nearest joint vector(s) inside the limits [rad] or [m].
    """
    if q is None:
        return q
    model = robot.model
    if q.__class__ is np.ndarray and q.dtype is _FLOAT64 and q.ndim == 1:
        # The common case, a float64 joint vector already inside: compared as Python floats
        # (about 1 us; the NumPy checks below cost about 5 us on every solve). A NaN fails a
        # comparison and goes the long way, which returns it as given.
        values = q.tolist()
        lower = model.lowerPositionLimit.tolist()
        if len(values) == len(lower):
            for low, value, high in zip(lower, values, model.upperPositionLimit.tolist()):
                if not low <= value <= high:
                    break
            else:
                return q
    try:
        values = np.asarray(q, dtype=float)
    except (TypeError, ValueError):
        return q
    if values.ndim not in (1, 2) or values.shape[-1] != robot.nq or not np.isfinite(values).all():
        return q
    lower, upper = model.lowerPositionLimit, model.upperPositionLimit
    if bool(np.all(values >= lower)) and bool(np.all(values <= upper)):
        return q
    continuous = np.array([row.continuous for row in robot.table.rows], dtype=bool)
    return np.where(continuous, values, np.minimum(np.maximum(values, lower), upper))


def default_seed(robot: RobotModel) -> np.ndarray:
    """The seed of a solve given none: zero, or the nearest joint vector to it inside the limits.

    An arm whose zero lies inside its limits starts from zero; Panda's joint 4 (range about
    [-3.07, -0.07] rad) starts at its upper limit.

    Returns:
        Joint vector (nq,) [rad] or [m].
    """
    return seed_inside(robot, np.zeros(robot.nq))


class Configuration:
    """Model, data and joint vector of a robot, with frame poses and Jacobians.

    Args:
        robot: The loaded robot.
        q: Initial joint vector [rad] or [m]; zeros if None.
        check_limits: Raise :class:`NotWithinLimitsError` when ``q`` is outside the limits.
    """

    def __init__(
        self, robot: RobotModel, q: npt.ArrayLike | None = None, check_limits: bool = False
    ):
        self.robot = robot
        self.model = robot.model
        self.data = robot.model.createData()
        self._fk_data = robot.model.createData()  # scratch of fk(): self.data stays at self.q
        self._frame_ids: dict[str, int] = {}
        self._nq = robot.nq
        self._shape = (robot.nq,)
        self._q = np.zeros(self._nq)
        self.update(self._q if q is None else q, check_limits=check_limits)

    @property
    def q(self) -> np.ndarray:
        """Current joint vector [rad] or [m] (a read-only view)."""
        view = self._q.view()
        view.setflags(write=False)
        return view

    def frame_id(self, frame: str) -> int:
        """Pinocchio index of a frame.

        Raises:
            FrameError: No frame of that name; the message lists the frames.
        """
        try:
            return self._frame_ids[frame]
        except KeyError:
            pass
        if not self.model.existFrame(frame):
            raise FrameError(frame, self.robot.frame_names)
        self._frame_ids[frame] = fid = self.model.getFrameId(frame)
        return fid

    def update(self, q: npt.ArrayLike, check_limits: bool = False) -> None:
        """Set the joint vector and compute the placements of all joints and frames.

        Args:
            q: Joint vector [rad] or [m].
            check_limits: Raise :class:`NotWithinLimitsError` when ``q`` is outside the limits.

        Raises:
            JointVectorError: Wrong size or non-finite values.
        """
        q = as_joint_vector(self.robot, q)
        if check_limits:
            violations = limit_violations(self.robot, q)
            if violations:
                raise violations[0]
        self._q = q
        pin.framesForwardKinematics(self.model, self.data, q)

    def fk(self, q: np.ndarray, frame: str = "tool") -> pin.SE3:
        """Fast path: pose ``T_world_frame`` of one frame at ``q``, without changing ``self.q``.

        Fastest with a float64 NumPy array of the model's size; anything else goes through
        :func:`as_joint_vector` (size and finiteness are always checked). The result is a copy.

        Raises:
            JointVectorError: Wrong size or non-finite values.
            FrameError: Unknown frame.
        """
        fid = self._frame_ids.get(frame)
        if fid is None:
            fid = self.frame_id(frame)
        if q.__class__ is not np.ndarray or q.dtype is not _FLOAT64 or q.shape != self._shape:
            q = as_joint_vector(self.robot, q)
        elif not math.isfinite(q.dot(q)):
            as_joint_vector(self.robot, q)  # raises the detailed error
        pin.forwardKinematics(self.model, self._fk_data, q)
        return pin.updateFramePlacement(self.model, self._fk_data, fid).copy()

    def transform_frame_to_world(self, frame: str = "tool") -> pin.SE3:
        """Pose ``T_world_frame`` of ``frame`` at the current ``q`` (a copy), meters."""
        return self.data.oMf[self.frame_id(frame)].copy()

    def frame_jacobian(
        self, frame: str = "tool", reference: Reference = "local_world_aligned"
    ) -> np.ndarray:
        """Frame Jacobian (6 x nq) at the current ``q``.

        Args:
            frame: Frame name.
            reference: ``"local"`` (axes of the frame) or ``"local_world_aligned"`` (world axes at
                the frame origin); ``"world"`` is Pinocchio's spatial Jacobian at the world origin.

        Returns:
            Rows ``(v [m/s], omega [rad/s])`` per unit joint velocity.
        """
        try:
            ref = _REFERENCES[reference]
        except KeyError:
            raise ValueError(
                f"unknown reference {reference!r}; choose one of: {', '.join(sorted(_REFERENCES))}"
            ) from None
        return pin.computeFrameJacobian(self.model, self.data, self._q, self.frame_id(frame), ref)

    def collisions(self, checker: CollisionQueries) -> tuple[Any, ...]:
        """The checked pairs in contact at the current ``q``, deepest first.

        Args:
            checker: A :class:`kin.collision.CollisionChecker` of this robot.

        Returns:
            :class:`kin.collision.Contact` per pair (depth [m], witness points in the world [m]).
        """
        return checker.collisions(self._q)

    def distance(self, checker: CollisionQueries) -> Any:
        """The closest checked pair at the current ``q``: a :class:`kin.collision.Closest`.

        Args:
            checker: A :class:`kin.collision.CollisionChecker` of this robot.

        Returns:
            The pair, its distance [m] (negative when the shapes overlap) and nearest points.
        """
        return checker.distance(self._q)

    def within_limits(self, tol: float = 0.0) -> bool:
        """Whether the current ``q`` is inside the joint limits (widened by ``tol``)."""
        return not limit_violations(self.robot, self._q, tol)
