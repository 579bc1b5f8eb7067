"""The batch's compiled closed-form stage (``seeded_many``) answers what the Python pieces answer.

``seeded_many`` (``kin/_native/ik/analytic/seven_r/_seeded7.h``) does in one call per block of rows what
:func:`kin.ik.solve_batch` did in NumPy around the twin's ``first_many``: the world targets
brought to the structure's frames, the scan, then the judge (the table's DH product, 1e-9 m and
rad, the limits). The reference here is that older path: ``first_many`` on the same targets and
seeds, judged by :func:`kin.batch_forward_kinematics` and :func:`kin.ik.judge.batch_pose_errors`
in NumPy. The frame change rounds differently in C and NumPy: joint vectors agree to 1e-9 rad,
errors to 1e-12, found and not found exactly.

The twins also skip, without their angles, the free-joint values where no branch followed as
directions fits every joint's limits (``q1_may_fit`` in ``_closed7.c``, ``branches_may_fit`` in
``_shoulder7.c``): targets whose own joints sit on their limits check that no answer the Python
module finds is skipped.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest

from kin import batch_forward_kinematics, load_robot, robot_from_table
from kin.ik import solve_batch
from kin.ik.analytic.seven_r.seven_dof import COMPILED as CLOSED7
from kin.ik.analytic.seven_r.spherical_shoulder7 import COMPILED as SHOULDER7
from kin.ik.judge import batch_pose_errors
from kin.ik.numeric.free_joint import SeededMany, compiled_seeded_many
from kin.ik.numeric.solver import DEFAULT_CLOSED_FORM_STEPS, NumericIK

ROBOTS = {"humanoid7": CLOSED7, "panda": SHOULDER7, "xarm7": SHOULDER7}
TOL = 1e-9


@functools.cache
def solver(name: str) -> NumericIK:
    return NumericIK(load_robot(name), prepare=False)


def targets(robot, n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # noqa: ANN001
    """Tool positions (n, 3) [m], rotations (n, 3, 3) of random joint vectors in the limits, and
    seeds: random, some outside the limits, one not finite, some zero."""
    rng = np.random.default_rng(seed)
    poses = batch_forward_kinematics(robot.table, rng.uniform(robot.lower, robot.upper, (n, 7)))
    seeds = rng.uniform(robot.lower - 0.3, robot.upper + 0.3, (n, 7))
    seeds[3, 2] = np.nan
    seeds[::7] = 0.0
    return poses[:, :3, 3].copy(), poses[:, :3, :3].copy(), seeds


def reference(solver: NumericIK, robot, points, frames, seeds, steps) -> np.ndarray:  # noqa: ANN001
    """(N, 9): ``first_many`` judged in NumPy (q, position and rotation errors), NaN rows."""
    q = solver.closed_form.first_many(points, frames, seeds, steps)
    out = np.full((len(points), 9), np.nan)
    found = np.flatnonzero(~np.isnan(q).any(axis=1))
    poses = batch_forward_kinematics(robot.table, q[found])
    p_err, r_err = batch_pose_errors(
        poses, points[found], None if frames is None else frames[found]
    )
    ok = p_err < TOL
    if r_err is not None:
        ok &= r_err < TOL
    ok &= np.all((q[found] >= robot.lower) & (q[found] <= robot.upper), axis=1)
    rows = found[ok]
    out[rows, :7] = q[rows]
    out[rows, 7] = p_err[ok]
    if r_err is not None:
        out[rows, 8] = r_err[ok]
    return out


def assert_same_rows(got: np.ndarray, want: np.ndarray) -> None:
    found = ~np.isnan(want[:, :7]).any(axis=1)
    np.testing.assert_array_equal(~np.isnan(got[:, :7]).any(axis=1), found)
    np.testing.assert_array_equal(np.isnan(got[:, :8]).all(axis=1), ~found)  # whole rows
    np.testing.assert_array_equal(np.isnan(got[:, 8]), np.isnan(want[:, 8]))
    if found.any():
        assert np.abs(got[found, :7] - want[found, :7]).max() <= TOL
        assert (
            np.abs(
                got[found, 7:][~np.isnan(want[found, 7:])]
                - want[found, 7:][~np.isnan(want[found, 7:])]
            ).max()
            <= 1e-12
        )


@pytest.mark.parametrize("kind", ["pose", "position"])
@pytest.mark.parametrize("steps", [DEFAULT_CLOSED_FORM_STEPS, (0.0,)])
@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_seeded_many_equals_the_scan_judged_in_numpy(name, steps, kind):
    if not ROBOTS[name]:
        pytest.skip(f"the compiled twin of {name}'s closed form is not built")
    ik = solver(name)
    assert isinstance(ik.seeded_many, SeededMany)
    robot = ik.robot
    points, frames, seeds = targets(robot, 500, seed=31)
    if kind == "position":
        frames = None
    got = ik.seeded_many.start(points, frames, seeds, steps, TOL).result()
    want = reference(ik, robot, points, frames, seeds, steps)
    assert_same_rows(got, want)
    found = ~np.isnan(want[:, 0])
    if kind == "pose" and steps != (0.0,):  # there were answers to compare
        assert found.mean() >= 0.95
    if kind == "position" and name != "humanoid7":  # the spherical-shoulder form takes poses only
        assert not found.any()


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_the_judge_drops_answers_off_target_or_outside_the_limits(name):
    """A tolerance of zero keeps nothing; limits narrower than the closed form's (the judge's
    own) drop exactly the answers outside them."""
    if not ROBOTS[name]:
        pytest.skip(f"the compiled twin of {name}'s closed form is not built")
    ik = solver(name)
    robot = ik.robot
    points, frames, seeds = targets(robot, 200, seed=32)
    steps = DEFAULT_CLOSED_FORM_STEPS
    assert np.isnan(ik.seeded_many.start(points, frames, seeds, steps, 0.0).result()).all()
    full = ik.seeded_many.start(points, frames, seeds, steps, TOL).result()
    lower, upper = robot.lower.copy(), robot.upper.copy()
    lower[2], upper[4] = 0.0, 0.0
    narrow = compiled_seeded_many(ik.closed_form, robot.table, lower, upper)
    assert narrow is not None
    got = narrow.start(points, frames, seeds, steps, TOL).result()
    q = full[:, :7]
    inside = np.all((q >= lower) & (q <= upper), axis=1)
    np.testing.assert_array_equal(got[inside], full[inside])
    assert np.isnan(got[~inside]).all()
    assert inside.sum() > 10 and (~inside & ~np.isnan(q).any(axis=1)).sum() > 10


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_seeded_many_refuses_bad_arguments(name):
    if not ROBOTS[name]:
        pytest.skip(f"the compiled twin of {name}'s closed form is not built")
    many = solver(name).seeded_many
    call = many._call
    params, block, limits = many._head
    tolerances = np.array([TOL, TOL])
    good = (np.zeros((2, 12)), np.zeros((2, 7)), np.full((2, 9), np.nan), np.array([0.05]))
    assert call(params, block, limits, 0, tolerances, *good) == 0  # all-zero rows: no rotation
    bad = [
        ((params[:-8], block, limits, 0, tolerances, *good), "params"),
        ((params, block + b"x", limits, 0, tolerances, *good), "seed_block"),
        ((params, block, limits[:13], 0, tolerances, *good), "limits"),
        ((params, block, limits, 2, tolerances, *good), "mode"),
        ((params, block, limits, 0, tolerances[:1], *good), "tolerances"),
        ((params, block, limits, 0, tolerances, np.zeros((2, 3)), *good[1:]), "targets"),
        ((params, block, limits, 0, tolerances, good[0], np.zeros((3, 7)), *good[2:]), "starts"),
        ((params, block, limits, 0, tolerances, *good[:2], np.zeros((2, 7)), good[3]), "out"),
        ((params, block, limits, 0, tolerances, *good[:3], np.zeros((1, 1))), "steps"),
        ((params, block, limits, 0, tolerances, good[0].astype(np.float32), *good[1:]), "float64"),
    ]
    for args, word in bad:
        with pytest.raises((ValueError, TypeError), match=word):
            call(*args)
    with pytest.raises(TypeError):
        call(params.decode("latin-1"), block, limits, 0, tolerances, *good)  # not bytes


def test_a_batch_answers_as_before_the_stage_was_compiled():
    """solve_batch with the compiled stage and without it (the scan judged in NumPy): the same
    answers, stages and errors."""
    if not CLOSED7:
        pytest.skip("the compiled twin of humanoid7's closed form is not built")
    robot = load_robot("humanoid7")
    points, frames, seeds = targets(robot, 400, seed=33)
    seeds[3] = 0.0
    compiled = solve_batch(robot, points, frames, seeds)
    from kin.ik import batch_solve

    kept = batch_solve._SOLVERS[robot][2]
    many, kept.seeded_many = kept.seeded_many, None
    try:
        numpy_judged = solve_batch(robot, points, frames, seeds)
    finally:
        kept.seeded_many = many
    assert compiled.stage == numpy_judged.stage
    np.testing.assert_array_equal(compiled.success, numpy_judged.success)
    np.testing.assert_allclose(compiled.q, numpy_judged.q, atol=TOL, equal_nan=True)
    np.testing.assert_allclose(compiled.position_error, numpy_judged.position_error, atol=1e-12)
    np.testing.assert_allclose(compiled.rotation_error, numpy_judged.rotation_error, atol=1e-12)


def _edge_robot(name: str, seed: int):  # noqa: ANN202
    """The robot with every joint limited to a random arc narrower than a half turn."""
    robot = load_robot(name)
    rng = np.random.default_rng(seed)
    middle = rng.uniform(robot.lower * 0.5, robot.upper * 0.5)
    half = rng.uniform(0.15, 0.8, robot.nq)
    rows = tuple(
        dataclasses.replace(row, lower=float(m - h), upper=float(m + h))
        for row, m, h in zip(robot.table.rows, middle, half)
    )
    return robot_from_table(dataclasses.replace(robot.table, rows=rows))


#: The free joint of each arm's closed form (humanoid7's joint 1; the spherical shoulder's 7).
FREE = {"humanoid7": 0, "panda": 6, "xarm7": 6}


@pytest.mark.parametrize("seed", [41, 42, 43])
@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_the_skips_change_no_answer_on_the_limits(name, seed):
    """Targets whose own joints sit on their limits (each but the free joint with probability one
    half, exactly or 1e-9 rad in or out), some with joint 4 at the elbow's stretch or joint 6 at
    the wrist's singularity (as near as the limits allow), seeds elsewhere or with the target's
    own free joint: the twin's scan with its skips (the free-joint values where no branch,
    followed as directions, fits the limits: ``q1_may_fit``, ``branches_may_fit``) gives, bit for
    bit, the answers of its scan without them."""
    if not ROBOTS[name]:
        pytest.skip(f"the compiled twin of {name}'s closed form is not built")
    robot = _edge_robot(name, seed)
    ik = NumericIK(robot, prepare=False).closed_form
    free = FREE[name]
    rng = np.random.default_rng(seed)
    n = 400
    q = rng.uniform(robot.lower, robot.upper, (n, 7))
    edge = np.where(rng.random((n, 7)) < 0.5, robot.lower, robot.upper)
    edge += rng.choice([-1e-9, 0.0, 1e-9], (n, 7))
    on_edge = rng.random((n, 7)) < 0.5
    on_edge[:, free] = False
    q = np.where(on_edge, edge, q)
    q[::5, 3] = 0.0  # the elbow stretched (where joint 4 allows it)
    q[1::5, 5] = 0.0  # the wrist singular (where joint 6 allows it)
    q = np.clip(q, robot.lower, robot.upper)
    poses = batch_forward_kinematics(robot.table, q)
    points, frames = poses[:, :3, 3].copy(), poses[:, :3, :3].copy()
    seeds = rng.uniform(robot.lower, robot.upper, (n, 7))
    seeds[::2, free] = q[::2, free]  # the target's own free joint: its branch, on the limits
    twin = ik.twin
    rates = []
    try:
        for steps in (DEFAULT_CLOSED_FORM_STEPS, (0.0,)):
            assert twin.skips(True)
            skipping = ik.first_many(points, frames, seeds, steps)
            twin.skips(False)
            solving = ik.first_many(points, frames, seeds, steps)
            twin.skips(True)
            np.testing.assert_array_equal(skipping, solving)
            rates.append(np.isfinite(solving).all(axis=1).mean())
    finally:
        twin.skips(True)
    # There were answers to compare. Many targets are not reached: a joint set exactly on its
    # limit comes back from the closed form an ulp outside it.
    assert rates[1] > 0.05 and rates[0] > 0.2


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_targets_beyond_reach_get_no_answer_and_no_scan(name):
    """Targets beyond the arm's reach bound (and one at 1e200 m): no row, and the batch says
    no success for them (the solver answers ``out_of_reach``), the others as before."""
    if not ROBOTS[name]:
        pytest.skip(f"the compiled twin of {name}'s closed form is not built")
    ik = solver(name)
    robot = ik.robot
    points, frames, seeds = targets(robot, 60, seed=34)
    far = np.arange(60) % 3 == 0
    points[far] *= 1.0 + (ik.reach + 1.0) / np.linalg.norm(points[far], axis=1)[:, None]
    points[0] = 1e200
    rows = ik.seeded_many.start(points, frames, seeds, DEFAULT_CLOSED_FORM_STEPS, TOL).result()
    assert np.isnan(rows[far]).all()
    assert np.isfinite(rows[~far]).all(axis=1).mean() > 0.8
    seeds[3] = 0.0  # solve_batch refuses a seed that is not finite
    result = solve_batch(robot, points, frames, seeds)
    assert not result.success[far].any()
    assert all(result.stage[i] == "" for i in np.flatnonzero(far))
