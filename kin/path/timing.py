"""Time-optimal timing of a joint path under joint velocity and acceleration limits (toppra).

The geometric path is the cubic spline through the joint samples (``toppra.SplineInterpolator``,
parametrized by the joint-space chord length, so it passes through every sample); TOPP-RA
(``toppra.algorithm.TOPPRA``) finds the fastest timing with ``|qd_j| <= vmax_j`` and
``|qdd_j| <= amax_j`` (``JointVelocityConstraint``, ``JointAccelerationConstraint``), at rest at
both ends, and at rest at the ``stops`` (the corners of a polyline: a tool that turns a corner
without stopping leaves the path), each stretch between stops timed on its own. The limits hold at toppra's grid points; between them the constant-acceleration
parametrization keeps them within toppra's discretization tolerance (about 1 %).

Limits come from the DH table (``velocity`` and ``acceleration`` per joint, SI), or are given.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from .exceptions import PathError

#: Acceleration limit of a joint whose table row gives none [rad/s^2] / [m/s^2].
DEFAULT_ACCELERATION = {"revolute": 2.0 * math.pi, "prismatic": 1.0}


def table_limits(table: DHTable) -> tuple[np.ndarray, np.ndarray]:
    """Joint velocity [rad/s] / [m/s] and acceleration [rad/s^2] / [m/s^2] limits of ``table``.

    A row without ``acceleration`` gets :data:`DEFAULT_ACCELERATION` of its joint type.
    """
    vmax = np.array([row.velocity for row in table.rows], dtype=float)
    amax = np.array(
        [
            DEFAULT_ACCELERATION[row.joint_type] if row.acceleration is None else row.acceleration
            for row in table.rows
        ],
        dtype=float,
    )
    return vmax, amax


@dataclass(frozen=True, eq=False)
class TimedPath:
    """A timed joint path, sampled.

    Attributes:
        t: Sample times [s], shape (K,), from 0 to ``duration``.
        q: Joint values at ``t`` [rad] / [m], shape (K, nq).
        qd: Joint velocities at ``t`` [rad/s] / [m/s], shape (K, nq).
        qdd: Joint accelerations at ``t`` [rad/s^2] / [m/s^2], shape (K, nq).
        duration: Time of the whole motion [s].
        waypoint_times: Time at which each geometric sample is passed [s], shape (M,).
        waypoint_q: Joint values of the timed path at ``waypoint_times`` (the geometric samples,
            up to toppra's interpolation) [rad] / [m], shape (M, nq).
        waypoint_qd: Joint velocities there [rad/s] / [m/s], shape (M, nq).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    duration: float
    waypoint_times: np.ndarray
    waypoint_q: np.ndarray
    waypoint_qd: np.ndarray


def _limits(values: npt.ArrayLike, nq: int, what: str) -> np.ndarray:
    array = np.broadcast_to(np.asarray(values, dtype=float).reshape(-1), (nq,)).copy()
    if not (np.isfinite(array).all() and (array > 0).all()):
        raise PathError(f"{what} must be positive and finite, got {array.tolist()}", what)
    return array


def time_optimal(
    q: npt.ArrayLike,
    vmax: npt.ArrayLike,
    amax: npt.ArrayLike,
    dt: float | None = None,
    samples: int = 200,
    stops: Sequence[int] = (),
    grid_per_sample: int = 20,
) -> TimedPath:
    """The time-optimal timing of the joint path ``q`` under the limits.

    Args:
        q: Joint path, shape (M, nq) [rad] / [m], M >= 2.
        vmax: Velocity limit per joint (or one for all) [rad/s] / [m/s].
        amax: Acceleration limit per joint (or one for all) [rad/s^2] / [m/s^2].
        dt: Sample period of the output [s]; None: ``samples`` samples evenly in time.
        samples: Number of output samples when ``dt`` is None.
        stops: Sample indices where the motion comes to rest (the corners of a polyline: a tool
            that turns a corner without stopping leaves the path); the first and last always.
        grid_per_sample: toppra grid points per sample interval (the limits hold at the grid
            points; a finer grid keeps them closer in between).

    Raises:
        PathError: Fewer than 2 samples, or limits not positive and finite, or toppra fails.
    """
    way = np.asarray(q, dtype=float)
    if way.ndim != 2 or way.shape[0] < 2:
        raise PathError(f"timing needs a joint path of at least 2 samples, got {way.shape}", "q")
    nq = way.shape[1]
    v, a = _limits(vmax, nq, "vmax"), _limits(amax, nq, "amax")
    bounds = sorted({0, len(way) - 1, *(int(i) for i in stops if 0 < int(i) < len(way) - 1)})
    pieces, offsets, waypoint_times = [], [0.0], [np.zeros(1)]
    for first, last in zip(bounds, bounds[1:]):
        piece = _Piece(way[first : last + 1], v, a, grid_per_sample)
        pieces.append(piece)
        waypoint_times.append(offsets[-1] + piece.waypoint_times[1:])
        offsets.append(offsets[-1] + piece.duration)
    duration = offsets[-1]
    times = np.concatenate(waypoint_times)
    if duration <= 0.0:  # no motion: at rest
        zeros = np.zeros_like(way)
        return TimedPath(np.zeros(1), way[:1], zeros[:1], zeros[:1], 0.0, times, way, zeros)
    t = np.linspace(0.0, duration, samples) if dt is None else _times(duration, dt)

    def evaluate(t: np.ndarray, order: int) -> np.ndarray:
        which = np.clip(np.searchsorted(offsets, t, side="right") - 1, 0, len(pieces) - 1)
        out = np.empty((len(t), nq))
        for k, piece in enumerate(pieces):
            mask = which == k
            if mask.any():
                out[mask] = piece(t[mask] - offsets[k], order)
        return out

    return TimedPath(
        t=t,
        q=evaluate(t, 0),
        qd=evaluate(t, 1),
        qdd=evaluate(t, 2),
        duration=duration,
        waypoint_times=times,
        waypoint_q=evaluate(times, 0),
        waypoint_qd=evaluate(times, 1),
    )


class _Piece:
    """The time-optimal rest-to-rest timing of one stretch of samples (toppra)."""

    def __init__(self, way: np.ndarray, v: np.ndarray, a: np.ndarray, grid_per_sample: int):
        import toppra
        import toppra.algorithm
        import toppra.constraint

        self.way = way
        chord = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(way, axis=0), axis=1))])
        keep = np.concatenate([[True], np.diff(chord) > 1e-12])
        self.trajectory = None
        self.duration = 0.0
        self.waypoint_times = np.zeros(len(way))
        if keep.sum() < 2:  # no motion
            return
        ss = chord[keep] / chord[-1]
        spline = toppra.SplineInterpolator(ss, way[keep])
        constraints = [
            toppra.constraint.JointVelocityConstraint(np.column_stack([-v, v])),
            toppra.constraint.JointAccelerationConstraint(np.column_stack([-a, a])),
        ]
        fine = np.linspace(0.0, 1.0, grid_per_sample * (len(ss) - 1) + 1)
        gridpoints = np.unique(np.concatenate([ss, fine]))
        instance = toppra.algorithm.TOPPRA(
            constraints, spline, gridpoints=gridpoints, parametrizer="ParametrizeConstAccel"
        )
        trajectory = instance.compute_trajectory(0.0, 0.0)
        if trajectory is None:
            raise PathError("toppra found no timing of this path under the limits", "timing")
        self.trajectory = trajectory
        self.duration = float(trajectory.duration)
        # Time at each grid point of the constant-acceleration parametrization: ds / mean(sd).
        grid = np.asarray(instance.problem_data.gridpoints, dtype=float)
        sd = np.maximum(np.asarray(instance.problem_data.sd_vec, dtype=float), 0.0)
        t_grid = np.concatenate([[0.0], np.cumsum(2.0 * np.diff(grid) / (sd[:-1] + sd[1:]))])
        self.waypoint_times = np.interp(chord / chord[-1], grid, t_grid)

    def __call__(self, t: np.ndarray, order: int) -> np.ndarray:
        """Joint values (order 0), velocities (1) or accelerations (2) at ``t`` [s]."""
        if self.trajectory is None:
            value = self.way[0] if order == 0 else np.zeros_like(self.way[0])
            return np.tile(value, (len(t), 1))
        return np.asarray(self.trajectory(np.clip(t, 0.0, self.duration), order), dtype=float)


def _times(duration: float, dt: float) -> np.ndarray:
    """``0, dt, 2 dt, ...`` and ``duration`` itself [s]."""
    if not (math.isfinite(dt) and dt > 0):
        raise PathError(f"dt must be positive and finite, got {dt}", "dt")
    t = np.arange(0.0, duration, dt)
    return np.append(t, duration) if duration - t[-1] > 1e-12 else t
