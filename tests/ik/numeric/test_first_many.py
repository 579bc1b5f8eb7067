"""The compiled twins' batched ``first_many`` gives, target by target, the Python ``first``'s answer.

``first_many`` (``kin/_native/ik/analytic/seven_r/_closed7.c``, ``_shoulder7.c``) is what
:func:`kin.ik.solve_batch` calls for the free-joint closed form of humanoid7, Panda and xArm7:
N targets, each from its own start, the scan steps in turn. The reference is the pure-Python
``first`` (``compiled=False``) of each target alone, step after step, as the per-call solver asks
it. The batched frame change (NumPy on N poses) rounds differently from the scalar one: joint
vectors agree to 1e-9 rad, found and not found exactly.
"""

from __future__ import annotations

import functools

import numpy as np
import pinocchio as pin
import pytest

from kin import load_robot
from kin.ik import get_solver
from kin.ik.analytic.seven_r.seven_dof import COMPILED as CLOSED7
from kin.ik.analytic.seven_r.spherical_shoulder7 import COMPILED as SHOULDER7
from kin.ik.numeric.solver import DEFAULT_CLOSED_FORM_STEPS

ROBOTS = {"humanoid7": CLOSED7, "panda": SHOULDER7, "xarm7": SHOULDER7}
TARGETS = 400
TOL = 1e-9


@functools.cache
def closed_form(name: str):  # noqa: ANN201
    return get_solver(load_robot(name)).closed_form  # type: ignore[attr-defined]


def poses(name: str, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Tool positions (n, 3) [m] and rotations (n, 3, 3) of random joint vectors inside the limits."""
    robot = load_robot(name)
    rng = np.random.default_rng(seed)
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.tool_frame)
    positions, rotations = np.empty((n, 3)), np.empty((n, 3, 3))
    for i, q in enumerate(rng.uniform(robot.lower, robot.upper, size=(n, robot.nq))):
        pin.forwardKinematics(model, data, q)
        pose = pin.updateFramePlacement(model, data, frame)
        positions[i], rotations[i] = pose.translation, pose.rotation
    return positions, rotations


def starts(name: str, n: int, seed: int) -> np.ndarray:
    """Random starts, some outside the limits, one not finite."""
    robot = load_robot(name)
    rng = np.random.default_rng(seed)
    out = rng.uniform(robot.lower - 0.3, robot.upper + 0.3, size=(n, robot.nq))
    out[3, 2] = np.nan
    return out


def one_by_one(ik, positions, rotations, seeds, steps) -> np.ndarray:  # noqa: ANN001
    """The Python ``first`` per target, the steps in turn (NaN rows where none)."""
    out = np.full((len(positions), 7), np.nan)
    row = np.empty(7)
    for i in range(len(positions)):
        prepared = ik.prepare(positions[i], None if rotations is None else rotations[i])
        for step in steps:
            if prepared is not None and ik.first(prepared, seeds[i : i + 1], row, step, False) == 0:
                out[i] = row
                break
    return out


@pytest.mark.parametrize("kind", ["pose", "position"])
@pytest.mark.parametrize("steps", [DEFAULT_CLOSED_FORM_STEPS, (0.0,)])
@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_first_many_equals_first_target_by_target(name, steps, kind):
    if not ROBOTS[name]:
        pytest.skip(f"the compiled twin of {name}'s closed form is not built")
    ik = closed_form(name)
    positions, rotations = poses(name, TARGETS, seed=7)
    if kind == "position":
        rotations = None
    seeds = starts(name, TARGETS, seed=8)
    batched = ik.first_many(positions, rotations, seeds, steps)
    single = one_by_one(ik, positions, rotations, seeds, steps)
    found = ~np.isnan(single).any(axis=1)
    np.testing.assert_array_equal(~np.isnan(batched).any(axis=1), found)
    np.testing.assert_array_equal(np.isnan(batched).all(axis=1), ~found)  # whole rows
    if found.any():
        assert np.abs(batched[found] - single[found]).max() <= TOL
    if kind == "pose" and steps != (0.0,):  # the scan finds nearly all: answers were compared
        assert found.mean() >= 0.95, f"{found.mean()=}"
    if kind == "position" and name != "humanoid7":  # the spherical-shoulder form takes poses only
        assert not found.any()


@pytest.mark.skipif(not (CLOSED7 and SHOULDER7), reason="compiled twins not built")
@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_first_many_of_no_target_and_bad_arrays(name):
    ik = closed_form(name)
    none = ik.first_many(np.empty((0, 3)), np.empty((0, 3, 3)), np.empty((0, 7)), (0.05,))
    assert none.shape == (0, 7)
    twin = (
        __import__("kin.ik.analytic.seven_r._closed7", fromlist=["x"])
        if name == "humanoid7"
        else __import__("kin.ik.analytic.seven_r._shoulder7", fromlist=["x"])
    )
    head = (ik.c_params, 0) if name == "humanoid7" else (ik.c_params,)
    steps = np.array([0.05])
    good = (np.zeros((2, 12)), np.zeros((2, 7)), np.full((2, 7), np.nan), steps)
    assert twin.first_many(*head, *good) >= 0
    bad = [
        ((np.zeros((2, 11)), *good[1:]), "targets"),
        ((good[0], np.zeros((3, 7)), *good[2:]), "starts"),
        ((*good[:2], np.zeros((2, 6)), steps), "out"),
        ((*good[:3], np.zeros((1, 1))), "steps"),
        ((good[0].astype(np.float32), *good[1:]), "float64"),
    ]
    for args, word in bad:
        with pytest.raises((ValueError, TypeError), match=word):
            twin.first_many(*head, *args)
    with pytest.raises(ValueError, match="params"):
        twin.first_many(np.zeros(3), *head[1:], *good)
    if name == "humanoid7":
        with pytest.raises(ValueError, match="mode"):
            twin.first_many(ik.c_params, 2, *good)


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_narrow_limits_keep_every_branch_the_python_first_keeps(name):
    """Limits narrowed around the targets' own joint values (many branches at a limit's edge):
    the twins drop an angle pair before its second angle when no joint value in the limits fits
    it (``rotation_pair_fit`` in ``_twin.h``); they still find what the Python ``first`` finds."""
    if not ROBOTS[name]:
        pytest.skip(f"the compiled twin of {name}'s closed form is not built")
    import dataclasses

    from kin import robot_from_table

    robot = load_robot(name)
    rng = np.random.default_rng(21)
    middle = rng.uniform(robot.lower * 0.5, robot.upper * 0.5)
    half = rng.uniform(0.2, 0.9, robot.nq)
    rows = tuple(
        dataclasses.replace(row, lower=float(m - h), upper=float(m + h))
        for row, m, h in zip(robot.table.rows, middle, half)
    )
    narrow = robot_from_table(dataclasses.replace(robot.table, rows=rows))
    ik = get_solver(narrow).closed_form
    assert ik is not None
    model, data = narrow.model, narrow.model.createData()
    frame = model.getFrameId(narrow.tool_frame)
    n = 300
    positions, rotations = np.empty((n, 3)), np.empty((n, 3, 3))
    for i, q in enumerate(rng.uniform(narrow.lower, narrow.upper, size=(n, narrow.nq))):
        pin.forwardKinematics(model, data, q)
        pose = pin.updateFramePlacement(model, data, frame)
        positions[i], rotations[i] = pose.translation, pose.rotation
    seeds = rng.uniform(narrow.lower, narrow.upper, size=(n, narrow.nq))
    rates = []
    for steps in (DEFAULT_CLOSED_FORM_STEPS, (0.0,)):
        batched = ik.first_many(positions, rotations, seeds, steps)
        single = one_by_one(ik, positions, rotations, seeds, steps)
        found = ~np.isnan(single).any(axis=1)
        np.testing.assert_array_equal(~np.isnan(batched).any(axis=1), found)
        if found.any():
            assert np.abs(batched[found] - single[found]).max() <= TOL
        rates.append(found.mean())
    assert rates[0] > 0.5  # the scan found answers: there was something to compare
