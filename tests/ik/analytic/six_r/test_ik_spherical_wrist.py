"""Closed-form IK of 6R arms with a spherical wrist (kin.ik.analytic.six_r.spherical_wrist).

Round trips on every branch against Pinocchio's FK of the table's URDF: every branch that exists
reaches the target to 1e-9 m / 1e-9 rad, and the original q is among the branches (modulo 2 pi).
Arms: PUMA 560 (standard DH as in the Robotics Toolbox), PUMA 560 on a moved base with a tool,
and seeded random tables of the family in both conventions (random lengths, shoulder offsets,
joint offsets, base and tool; twists either +-90 deg or random where the structure allows).
Where the Robotics Toolbox is installed, its analytic ``ikine_a`` of its own Puma560 must be among
the branches.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from support.arm_tables import TOL, Reference, assert_round_trips, make_table, wrapped_gap
from support.spherical_wrist_arms import (
    ARMS,
    PUMA_A,
    PUMA_ALPHA,
    PUMA_D,
    arm_table,
    random_pieper_table,
)

import kin
from dh2urdf import DHRow, DHTable
from kin.ik.analytic.six_r.spherical_wrist import SphericalWrist6R
from kin.ik.exceptions import StructureError

SAMPLES = 200
PI = math.pi


@functools.cache
def reference(name: str) -> Reference:
    return Reference(arm_table(name))


@pytest.mark.parametrize("arm", ARMS)
def test_every_branch_reaches_the_target_and_q_is_among_them(arm):
    """Every existing branch reaches FK(q) within 1e-9 m / 1e-9 rad; q is one of the branches."""
    assert_round_trips(
        SphericalWrist6R.recognise(arm_table(arm)), reference(arm), SAMPLES, 17, f"{arm=}"
    )


def test_puma_has_8_distinct_branches_at_a_generic_pose():
    """A generic PUMA 560 pose has 8 distinct solutions, one per label, in the documented signs."""
    ref, solver = reference("puma560"), SphericalWrist6R.recognise(arm_table("puma560"))
    target = ref.fk([0.3, -0.6, 0.4, 0.8, -1.1, 0.4])
    found = solver.solve(target.translation, target.rotation)
    assert not np.isnan(found).any()
    gaps = [wrapped_gap(found[j : j + 1], found[i]).min() for i in range(8) for j in range(i)]
    assert min(gaps) > 1e-3
    assert len(SphericalWrist6R.branch_labels) == 8
    for index, label in enumerate(SphericalWrist6R.branch_labels):
        assert (math.sin(found[index, 4]) >= 0) == ("no flip" in label), label
    assert np.ptp(found[:4, 0]) < 1e-12 and np.ptp(found[4:, 0]) < 1e-12
    assert np.ptp(found[:2, 1:3], axis=0).max() < 1e-12  # one arm, two wrists


@pytest.mark.parametrize("arm", ARMS)
def test_batch_gives_the_same_numbers_as_solve(arm):
    """solve_batch equals solve row by row (NaN where solve has NaN) to rounding."""
    table = arm_table(arm)
    solver = SphericalWrist6R.recognise(table)
    rng = np.random.default_rng(3)
    q = rng.uniform(-PI, PI, (500, 6))
    poses = kin.batch_forward_kinematics(table, q)
    poses[:20, :3, 3] *= 5.0  # some targets out of reach
    batch = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    scalar = np.array([solver.solve(T[:3, 3], T[:3, :3]) for T in poses])
    assert batch.shape == (500, 8, 6)
    np.testing.assert_array_equal(np.isnan(batch), np.isnan(scalar))
    np.testing.assert_allclose(batch, scalar, rtol=0.0, atol=1e-9, equal_nan=True)


def test_out_of_reach_gives_nan_rows():
    """A target far beyond the reach has no branch."""
    solver = SphericalWrist6R.recognise(arm_table("puma560"))
    assert np.isnan(solver.solve(np.array([3.0, 0.0, 0.5]), np.eye(3))).all()
    assert np.isnan(solver.solve_batch(np.array([[3.0, 0.0, 0.5]]), np.eye(3)[None])).all()


@pytest.mark.parametrize("arm", ("puma560", "random_modified_0"))
def test_singular_wrist_takes_the_free_value_and_still_reaches(arm):
    """Axes 4 and 6 aligned (t5 = 0): q4 = free, the branches still reach the pose."""
    table = arm_table(arm)
    ref, solver = reference(arm), SphericalWrist6R.recognise(table)
    q = np.array([0.4, -0.5, 0.3, 0.9, -solver.offsets[4], 0.7])  # t5 = 0
    target = ref.fk(q)
    for free in (0.0, -0.3):
        found = solver.solve(target.translation, target.rotation, free=free)
        exist = found[~np.isnan(found[:, 0])]
        assert len(exist) >= 2
        singular = np.abs(np.sin(exist[:, 4] + solver.offsets[4])) < 1e-9
        assert singular.any()
        np.testing.assert_allclose(exist[singular, 3], free, atol=1e-12)
        for branch in exist:
            assert max(ref.errors(branch, target)) < TOL, f"{arm=} {branch=}"
        batch = solver.solve_batch(target.translation[None], target.rotation[None], free=free)
        np.testing.assert_allclose(batch[0], found, atol=1e-9, equal_nan=True)


# ---------------------------------------------------------------------------------------------
# Recognition


def test_puma_table_is_recognised_with_its_numbers():
    """PUMA 560: shoulder offset d3 (lateral), forearm (a3, d4)."""
    solver = SphericalWrist6R.recognise(arm_table("puma560"))
    assert solver.a2 == 0.4318 and solver.lateral == pytest.approx(0.15005, abs=1e-15)
    assert solver.forearm == pytest.approx((0.0203, 0.4318), abs=1e-15)
    assert SphericalWrist6R.name == "spherical_wrist" and SphericalWrist6R.dof == 6


def test_an_89_9_deg_twist_is_solved_as_89_9_not_90():
    """A table with alpha1 = 89.9 deg is not rounded to 90: the round trip stays at 1e-9."""
    alpha = list(PUMA_ALPHA)
    alpha[0] = math.radians(89.9)
    table = make_table(PUMA_A, alpha, PUMA_D, [0] * 6, name="puma_89_9")
    solver = SphericalWrist6R.recognise(table)
    assert solver.alpha1 == math.radians(89.9)
    q = np.array([0.3, -0.6, 0.4, 0.8, -1.1, 0.4])
    pose = kin.batch_forward_kinematics(table, q)[0]
    found = solver.solve(pose[:3, 3], pose[:3, :3])
    assert wrapped_gap(found[~np.isnan(found[:, 0])], q).min() < TOL


def puma_with(row: int, **changes) -> DHTable:
    """PUMA 560 with a changed row (1-based)."""
    values = {"a": list(PUMA_A), "alpha": list(PUMA_ALPHA), "d": list(PUMA_D)}
    for field, value in changes.items():
        values[field][row - 1] = value
    return make_table(values["a"], values["alpha"], values["d"], [0] * 6, name="puma_variant")


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        (puma_with(2, alpha=math.radians(0.1)), ["row 2 ('j2'): alpha = 0.1 deg, expected 0 deg"]),
        (puma_with(2, alpha=math.radians(89.9)), ["row 2 ('j2'): alpha = 89.9 deg"]),
        (puma_with(4, a=1e-6), ["row 4 ('j4'): a = 1e-06 m, expected 0"]),
        (puma_with(5, a=-1e-3), ["row 5 ('j5'): a = -0.001 m, expected 0"]),
        (puma_with(5, d=0.01), ["row 5 ('j5'): d = 0.01 m, expected 0"]),
        (puma_with(4, alpha=0.0), ["row 4 ('j4'): alpha = 0 deg, expected an angle other than"]),
        (puma_with(5, alpha=PI), ["row 5 ('j5'): alpha = 180 deg"]),
        (puma_with(1, alpha=0.0), ["row 1 ('j1'): alpha = 0 deg"]),
        (puma_with(2, a=0.0), ["row 2 ('j2'): a = 0 m, expected non-zero"]),
    ],
    ids=[
        "alpha2=0.1",
        "alpha2=89.9",
        "a4=1um",
        "a5=-1mm",
        "d5=1cm",
        "alpha4=0",
        "alpha5=180",
        "alpha1=0",
        "a2=0",
    ],  # fmt: skip
)
def test_near_misses_are_refused_naming_row_and_parameter(table, expected):
    """A table that almost has a spherical wrist raises StructureError naming row and parameter."""
    with pytest.raises(StructureError) as info:
        SphericalWrist6R.recognise(table)
    for text in expected:
        assert text in str(info.value), str(info.value)
    assert info.value.solver == "6R spherical-wrist"


def test_modified_near_miss_names_the_modified_row():
    """In Craig's convention a5 (joint 5's normal) is in row 6: the error names row 6."""
    table = random_pieper_table(10, "modified", skew=False)
    rows = list(table.rows)
    r = rows[5]
    rows[5] = DHRow(6, "j6", "revolute", 0.002, r.alpha, r.d, r.theta, -PI, PI, 1.0, 1.0)
    bad = DHTable("bad", "", "", "modified", tuple(rows))
    with pytest.raises(StructureError, match=r"row 6 \('j6'\): a \(modified convention"):
        SphericalWrist6R.recognise(bad)


def test_wrong_joint_count_ur5_and_prismatic_are_refused():
    """Seven joints, a UR arm (offset wrist), or a prismatic joint is not this family."""
    from dh2urdf import get_robot, load_table

    puma = arm_table("puma560")
    seven = DHTable("seven", "", "", "standard", (*puma.rows, puma.rows[0]))
    with pytest.raises(StructureError, match="7 joints, expected 6"):
        SphericalWrist6R.recognise(seven)
    with pytest.raises(StructureError, match=r"row 5 \('wrist_2_joint'\): d = 0.09465 m"):
        SphericalWrist6R.recognise(load_table(get_robot("ur5").table_path))
    rows = list(puma.rows)
    r = rows[1]
    rows[1] = DHRow(2, r.name, "prismatic", r.a, r.alpha, r.d, r.theta, 0.0, 1.0, 1.0, 1.0)
    with pytest.raises(StructureError, match=r"row 2 \('j2'\) is prismatic"):
        SphericalWrist6R.recognise(DHTable("p", "", "", "standard", tuple(rows)))


# ---------------------------------------------------------------------------------------------
# Peer


@pytest.mark.peer
def test_ikine_a_of_the_robotics_toolbox_is_among_the_branches():
    """Puma560 of the Robotics Toolbox: each of its 8 ikine_a configurations is one of ours."""
    rtb = pytest.importorskip("roboticstoolbox", reason="roboticstoolbox is not installed")
    robot = rtb.models.DH.Puma560()
    links = robot.links
    table = make_table([L.a for L in links], [L.alpha for L in links], [L.d for L in links],
                       [L.offset for L in links], name="rtb_puma560")  # fmt: skip
    solver = SphericalWrist6R.recognise(table)
    rng = np.random.default_rng(560)
    compared = 0
    for q in rng.uniform(-PI, PI, (100, 6)):
        pose = robot.fkine(q).A
        np.testing.assert_allclose(kin.batch_forward_kinematics(table, q)[0], pose, atol=1e-12)
        ours = solver.solve(pose[:3, 3], pose[:3, :3])
        ours = ours[~np.isnan(ours[:, 0])]
        for config in ("lun", "luf", "ldn", "ldf", "run", "ruf", "rdn", "rdf"):
            theirs = robot.ikine_a(pose, config=config)
            if not theirs.success:
                continue
            assert wrapped_gap(ours, theirs.q).min() < 1e-9, f"{q=} {config=} {theirs.q=}"
            compared += 1
    assert compared >= 400


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_antiparallel_axes_are_turned_over(convention):
    """A spherical-wrist arm whose axes 2 and 3 are antiparallel (twist pi, as a URDF extraction
    writes them) is this family's, not the general Pieper one's: the table is solved with axis 3
    turned over (q3' = -q3); every branch, mapped back, reaches FK(q) by Pinocchio on the
    table's URDF and the q is among them."""
    import dataclasses

    import pinocchio as pin

    from kin.ik import PoseTarget, get_solver

    base = random_pieper_table(3, convention, skew=False)
    # The twist joining axes 2 and 3 (row 2 standard, row 3 modified) becomes pi; joint 3's
    # axis turns over (its theta and d change sign) and the next twist gains pi.
    twist, following = (1, 2) if convention == "standard" else (2, 3)
    rows = list(base.rows)
    rows[twist] = dataclasses.replace(rows[twist], alpha=PI)
    row = rows[2]
    rows[2] = dataclasses.replace(row, theta=-row.theta, d=-row.d)
    after = rows[following]
    rows[following] = dataclasses.replace(after, alpha=math.remainder(after.alpha + PI, 2 * PI))
    table = dataclasses.replace(base, rows=tuple(rows), name=f"antiparallel_{convention}")
    robot = kin.robot_from_table(table)
    solver = get_solver(robot)
    assert solver.name == "closed_form:spherical_wrist", solver.name
    data = robot.model.createData()
    frame = robot.model.getFrameId(robot.tool_frame)
    rng = np.random.default_rng(8)
    for q in rng.uniform(-PI, PI, (100, 6)):
        pin.framesForwardKinematics(robot.model, data, q)
        pose = data.oMf[frame].copy()
        result = solver.solve(PoseTarget(pose.translation, pose.rotation))
        branches = [s.q for s in result.solutions + result.rejected]
        assert branches and wrapped_gap(np.array(branches), q).min() < 1e-6
        for branch in branches:
            pin.framesForwardKinematics(robot.model, data, branch)
            assert np.abs(pin.log6(data.oMf[frame].actInv(pose)).vector).max() < TOL
