"""``seed_inside``'s short way (a float64 vector compared as floats) gives the NumPy way's answer.

The reference is a plain clip written here: each joint clipped to its range, continuous joints
kept, a seed that is not finite joint vectors returned as given; a seed already inside is
returned as the same object (no copy).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from dh2urdf import get_robot, load_table
from kin import load_robot, robot_from_table
from kin.configuration import seed_inside


def _puma_continuous_first():
    """PUMA 560 with joint 1 continuous (limits [-pi, pi], kept as given by the clip)."""
    table = load_table(get_robot("puma560").table_path)
    first = dataclasses.replace(table.rows[0], lower=-math.pi, upper=math.pi, continuous=True)
    return robot_from_table(dataclasses.replace(table, rows=(first, *table.rows[1:])))


def _reference(robot, q):
    try:
        values = np.asarray(q, dtype=float)
    except ValueError:
        return q
    if values.ndim not in (1, 2) or values.shape[-1] != robot.nq:
        return q
    if not np.isfinite(values).all():
        return q
    lower, upper = robot.lower, robot.upper
    if ((values >= lower) & (values <= upper)).all():
        return q
    continuous = [row.continuous for row in robot.table.rows]
    return np.array(
        [
            [v if c else min(max(v, lo), hi) for v, c, lo, hi in zip(row, continuous, lower, upper)]
            for row in np.atleast_2d(values)
        ]
    ).reshape(values.shape)


def _seeds(robot, rng):
    nq = robot.nq
    lower, upper = robot.lower, robot.upper
    inside = rng.uniform(lower, upper)
    yield inside
    yield lower.copy()  # on the bounds: inside
    yield upper.copy()
    yield inside + 10.0  # every joint outside
    one = inside.copy()
    one[nq - 1] = upper[nq - 1] + 1e-12  # one joint just outside
    yield one
    for bad in (np.nan, np.inf, -np.inf):
        odd = inside.copy()
        odd[1] = bad
        yield odd
    yield inside.tolist()  # a list
    yield inside.astype(np.float32)  # another dtype
    yield np.zeros(nq, dtype=int)
    yield rng.uniform(lower - 1.0, upper + 1.0, size=(4, nq))  # a batch
    yield np.zeros(nq + 1)  # the wrong size: as given
    yield np.zeros((nq, 1))
    yield inside[::-1][::-1]  # a view
    yield "not numbers"


@pytest.mark.parametrize("arm", ["ur5", "panda", "humanoid7", "puma560 continuous"])
def test_seed_inside_equals_a_plain_clip(arm):
    robot = _puma_continuous_first() if arm == "puma560 continuous" else load_robot(arm)
    rng = np.random.default_rng(3)
    for _ in range(20):
        for seed in _seeds(robot, rng):
            got, expected = seed_inside(robot, seed), _reference(robot, seed)
            if expected is seed:
                assert got is seed, f"{arm}: {seed!r} must be returned as given"
            else:
                assert isinstance(got, np.ndarray) and got.shape == expected.shape, f"{seed!r}"
                assert np.array_equal(got, expected), f"{arm}: {seed!r} -> {got!r}"


def test_limits_narrowed_after_loading_are_read_on_every_call():
    """A user may narrow a model's limits: the short way reads them each call, as the long one."""
    robot = robot_from_table(load_table(get_robot("ur5").table_path))
    q = np.full(robot.nq, 0.5)
    assert seed_inside(robot, q) is q
    robot.model.upperPositionLimit = np.full(robot.nq, 0.25)
    assert seed_inside(robot, q).tolist() == [0.25] * robot.nq
