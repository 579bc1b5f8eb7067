"""A general 7R arm near a special one (kin/ik/analytic/seven_r/ideal_7r.py, General7RIK.ideal).

Kinova's Gen3 as its URDF has it: the user guide's DH table (humanoid7's structure) with the
twists rounded to 1.5708 and the wrist axes 0.35 mm apart (row 6 ``d``). No special form fits it;
the general form holds joint 1 and polishes the snapped arm's branches with joint 1 fixed.

- at every held value its branches are the general elimination's (an independent algorithm:
  Raghavan-Roth / Manocha-Canny on the same 6R), each on the pose by the plain NumPy DH product
  (``tests/support/dh_reference.py``), the q the pose came from among them;
- ``solve(..., all_branches=True)`` gives the same answer through the twin's ``held_rows`` and
  through the Python path, and so does a scan of one target over many held values;
- an arm far from every special one (random offsets) gets no snapped form.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from support.arm_tables import make_table, random_pose, wrapped_gap
from support.dh_reference import fk_frames, load_reference, rotation_angle

import kin
from kin.ik import PoseTarget, get_solver
from kin.ik.analytic.seven_r.general_7r import General7RIK
from kin.ik.analytic.seven_r.ideal_7r import held_branches, held_rows_at, held_twin, ideal_form
from kin.ik.analytic.seven_r.seven_dof import SevenDofIK
from kin.ik.numeric import branch_arm

GEN3 = Path(__file__).resolve().parents[3] / "data" / "seven_r" / "gen3.toml"
POSES = 12
VALUES = 8


def rounded_gen3():
    """The Gen3 table as its URDF rounds it, and its reference arrays (limits +-2 pi)."""
    ref = load_reference(GEN3)
    alpha = np.where(
        np.isclose(np.abs(ref.alpha), math.pi / 2), np.sign(ref.alpha) * 1.5708, ref.alpha
    )
    d = ref.d.copy()
    d[5] = -0.00035
    table = make_table(ref.a, alpha, d, ref.theta, ref.convention, ref.T_world_base, ref.T_last_tool,
                       name="gen3_rounded")  # fmt: skip
    turn = 2 * math.pi * np.ones(7)
    reference = dataclasses.replace(ref, alpha=alpha, d=d, lower=-turn, upper=turn)
    return table, reference


@pytest.fixture(scope="module")
def gen3():
    table, reference = rounded_gen3()
    return table, reference, General7RIK(table, table.lower, table.upper)


def test_the_rounded_arm_takes_the_snapped_form_with_joint_1_held(gen3):
    """No special form fits the rounded table; the general form holds the snapped arm's joint 1."""
    table, _, closed = gen3
    assert isinstance(closed.ideal, SevenDofIK)
    assert closed.free == 0


def test_the_branches_are_the_general_eliminations_at_every_value(gen3):
    """Same branches as the 6R elimination at each held value, each on the pose (NumPy DH),
    the q the pose came from among those at its own value."""
    table, reference, closed = gen3
    exact = General7RIK(table, table.lower, table.upper)
    exact.ideal = None  # the same held joint, the general elimination
    rng = np.random.default_rng(5)
    q = rng.uniform(-math.pi, math.pi, (POSES, 7))
    q[:, [1, 3, 5]] *= 0.7  # away from the folded arm
    poses = fk_frames(reference, q)[:, -1]
    compared = 0
    for k, pose in enumerate(poses):
        values = np.concatenate(([q[k, 0]], rng.uniform(-math.pi, math.pi, VALUES - 1)))
        ours = closed.branches_at(pose[:3, 3], pose[:3, :3], values)
        theirs = exact.branches_at(pose[:3, 3], pose[:3, :3], values)
        for g in range(VALUES):
            a = ours[g][np.isfinite(ours[g]).all(axis=1)]
            b = theirs[g][np.isfinite(theirs[g]).all(axis=1)]
            assert a.shape == b.shape, f"pose {k} value {g}: {len(a)} != {len(b)}"
            if not len(a):
                continue
            gap = np.abs(np.remainder(a[:, None] - b[None] + math.pi, 2 * math.pi) - math.pi)
            assert gap.max(axis=2).min(axis=1).max() < 1e-8, f"pose {k} value {g}"
            assert np.all(a[:, 0] == values[g])
            reached = fk_frames(reference, a)[:, -1]
            assert np.linalg.norm(reached[:, :3, 3] - pose[:3, 3], axis=1).max() < 1e-9
            assert rotation_angle(reached[:, :3, :3], pose[:3, :3]).max() < 1e-9
            compared += len(a)
        first = ours[0][np.isfinite(ours[0]).all(axis=1)]
        assert wrapped_gap(first, q[k]).min() < 1e-6, f"pose {k}: q not among the branches"
    assert compared > POSES * VALUES, compared


def test_all_branches_through_the_twin_is_the_python_paths(gen3):
    """``held_rows`` then ``sift_rows`` give the Python path's branches, order and rejected."""
    table, reference, _ = gen3
    solver = get_solver(kin.robot_from_table(table))
    closed = solver.closed_form
    assert isinstance(closed, General7RIK) and closed.ideal is not None
    arm = branch_arm.branch_arm(solver, closed)
    if arm.rows is None:
        pytest.skip("the compiled twins are not built")
    rng = np.random.default_rng(8)
    poses = fk_frames(reference, rng.uniform(-2.0, 2.0, (4, 7)))[:, -1]
    seeds = rng.uniform(-2.0, 2.0, (4, 7))
    for pose, seed in zip(poses, seeds):
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        fast = solver.solve(target, seed, all_branches=True)
        branch_arm._remember(solver, dataclasses.replace(arm, sift=None, rows=None))
        try:
            slow = solver.solve(target, seed, all_branches=True)
        finally:
            branch_arm._remember(solver, arm)
        q_fast = np.array([s.q for s in fast.solutions]).reshape(-1, 7)
        q_slow = np.array([s.q for s in slow.solutions]).reshape(-1, 7)
        assert fast.message == slow.message and q_fast.shape[0] > 1
        assert q_fast.shape == q_slow.shape
        np.testing.assert_allclose(q_fast, q_slow, rtol=0, atol=1e-10)
        assert len(fast.rejected) == len(slow.rejected)
        reached = fk_frames(reference, q_fast)[:, -1]
        assert np.linalg.norm(reached[:, :3, 3] - pose[:3, 3], axis=1).max() < 1e-9


def test_an_arm_far_from_a_special_one_gets_no_snapped_form():
    """Random offsets of centimetres: nothing to snap that makes a special form fit."""
    rng = np.random.default_rng(3)
    a, d = rng.uniform(-0.4, 0.4, (2, 7))
    alpha, theta = rng.uniform(-np.pi, np.pi, (2, 7))
    table = make_table(a, alpha, d, theta, "standard", random_pose(rng), random_pose(rng))
    assert ideal_form(table, table.lower, table.upper) is None
    assert General7RIK(table, table.lower, table.upper).ideal is None


def test_a_scan_through_the_twin_gives_the_python_branches(gen3):
    """One target at many held values (a free-joint scan): ``held_rows_at`` (the twin, values
    near a double root by the 6R elimination) gives :func:`held_branches`' rows, slot by slot."""
    table, reference, closed = gen3
    twin = held_twin(closed.ideal, closed.table)
    if twin is None:
        pytest.skip("the compiled twins are not built")
    rng = np.random.default_rng(11)
    q = rng.uniform(-2.5, 2.5, (6, 7))
    poses = fk_frames(reference, q)[:, -1]
    values = np.concatenate((np.linspace(-math.pi, math.pi, 61), q[:, 0]))
    doubts = compared = 0
    for pose in poses:
        fast = held_rows_at(twin, closed.fold_margin, closed.end, pose, values)
        targets = np.broadcast_to(pose, (values.size, 4, 4))
        sub = closed.end.targets(targets, values)
        q6 = held_branches(closed.ideal, closed.fold_margin, closed.end, targets, values, sub)
        slow = closed.end.joint_vectors(q6, values)
        assert fast is not None and fast.shape == slow.shape
        np.testing.assert_array_equal(np.isnan(fast), np.isnan(slow))
        np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-10, equal_nan=True)
        compared += int(np.isfinite(fast).all(axis=2).sum())
        folds = np.full(values.size, np.inf)
        closed.ideal.branches_at(pose[:3, 3], pose[:3, :3], values, folds)  # the folds alone
        doubts += int((folds < closed.fold_margin).sum())
    assert compared > 6 * values.size  # rows on most values
    assert doubts > 0  # values left to the 6R elimination are among them
    assert (
        held_rows_at(twin, closed.fold_margin, closed.end, np.full((4, 4), np.nan), values) is None
    )
