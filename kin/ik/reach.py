"""How far an arm's tool reaches from its base: a sure bound and the real maximum.

Two numbers, both distances of the tool point from the base origin (the origin of
``T_world_base``, in the world frame) [m]:

- :attr:`Reach.bound`: every link length, offset, prismatic travel and the tool offset laid end
  to end (the triangle inequality). Surely no smaller than any distance the tool reaches, and
  free to compute: a target beyond it is answered ``out_of_reach`` before any search.
- :attr:`Reach.maximum`: the largest distance the tool reaches inside the joint limits, found by
  sampling :data:`SAMPLES` joint vectors (NumPy DH product, seeded) and maximizing the distance
  from the :data:`STARTS` farthest ones with SciPy's bounded L-BFGS-B on Pinocchio's FK and
  Jacobian. It is what messages print ("the arm reaches 0.652 m"): for an ABB IRB 120 the bound
  is 1.004 m and the maximum 0.652 m. Being found by a search it could be short of the true
  maximum; the tests compare it with dense sampling and with the closed forms' distances.

:func:`arm_reach` computes both once per robot (a few milliseconds) and keeps them.

A long rail (a mobile base's prismatic joint, +-999,999 m on the Robotics Toolbox's Frankie and
Fetch; :mod:`kin.ik.numeric.sampling_box`) carries the tool as far as it runs along the directions
its axis takes, so a distance from the base says nothing there. :meth:`Reach.distance` and
:attr:`Reach.maximum` then measure across those directions (:attr:`Reach.across`, the projection
on what the rail cannot change: the height on Frankie, whose rail turns in the floor's plane;
``bound`` stays a sure bound), and the samples draw the rail within the arm's size (its value
changes no distance across). Every other arm: plain distances, the same samples as before.
"""

from __future__ import annotations

import math
import threading
import weakref
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from kin import RobotModel
from kin.batch_fk import batch_tool_positions
from kin.ik.numeric.sampling_box import sampling_limits

#: Joint vectors sampled for :attr:`Reach.maximum`.
SAMPLES = 4096
#: The farthest samples refined by local maximization.
STARTS = 6
#: Second entropy word of the sampling's random generator (keeps it apart from other streams).
_REACH_STREAM = 0x2EAC4


@dataclass(frozen=True)
class Reach:
    """The tool's distances from the base origin.

    Attributes:
        origin: The base origin in the world frame [m], shape (3,).
        bound: Sure upper bound of the distance (links laid end to end) [m].
        maximum: Largest distance found inside the joint limits [m] (at most ``bound``).
        across: For an arm with a long rail, the projection (3 x 3, world frame) on the
            directions no long rail moves the tool along: distances are measured after it.
            None for every other arm.
    """

    origin: np.ndarray
    bound: float
    maximum: float
    across: np.ndarray | None = None

    def distance(self, position: np.ndarray) -> float:
        """Distance of a world point from the base origin [m] (across a long rail's directions)."""
        gap = np.asarray(position, dtype=float) - self.origin
        x, y, z = (gap if self.across is None else self.across @ gap).tolist()
        return math.hypot(x, y, z)  # no overflow for 1e308


_CACHE: weakref.WeakKeyDictionary[RobotModel, Reach] = weakref.WeakKeyDictionary()
_LOCK = threading.Lock()


def arm_reach(robot: RobotModel) -> Reach:
    """The :class:`Reach` of ``robot`` (computed on first use, then kept with the robot)."""
    with _LOCK:
        found = _CACHE.get(robot)
        if found is None:
            found = _CACHE[robot] = _compute(robot)
        return found


def known_reach(robot: RobotModel) -> Reach | None:
    """The :class:`Reach` of ``robot`` if already computed, else None (never computes)."""
    return _CACHE.get(robot)


#: Expected time of a first :func:`arm_reach` [s] (about 10 ms measured).
REACH_COST = 0.03


def reach_bound(robot: RobotModel) -> float:
    """:attr:`Reach.bound` of ``robot`` [m]: the table's lengths laid end to end."""
    total = 0.0
    for row in robot.table.rows:
        total += abs(row.a) + abs(row.d)
        if row.joint_type == "prismatic":
            total += max(abs(row.lower), abs(row.upper))
    tool = np.asarray(robot.table.T_last_tool, dtype=float)[:3, 3]
    return float(total + np.linalg.norm(tool))


def _compute(robot: RobotModel) -> Reach:
    origin = np.asarray(robot.table.T_world_base, dtype=float)[:3, 3].copy()
    bound = reach_bound(robot)
    model = robot.model
    limits = (model.lowerPositionLimit.copy(), model.upperPositionLimit.copy())
    lower, upper = sampling_limits(robot.table, *limits)  # those arrays but for a long rail
    rng = np.random.default_rng([0, _REACH_STREAM])
    q = rng.uniform(lower, upper, size=(SAMPLES, model.nq))
    tool = batch_tool_positions(robot.table, q)
    points, across = tool - origin, None
    if lower is not limits[0]:  # a long rail: distances across the directions it runs along
        across = _across(robot, q, tool, upper - lower < limits[1] - limits[0])
        points = points @ across
    distances = np.einsum("ij,ij->i", points, points)
    order = np.argsort(distances)[::-1][:STARTS]
    best = math.sqrt(float(distances[order[0]]))
    data = model.createData()
    frame = model.getFrameId(robot.tool_frame)
    for i in order.tolist():
        best = max(best, _farthest(model, data, frame, q[i], lower, upper, origin, across))
    return Reach(origin, bound, min(best, bound), across)


def _across(robot: RobotModel, q: np.ndarray, tool: np.ndarray, rails: np.ndarray) -> np.ndarray:
    """The projection on the directions no long rail moves the tool along, world frame (3 x 3).

    ``q``: the samples [rad, m], ``tool``: their tool positions [m], ``rails``: which joints are
    long rails. A rail's direction at each sample is the tool's move for one more meter of it
    (exact: the tool moves linearly along a prismatic joint); the directions they span go.
    """
    directions = []
    for i in np.flatnonzero(rails).tolist():
        moved = q.copy()
        moved[:, i] += 1.0
        directions.append(batch_tool_positions(robot.table, moved) - tool)
    stacked = np.concatenate(directions)
    _, values, vt = np.linalg.svd(stacked, full_matrices=False)  # vt: 3 x 3
    spanned = int(np.count_nonzero(values > 1e-6 * values[0]))
    rest = vt[spanned:]
    return rest.T @ rest


def _farthest(
    model: pin.Model,
    data: pin.Data,
    frame: int,
    q0: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    origin: np.ndarray,
    across: np.ndarray | None,
) -> float:
    """The largest tool distance from ``origin`` found by projected gradient ascent from ``q0`` [m].

    Steps along ``J^T (p - origin)`` (that gap projected by ``across`` if given) clamped to the limits, growing by half after a gain and
    halved after a loss (no SciPy optimizer: importing one costs more than the whole search).
    """
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    def square(q: np.ndarray) -> tuple[float, np.ndarray]:
        pin.forwardKinematics(model, data, q)
        gap = pin.updateFramePlacement(model, data, frame).translation - origin
        if across is not None:  # the distance across a long rail's directions
            gap = across @ gap
        return float(gap @ gap), gap

    q = q0.copy()
    value, gap = square(q)
    step = 0.1  # [rad] (or [m]) of the largest joint change
    for _ in range(_ITERATIONS):
        pin.computeJointJacobians(model, data, q)
        direction = pin.getFrameJacobian(model, data, frame, world)[:3].T @ gap
        largest = float(np.abs(direction).max())
        if not largest > 0.0:
            break
        trial = np.minimum(np.maximum(q + (step / largest) * direction, lower), upper)
        trial_value, trial_gap = square(trial)
        if trial_value > value:
            q, value, gap, step = trial, trial_value, trial_gap, step * 1.5
        else:
            value, gap = square(q)  # data back at q for the next Jacobian
            step *= 0.5
            if step < 1e-9:
                break
    return math.sqrt(value)


#: Gradient steps per start of :func:`_farthest`.
_ITERATIONS = 150
