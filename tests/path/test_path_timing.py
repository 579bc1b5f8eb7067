"""Time-optimal timing of joint paths (toppra): limits respected, geometric path kept."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from dh2urdf import TableError
from dh2urdf.table_file import parse_table
from kin import load_robot
from kin.batch_fk import batch_tool_positions
from kin.ik import PitchTarget, PoseTarget
from kin.path import (
    DEFAULT_ACCELERATION,
    PathError,
    follow_path,
    line,
    polyline,
    table_limits,
    time_optimal,
)
from kin.path.cartesian import segment_distance

#: toppra enforces the limits at its grid points; between them they hold to this fraction.
TOLERANCE = 0.01
DT = 1e-3  # [s]


@functools.cache
def scorbot_path():
    """A scorbot polyline (pitch 0.3 rad) followed in closed form."""
    robot = load_robot("scorbot")
    points = [[0.45, 0.1, 0.30], [0.40, -0.05, 0.35], [0.50, -0.1, 0.25]]
    path = polyline([PitchTarget(p, 0.3) for p in points], 40)
    result = follow_path(robot, path)
    assert result.success, result.message
    return robot, path, result


def test_sampled_velocity_and_acceleration_respect_the_limits():
    """|qd| <= vmax and finite-difference |qdd| <= amax (1 %), at rest at the corners."""
    robot, path, result = scorbot_path()
    vmax = np.array([1.0, 0.8, 0.8, 1.5, 2.0])
    amax = np.array([2.0, 1.5, 1.5, 3.0, 4.0])
    timed = time_optimal(result.q, vmax, amax, dt=DT, stops=path.waypoint_indices)
    assert (np.abs(timed.qd) <= vmax * (1 + TOLERANCE)).all()
    accelerations = np.diff(timed.qd, axis=0) / np.diff(timed.t)[:, None]
    assert (np.abs(accelerations) <= amax * (1 + TOLERANCE)).all()
    corner_times = timed.waypoint_times[list(path.waypoint_indices)]
    np.testing.assert_allclose(
        [timed.qd[np.argmin(np.abs(timed.t - t))] for t in corner_times], 0.0, atol=0.02
    )
    # Time optimal: some joint reaches its velocity or acceleration limit.
    ratio = max((np.abs(timed.qd) / vmax).max(), (np.abs(accelerations) / amax).max())
    assert ratio > 0.98
    # And no faster than the bang-bang time of the joint that moves farthest.
    travel = np.abs(result.q[-1] - result.q[0])
    assert timed.duration >= (2 * np.sqrt(travel / amax)).max() * 0.99


def test_timed_path_passes_through_the_geometric_path():
    """The timed motion is at each sample at its waypoint time, and stays on the Cartesian path."""
    robot, path, result = scorbot_path()
    timed = time_optimal(result.q, *table_limits(robot.table), dt=DT, stops=path.waypoint_indices)
    np.testing.assert_allclose(timed.waypoint_q, result.q, atol=1e-6)
    assert timed.waypoint_times[0] == 0.0
    assert timed.waypoint_times[-1] == pytest.approx(timed.duration, abs=1e-9)
    assert (np.diff(timed.waypoint_times) > 0).all()
    # Every timed sample's tool point is within 0.5 mm of the Cartesian polyline.
    points = batch_tool_positions(robot.table, timed.q)
    corners = path.positions[list(path.waypoint_indices)]
    distance = np.min(
        [
            segment_distance(points, np.tile(a, (len(points), 1)), np.tile(b, (len(points), 1)))
            for a, b in zip(corners, corners[1:])
        ],
        axis=0,
    )
    assert distance.max() < 5e-4, distance.max()


def test_humanoid7_pose_line_timed_with_table_limits():
    """humanoid7: a pose line timed under its table limits (pi rad/s, default 2 pi rad/s^2)."""
    robot = load_robot("humanoid7")
    q0 = np.array([0.2, 0.3, 0.1, 1.0, 0.1, 0.4, 0.1])
    from kin import Configuration

    T = Configuration(robot, q0).transform_frame_to_world("tool")
    a = PoseTarget(T.translation, T.rotation)
    b = PoseTarget(T.translation + [-0.04, 0.02, 0.03], T.rotation)
    result = follow_path(robot, line(a, b, 20), q0)
    vmax, amax = table_limits(robot.table)
    np.testing.assert_allclose(vmax, math.pi)
    np.testing.assert_allclose(amax, DEFAULT_ACCELERATION["revolute"])
    timed = time_optimal(result.q, vmax, amax, samples=500)
    assert timed.t.shape == (500,) and timed.q.shape == (500, 7)
    assert (np.abs(timed.qd) <= vmax * (1 + TOLERANCE)).all()
    accelerations = np.diff(timed.qd, axis=0) / np.diff(timed.t)[:, None]
    assert (np.abs(accelerations) <= amax * (1 + TOLERANCE)).all()


def test_bad_limits_and_paths_raise_path_error():
    """Non-positive limits and one-sample paths are refused."""
    q = np.zeros((3, 2)) + np.arange(3)[:, None] * 0.1
    with pytest.raises(PathError, match="vmax"):
        time_optimal(q, [1.0, 0.0], 1.0)
    with pytest.raises(PathError, match="at least 2 samples"):
        time_optimal(q[:1], 1.0, 1.0)


def test_path_without_motion_is_at_rest():
    """Repeated samples: duration 0, one sample at rest."""
    timed = time_optimal(np.ones((4, 3)), 1.0, 1.0)
    assert timed.duration == 0.0 and timed.q.shape == (1, 3)


TABLE = {
    "convention": "standard",
    "length_unit": "mm",
    "angle_unit": "deg",
    "joints": [
        {"type": "revolute", "a": 100.0, "alpha": 0.0, "d": 0.0, "theta": 0.0,
         "limits": [-90.0, 90.0], "velocity": 90.0, "acceleration": 180.0},
        {"type": "prismatic", "a": 0.0, "alpha": 0.0, "d": 0.0, "theta": 0.0,
         "limits": [0.0, 100.0]},
    ],
}  # fmt: skip


def test_table_acceleration_is_read_in_table_units():
    """acceleration = 180 deg/s^2 is pi rad/s^2; a row without one gets the default."""
    table = parse_table(TABLE)
    assert table.rows[0].acceleration == pytest.approx(math.pi)
    assert table.rows[1].acceleration is None
    vmax, amax = table_limits(table)
    np.testing.assert_allclose(vmax, [math.pi / 2, 0.5])
    np.testing.assert_allclose(amax, [math.pi, DEFAULT_ACCELERATION["prismatic"]])


def test_table_acceleration_must_be_positive():
    """A zero acceleration names the row and the field."""
    bad = {**TABLE, "joints": [{**TABLE["joints"][0], "acceleration": 0.0}]}
    with pytest.raises(TableError, match="acceleration"):
        parse_table(bad)
