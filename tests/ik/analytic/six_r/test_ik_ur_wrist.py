"""Closed-form IK of the UR family (kin.ik.analytic.six_r.ur_wrist) against Pinocchio and ur-analytic-ik.

Round trips on every branch: FK(q) by Pinocchio -> ``solve`` -> every branch that exists reaches
the target to 1e-9 m / 1e-9 rad by Pinocchio's FK, and q is among the branches (modulo 2 pi). Arms:
the shipped UR5, UR5 on a moved base with a tool, and seeded random tables of the family (random
lengths, offsets, joint-1 twist, signs of the wrist twists, base and tool), in both conventions.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from support.arm_tables import TOL, Reference, assert_round_trips, make_table, wrapped_gap
from support.ur_wrist_arms import UR5, arm_table, random_ur_table

import kin
from dh2urdf import DHRow, DHTable, get_robot, load_table
from kin.ik.analytic.six_r.ur_wrist import URWrist6R
from kin.ik.exceptions import StructureError

SAMPLES = 200
PI = math.pi


@functools.cache
def reference(name: str) -> Reference:
    return Reference(arm_table(name))


@pytest.mark.parametrize("arm", UR5)
def test_every_branch_reaches_the_target_and_q_is_among_them(arm):
    """Every existing branch reaches FK(q) within 1e-9 m / 1e-9 rad; q is one of the branches."""
    assert_round_trips(URWrist6R.recognise(arm_table(arm)), reference(arm), SAMPLES, 11, f"{arm=}")


def test_ur5_has_8_distinct_branches_at_a_generic_pose():
    """A generic UR5 pose has 8 distinct solutions, one per label, in the documented signs."""
    ref, solver = reference("ur5"), URWrist6R.recognise(arm_table("ur5"))
    target = ref.fk([0.3, -1.2, 1.4, -0.8, 1.1, 0.4])
    found = solver.solve(target.translation, target.rotation)
    assert not np.isnan(found).any()
    gaps = [wrapped_gap(found[j : j + 1], found[i]).min() for i in range(8) for j in range(i)]
    assert min(gaps) > 1e-3
    assert len(URWrist6R.branch_labels) == 8
    for index, label in enumerate(URWrist6R.branch_labels):
        wrist_up, elbow_up = "wrist up" in label, "elbow up" in label
        assert (math.sin(found[index, 4]) >= 0) == wrist_up, label
        assert (math.sin(found[index, 2]) >= 0) == elbow_up, label
    # the two shoulders differ in q1, each shared by its 4 rows
    assert np.ptp(found[:4, 0]) < 1e-12 and np.ptp(found[4:, 0]) < 1e-12


@pytest.mark.parametrize("arm", UR5)
def test_batch_gives_the_same_numbers_as_solve(arm):
    """solve_batch equals solve row by row (NaN where solve has NaN) to rounding."""
    table = arm_table(arm)
    solver = URWrist6R.recognise(table)
    rng = np.random.default_rng(3)
    q = rng.uniform(-PI, PI, (500, 6))
    poses = kin.batch_forward_kinematics(table, q)
    poses[:20, :3, 3] *= 5.0  # some targets out of reach
    batch = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    scalar = np.array([solver.solve(T[:3, 3], T[:3, :3]) for T in poses])
    assert batch.shape == (500, 8, 6)
    np.testing.assert_array_equal(np.isnan(batch), np.isnan(scalar))
    np.testing.assert_allclose(batch, scalar, rtol=0.0, atol=1e-9, equal_nan=True)
    assert np.isnan(batch[:20]).mean() > 0.5


def test_out_of_reach_gives_nan_rows():
    """A target far beyond the reach has no branch."""
    solver = URWrist6R.recognise(arm_table("ur5"))
    assert np.isnan(solver.solve(np.array([3.0, 0.0, 0.5]), np.eye(3))).all()
    assert np.isnan(solver.solve_batch(np.array([[3.0, 0.0, 0.5]]), np.eye(3)[None])).all()


@pytest.mark.parametrize("arm", ("ur5", "random_modified_0"))
def test_singular_wrist_takes_the_free_value_and_still_reaches(arm):
    """sin t5 = 0 (axis 6 parallel to axes 2-4): q6 = free, the branches still reach the pose."""
    table = arm_table(arm)
    ref, solver = reference(arm), URWrist6R.recognise(table)
    q = np.array([0.4, -1.0, 1.2, -0.5, -solver.offsets[4], 0.7])  # t5 = 0
    target = ref.fk(q)
    for free in (0.0, 0.3):
        found = solver.solve(target.translation, target.rotation, free=free)
        exist = found[~np.isnan(found[:, 0])]
        assert len(exist) >= 2
        singular = np.abs(np.sin(exist[:, 4] + solver.offsets[4])) < 1e-9
        assert singular.any()
        np.testing.assert_allclose(exist[singular, 5], free, atol=1e-12)
        for branch in exist:
            assert max(ref.errors(branch, target)) < TOL, f"{arm=} {branch=}"
        batch = solver.solve_batch(target.translation[None], target.rotation[None], free=free)
        np.testing.assert_allclose(batch[0], found, atol=1e-9, equal_nan=True)


# ---------------------------------------------------------------------------------------------
# Recognition


def test_ur5_table_is_recognised_with_its_numbers():
    """The shipped UR5 table is the UR family with the maker's numbers."""
    solver = URWrist6R.recognise(load_table(get_robot("ur5").table_path))
    assert (solver.a2, solver.a3) == (-0.425, -0.39225)
    assert (solver.d1, solver.lateral, solver.d5, solver.d6) == (0.089159, 0.10915, 0.09465, 0.0823)
    assert (solver.alpha4, solver.alpha5, solver.alpha1) == (PI / 2, -PI / 2, PI / 2)
    assert URWrist6R.name == "ur_wrist" and URWrist6R.dof == 6


PUMA = make_table([0, 0.4318, 0.0203, 0, 0, 0], [PI / 2, 0, -PI / 2, PI / 2, -PI / 2, 0],
                  [0, 0, 0.15005, 0.4318, 0, 0], [0] * 6, name="puma560")  # fmt: skip


def ur5_with(row: int, **changes) -> DHTable:
    """UR5 with a changed row (1-based)."""
    table = load_table(get_robot("ur5").table_path)
    rows = list(table.rows)
    fields = {f: getattr(rows[row - 1], f) for f in ("a", "alpha", "d", "theta")}
    fields.update(changes)
    rows[row - 1] = DHRow(row, rows[row - 1].name, "revolute", fields["a"], fields["alpha"],
                          fields["d"], fields["theta"], -PI, PI, 1.0, 1.0)  # fmt: skip
    return DHTable("ur5_variant", "", "", "standard", tuple(rows))


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        (ur5_with(4, alpha=0.0), ["row 4 ('wrist_1_joint'): alpha", "other than 0"]),
        (ur5_with(5, alpha=PI), ["row 5 ('wrist_2_joint'): alpha", "other than 0"]),
        (ur5_with(2, alpha=math.radians(0.1)), ["row 2 ('shoulder_lift_joint'): alpha"]),
        (ur5_with(3, alpha=PI), ["row 3 ('elbow_joint'): alpha", "expected 0 deg"]),
        (ur5_with(5, a=1e-6), ["row 5 ('wrist_2_joint'): a = 1e-06 m, expected 0"]),
        (ur5_with(3, a=0.0), ["row 3 ('elbow_joint'): a = 0 m, expected non-zero"]),
        (ur5_with(1, alpha=0.0), ["row 1 ('shoulder_pan_joint'): alpha", "other than 0"]),
        (PUMA, ["row 3 ('j3'): alpha = -90 deg, expected 0 deg"]),
    ],
    ids=[
        "alpha4=0",
        "alpha5=180",
        "alpha2=0.1",
        "alpha3=180",
        "a5=1um",
        "a3=0",
        "alpha1=0",
        "puma560",
    ],  # fmt: skip
)
def test_near_misses_are_refused_naming_row_and_parameter(table, expected):
    """A table that is almost UR-like raises StructureError naming the row and the parameter."""
    with pytest.raises(StructureError) as info:
        URWrist6R.recognise(table)
    for text in expected:
        assert text in str(info.value), str(info.value)
    assert info.value.solver.startswith("6R UR-wrist")


def test_modified_near_miss_names_the_modified_row():
    """In Craig's convention joint 2's twist is in row 3: the error names row 3."""
    table = random_ur_table(10, "modified")
    rows = list(table.rows)
    rows[2] = DHRow(3, "j3", "revolute", rows[2].a, math.radians(0.1), rows[2].d, 0.0, -PI, PI,
                    1.0, 1.0)  # fmt: skip
    bad = DHTable("bad", "", "", "modified", tuple(rows))
    with pytest.raises(StructureError, match=r"row 3 \('j3'\): alpha \(modified convention"):
        URWrist6R.recognise(bad)


@pytest.mark.parametrize(("row", "degrees"), [(4, 89.9), (5, -90.1), (4, 30.0)])
def test_wrist_twist_near_90_is_solved_with_its_own_value(row, degrees):
    """A wrist twist of 89.9 deg is not taken for 90: the table is solved with 89.9, and every
    branch reaches FK(q) of that table (Pinocchio) with q among them."""
    table = ur5_with(row, alpha=math.radians(degrees))
    solver = URWrist6R.recognise(table)
    assert getattr(solver, f"alpha{row}") == math.radians(degrees)
    ref = Reference(table)
    for q in np.random.default_rng(row).uniform(-PI, PI, (50, 6)):
        target = ref.fk(q)
        for compiled in (True, False):
            found = solver.solve(target.translation, target.rotation, compiled=compiled)
            exist = found[~np.isnan(found[:, 0])]
            ref.check_branches(exist, q, target, f"{row=} {degrees=} {compiled=}")


def test_wrong_joint_count_and_prismatic_are_refused():
    """Five joints, or a prismatic joint, is not this family."""
    table = load_table(get_robot("ur5").table_path)
    five = DHTable("five", "", "", "standard", table.rows[:5])
    with pytest.raises(StructureError, match="5 joints, expected 6"):
        URWrist6R.recognise(five)
    rows = list(table.rows)
    r = rows[2]
    rows[2] = DHRow(3, r.name, "prismatic", r.a, r.alpha, r.d, r.theta, 0.0, 1.0, 1.0, 1.0)
    with pytest.raises(StructureError, match=r"row 3 \('elbow_joint'\) is prismatic"):
        URWrist6R.recognise(DHTable("p", "", "", "standard", tuple(rows)))


# ---------------------------------------------------------------------------------------------
# Peer


@pytest.mark.peer
def test_same_solutions_as_ur_analytic_ik():
    """UR5: the same solutions as ur-analytic-ik on 1000 random targets (1e-9 after matching).

    Its forward kinematics equals our table's product up to one fixed base transform, the same
    for every joint vector (its 0.1.0.post3 puts the base turned half a turn about z, ROS's
    ``base`` rather than ``base_link``); each gets the pose in its own base frame.
    """
    ur_ik = pytest.importorskip("ur_analytic_ik", reason="ur-analytic-ik is not installed")
    table = load_table(get_robot("ur5").table_path)
    solver = URWrist6R.recognise(table)
    rng = np.random.default_rng(7)
    q = rng.uniform(-PI, PI, (1000, 6))
    poses = kin.batch_forward_kinematics(table, q)
    base = ur_ik.ur5.forward_kinematics(*q[0]) @ np.linalg.inv(poses[0])
    np.testing.assert_allclose(base[:3, 3], 0.0, atol=1e-12)  # a turn about z, no shift
    np.testing.assert_allclose(base[2], [0.0, 0.0, 1.0, 0.0], atol=1e-12)
    compared = 0
    for k, pose in enumerate(poses):
        pose_theirs = np.asarray(ur_ik.ur5.forward_kinematics(*q[k]))
        np.testing.assert_allclose(pose_theirs, base @ pose, atol=1e-12)
        theirs = np.array(ur_ik.ur5.inverse_kinematics(np.ascontiguousarray(pose_theirs)))
        ours = solver.solve(pose[:3, 3], pose[:3, :3])
        ours = ours[~np.isnan(ours[:, 0])]
        assert len(theirs) == len(ours), f"{q[k]=}"
        for branch in theirs:
            assert wrapped_gap(ours, branch).min() < 1e-9, f"{q[k]=} {branch=}"
            compared += 1
    assert compared > 4000


def test_batch_larger_than_a_block_and_malformed_targets():
    """More targets than a block give the same rows as solve; malformed shapes raise TargetError."""
    from kin.ik.analytic.six_r._six_r import BLOCK
    from kin.ik.exceptions import TargetError

    table = arm_table("random_modified_0")
    solver = URWrist6R.recognise(table)
    q = np.random.default_rng(4).uniform(-PI, PI, (BLOCK + 3, 6))
    poses = kin.batch_forward_kinematics(table, q)
    batch = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    assert batch.shape == (BLOCK + 3, 8, 6)
    for k in (0, BLOCK - 1, BLOCK, BLOCK + 2):
        scalar = solver.solve(poses[k, :3, 3], poses[k, :3, :3])
        np.testing.assert_allclose(batch[k], scalar, atol=1e-9, equal_nan=True)
    with pytest.raises(TargetError, match=r"got \(2, 3\) and \(3, 3, 3\)"):
        solver.solve_batch(poses[:2, :3, 3], poses[:3, :3, :3])
