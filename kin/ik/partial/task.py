"""One partial target as the search sees it: its rows, its errors and the rotations that meet it.

Units: positions [m], rotations [rad] (rotation matrices (3, 3)), world axes.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..targets.target import TOOL_AXES, AxisTarget, PoseTarget, axis_turn
from .settings import ROLL_GRID, ROTATION_WEIGHT

__all__ = ["PartialTask", "free_rotation", "sweep", "sweeps"]

#: The components of a pose error a mask names (the Robotics Toolbox's order).
_POSITION_ROWS = (0, 1, 2)


class PartialTask:
    """The errors and least-squares rows of one partial target (:mod:`kin.ik.partial_pose`).

    Args:
        target: A :class:`~kin.ik.PoseTarget` (with or without a mask) or an
            :class:`~kin.ik.AxisTarget`, in the world frame.
    """

    def __init__(self, target: PoseTarget | AxisTarget):
        self.target = target
        self.position = target.position
        self.axis_column: int | None = None
        if isinstance(target, AxisTarget):
            self.axis_column = TOOL_AXES[target.tool_axis]
            self.rows = np.arange(6)
            self.position_rows = [0, 1, 2]
            self.rotation_rows = [3, 4, 5]
        else:
            mask = target.mask or (True,) * 6
            self.rows = np.flatnonzero(mask)
            self.position_rows = [i for i in _POSITION_ROWS if mask[i]]
            self.rotation_rows = [i for i in range(3, 6) if mask[i]]
        self.weights = np.where(self.rows >= 3, ROTATION_WEIGHT, 1.0)
        self.free = target.free

    def error(self, p: np.ndarray, rotation: np.ndarray) -> np.ndarray:
        """The unweighted error (6,): position [m] and rotation vector [rad], world axes."""
        e = np.empty(6)
        e[:3] = self.position - p
        if self.axis_column is None:
            e[3:] = pin.log3(self.target.rotation @ rotation.T)  # type: ignore[union-attr]
        else:
            e[3:] = axis_turn(rotation[:, self.axis_column], self.target.axis)  # type: ignore[union-attr]
        return e

    def near(self, p: np.ndarray) -> np.ndarray:
        """The target's constrained position components [m], the others taken from ``p`` [m].

        A masked target's free components are any values (``1e308`` included): a lookup of the
        poses near the target (the seed table's) measures from this point instead.
        """
        point = np.array(p, dtype=float)
        point[self.position_rows] = self.position[self.position_rows]
        return point

    def errors(self, e: np.ndarray) -> tuple[float, float]:
        """Position and rotation errors [m], [rad] of the constrained components of ``e``."""
        values = e.tolist()
        position = math.hypot(*[values[i] for i in self.position_rows])  # no overflow
        rotation = math.hypot(*[values[i] for i in self.rotation_rows])
        return position, rotation

    def jacobian(
        self, e: np.ndarray, rotation: np.ndarray, frame_jacobian: np.ndarray
    ) -> np.ndarray:
        """Rows (6, nq) of ``-d e / d q`` from the tool's ``LOCAL_WORLD_ALIGNED`` Jacobian."""
        rows = frame_jacobian.copy()
        if self.axis_column is None:
            rows[3:] = pin.Jlog3(self.target.rotation @ rotation.T) @ frame_jacobian[3:]  # type: ignore[union-attr]
        else:  # the roll about the current tool axis changes nothing
            a = rotation[:, self.axis_column]
            rows[3:] = frame_jacobian[3:] - np.outer(a, a @ frame_jacobian[3:])
        return rows


def free_rotation(task: PartialTask) -> np.ndarray | None:
    """The world axis of the one free rotation of a masked pose (unit (3,)), else None."""
    target = task.target
    if not isinstance(target, PoseTarget) or target.mask is None:
        return None
    free = [i for i in range(3) if not target.mask[3 + i]]
    if len(free) != 1:
        return None
    return np.eye(3)[free[0]]


def sweeps(task: PartialTask) -> bool:
    """Whether the target leaves one rotation free: a tool axis's roll, or one masked rotation."""
    return task.axis_column is not None or free_rotation(task) is not None


def sweep(task: PartialTask, seed_rotation: np.ndarray, grid: bool) -> tuple[np.ndarray, list[str]]:
    """Tool rotations (K, 3, 3) that meet the target's constrained rotation, and their names.

    An axis target: the seed's tool turned onto the axis by the smallest rotation (``grid``
    False), or :data:`~.settings.ROLL_GRID` rolls over a turn about the axis from there (True). A
    mask that frees one rotation component: the given rotation (False), or
    :data:`~.settings.ROLL_GRID` turns of it over a turn about that world axis (True). Any other
    mask: the given rotation.
    """
    target = task.target
    # the grid's other turns, nearest the first rotation first: 1, -1, 2, -2, ... steps
    steps = sorted(range(1, ROLL_GRID), key=lambda k: (min(k, ROLL_GRID - k), k > ROLL_GRID // 2))
    turns = [2.0 * math.pi * k / ROLL_GRID for k in steps]
    degrees = [360.0 * (k if k <= ROLL_GRID // 2 else k - ROLL_GRID) / ROLL_GRID for k in steps]
    names = [f"roll {value:+g} deg" for value in degrees]
    if isinstance(target, AxisTarget):
        column = TOOL_AXES[target.tool_axis]
        axis = target.axis
        turned = pin.exp3(axis_turn(seed_rotation[:, column], axis)) @ seed_rotation
        if not grid:
            return turned[None], ["seed's roll"]
        return np.array([pin.exp3(axis * turn) @ turned for turn in turns]), names
    free = free_rotation(task)
    if free is None or not grid:
        return target.rotation[None], ["given rotation"]
    turned_rotations = [pin.exp3(free * turn) @ target.rotation for turn in turns]
    return np.array(turned_rotations), [
        f"turn {value:+g} deg about world {'xyz'[int(np.argmax(free))]}" for value in degrees
    ]
