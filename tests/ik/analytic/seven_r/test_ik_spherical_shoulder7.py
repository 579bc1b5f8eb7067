"""Closed-form IK of 7R arms with a spherical shoulder, joint 7 free (kin.ik.analytic.seven_r.spherical_shoulder7).

Round trips on every branch against Pinocchio's FK of the table's URDF: every branch that exists
for the original q7 reaches the target to 1e-9 m / 1e-9 rad, and the original q is among them.
Arms: Panda and xArm7 (makers' modified DH), and seeded random tables of the family in both
conventions (random lengths, twists, joint offsets, base and tool). The recogniser is tried on
near-misses; the batched solve against the scalar one; the numeric solver's stage 0 on Panda and
xArm7 full poses, every success checked by an independent NumPy DH product
(``tests/support/dh_reference.py``) and the limits.
"""

from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np
import pytest
from support.arm_tables import TOL, Reference, make_table, random_pose, wrapped_gap
from support.dh_reference import fk_frames, load_reference, rotation_angle
from support.solver_caps import NO_CAP

import kin
from dh2urdf import DHTable, get_robot
from kin.ik.analytic.seven_r.seven_dof import SevenDofIK
from kin.ik.analytic.seven_r.shoulder7_structure import spherical_shoulder7
from kin.ik.analytic.seven_r.spherical_shoulder7 import SphericalShoulder7RIK
from kin.ik.exceptions import StructureError, TargetError
from kin.ik.numeric.numeric_target import NumericTarget
from kin.ik.numeric.solver import NumericIK

SAMPLES = 100
PI = math.pi
RANDOM = ("random_standard_0", "random_standard_1", "random_modified_0", "random_modified_1")
ARMS = ("panda", "xarm7", *RANDOM)


def random_family_table(seed: int, convention: str) -> DHTable:
    """A random arm of the family: axes 1-3 meet, axes 5-6 meet, everything else random."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(-0.5, 0.5, 7)
    d = rng.uniform(-0.5, 0.5, 7)
    theta = rng.uniform(-PI, PI, 7)
    alpha = rng.uniform(0.3, PI - 0.3, 7) * rng.choice([-1.0, 1.0], 7)
    j = 0 if convention == "standard" else 1  # modified: row i + 1 holds the normal of axes i, i+1
    a[0 + j] = a[1 + j] = a[4 + j] = 0.0
    d[1] = 0.0
    return make_table(a, alpha, d, theta, convention, random_pose(rng), random_pose(rng),
                      f"shoulder7_{convention}_{seed}")  # fmt: skip


@functools.cache
def arm_table(name: str) -> DHTable:
    if name in ("panda", "xarm7"):
        return kin.load_robot(name).table
    _, convention, seed = name.split("_")
    return random_family_table(int(seed) + (0 if convention == "standard" else 10), convention)


@functools.cache
def reference(name: str) -> Reference:
    return Reference(arm_table(name), solved=slice(0, 6))  # q7 is given


def solver_of(name: str) -> SphericalShoulder7RIK:
    table = arm_table(name)
    lower = [row.lower for row in table.rows]
    upper = [row.upper for row in table.rows]
    return SphericalShoulder7RIK(spherical_shoulder7(table), lower, upper)


def sample_q(name: str, count: int, seed: int) -> np.ndarray:
    table = arm_table(name)
    lower = np.maximum([row.lower for row in table.rows], -PI)
    upper = np.minimum([row.upper for row in table.rows], PI)
    return np.random.default_rng(seed).uniform(lower, upper, (count, 7))


@pytest.mark.parametrize("arm", ARMS)
def test_every_branch_reaches_the_target_and_q_is_among_them(arm):
    """Every existing branch at the original q7 reaches FK(q) within 1e-9 m / 1e-9 rad; q is one."""
    ref, solver = reference(arm), solver_of(arm)
    worst, counted = 0.0, 0
    for q in sample_q(arm, SAMPLES, 17):
        target = ref.fk(q)
        found = solver.solve(target.translation, target.rotation, q[6])
        assert found.shape == (8, 7)
        exist = found[~np.isnan(found[:, 0])]
        assert not np.isnan(exist).any()
        assert np.all((exist[:, :6] > -PI) & (exist[:, :6] <= PI)), f"{arm=} {exist=}"
        assert np.all(exist[:, 6] == q[6]), f"{arm=}"
        worst = max(worst, ref.check_branches(exist, q, target, f"{arm=}"))
        counted += len(exist)
    assert counted >= 2 * SAMPLES, f"{arm=}: {counted=}"
    assert worst < TOL, f"{arm=} {worst=}"


@pytest.mark.parametrize("arm", ("panda", "random_modified_0"))
def test_other_q7_values_give_branches_that_keep_q7(arm):
    """Joint 7 is free: at another q7 the branches still reach the pose, with that q7."""
    ref, solver = reference(arm), solver_of(arm)
    reached = 0
    for q in sample_q(arm, 30, 5):
        target = ref.fk(q)
        for q7 in (q[6] + 0.2, q[6] - 0.3):
            found = solver.solve(target.translation, target.rotation, q7)
            for branch in found[~np.isnan(found[:, 0])]:
                assert branch[6] == q7
                assert max(ref.errors(branch, target)) < TOL, f"{arm=} {q=} {q7=}"
                reached += 1
    assert reached >= 30, f"{arm=} {reached=}"


def test_generic_panda_pose_has_8_distinct_branches_without_limits():
    """A generic Panda pose (limits aside) has 8 distinct branches at its q7."""
    ref, solver = reference("panda"), solver_of("panda")
    q = np.array([0.92, 0.17, 1.74, 1.26, -1.99, 1.43, -1.87])
    target = ref.fk(q)
    found = solver.solve(target.translation, target.rotation, q[6])
    assert not np.isnan(found).any()
    assert np.ptp(found[:4, 3]) < 1e-12 and np.ptp(found[4:, 3]) < 1e-12  # one elbow per half
    assert np.ptp(found[:2, 4:6], axis=0).max() < 1e-12  # one wrist, two shoulders
    gaps = [wrapped_gap(found[j : j + 1], found[i]).min() for i in range(8) for j in range(i)]
    assert min(gaps) > 1e-3


@pytest.mark.parametrize("arm", ARMS)
def test_batch_gives_the_same_numbers_as_solve(arm):
    """solve_batch equals solve row by row (NaN where solve has NaN) to rounding."""
    table, solver = arm_table(arm), solver_of(arm)
    q = sample_q(arm, 300, 3)
    poses = kin.batch_forward_kinematics(table, q)
    poses[:10, :3, 3] *= 10.0  # some targets out of reach
    q7 = q[:, 6] + np.linspace(-0.5, 0.5, len(q))
    batch = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3], q7)
    scalar = np.array([solver.solve(T[:3, 3], T[:3, :3], v) for T, v in zip(poses, q7)])
    assert batch.shape == (300, 8, 7)
    np.testing.assert_array_equal(np.isnan(batch), np.isnan(scalar))
    np.testing.assert_allclose(batch, scalar, rtol=0.0, atol=1e-9, equal_nan=True)
    assert np.isnan(batch[:10]).all(), f"{arm=}: out-of-reach targets have no branch"


def test_batch_rejects_bad_shapes():
    solver = solver_of("panda")
    with pytest.raises(TargetError, match="positions must be"):
        solver.solve_batch(np.zeros((2, 3)), np.zeros((3, 3, 3)), [0.0, 0.0])
    with pytest.raises(TargetError, match="q7 must be"):
        solver.solve_batch(np.zeros((2, 3)), np.tile(np.eye(3), (2, 1, 1)), [0.0, 0.0, 0.0])


# ---------------------------------------------------------------------------------------------
# The recogniser


@pytest.mark.parametrize("arm", ARMS)
def test_family_tables_fit(arm):
    """Panda, xArm7 and the random family tables fit."""
    assert spherical_shoulder7(arm_table(arm)).offsets == tuple(
        r.theta for r in arm_table(arm).rows
    )


def with_row(table: DHTable, index: int, **changes) -> DHTable:
    rows = list(table.rows)
    rows[index] = replace(rows[index], **changes)
    return replace(table, rows=tuple(rows))


@pytest.mark.parametrize(
    ("arm", "row", "field", "value", "message"),
    [
        # 1e-4 m between axes 5 and 6 (modified: row 6 holds their normal; standard: row 5).
        ("panda", 5, "a", 1e-4, r"row 6 \('panda_joint6'\): a = 0\.0001 m, expected 0 "
         r"\(axes 5 and 6 must meet at the wrist point\)"),
        ("random_standard_0", 4, "a", 1e-4, r"row 5 \('j5'\): a = 0\.0001 m, expected 0"),
        # Axes 1-3 meeting pairwise, 1e-4 m apart along axis 2.
        ("xarm7", 1, "d", 1e-4, r"row 2 \('joint2'\): d = 0\.0001 m, expected 0 "
         r"\(axes 1, 2 and 3 must meet in one point\)"),
        ("panda", 2, "a", -1e-4, r"row 3 \('panda_joint3'\): a = -0\.0001 m, expected 0 "
         r"\(axes 2 and 3 must meet"),
        # Parallel shoulder or wrist axes.
        ("panda", 1, "alpha", 0.0, r"row 2 \('panda_joint2'\): alpha = 0 deg, expected an angle "
         r"other than 0 or 180 deg \(axes 1 and 2 must not be parallel\)"),
        ("random_standard_1", 4, "alpha", PI, r"row 5 \('j5'\): alpha = 180 deg"),
    ],
)  # fmt: skip
def test_near_misses_name_the_row_and_parameter(arm, row, field, value, message):
    """An offset of 1e-4 m is not taken for 0; the error names the row and the parameter."""
    table = with_row(arm_table(arm), row, **{field: value})
    with pytest.raises(StructureError, match=message):
        spherical_shoulder7(table)


@pytest.mark.parametrize("arm", ("panda", "random_modified_1"))
def test_a_twist_of_89_9_deg_is_read_not_rounded_to_90(arm):
    """Twist 89.9 deg where the table has about 90: still the family, and the round trip stays exact
    (the solver uses the table's twist, not 90 deg)."""
    table = with_row(arm_table(arm), 3, alpha=math.radians(89.9))
    ref = Reference(table, solved=slice(0, 6))
    solver = SphericalShoulder7RIK(spherical_shoulder7(table), [-2 * PI] * 7, [2 * PI] * 7)
    for q in sample_q(arm, 20, 9):
        target = ref.fk(q)
        found = solver.solve(target.translation, target.rotation, q[6])
        exist = found[~np.isnan(found[:, 0])]
        assert len(exist) >= 1 and wrapped_gap(exist, q).min() < 1e-6, f"{arm=} {q=}"
        for branch in exist:
            assert max(ref.errors(branch, target)) < TOL, f"{arm=} {q=}"


def test_a_twist_of_0_1_deg_is_not_taken_for_parallel():
    """Axes 5 and 6 at 0.1 deg meet at one point (a = 0): the table fits; at 0 deg it does not."""
    panda = arm_table("panda")
    spherical_shoulder7(with_row(panda, 5, alpha=math.radians(0.1)))
    with pytest.raises(StructureError, match="axes 5 and 6 must not be parallel"):
        spherical_shoulder7(with_row(panda, 5, alpha=0.0))


@pytest.mark.parametrize("name", ["humanoid7", "ur5", "puma560", "lab5"])
def test_other_shipped_arms_do_not_fit(name):
    """humanoid7 (axes 1-3 do not meet), 6R and 5R arms: StructureError naming the mismatch."""
    with pytest.raises(StructureError, match="does not fit the seven-joint \\(spherical shoulder"):
        spherical_shoulder7(kin.load_robot(name).table)


def test_prismatic_joint_and_elbow_on_the_shoulder_are_rejected():
    panda = arm_table("panda")
    with pytest.raises(StructureError, match=r"row 4 \('panda_joint4'\) is prismatic"):
        spherical_shoulder7(with_row(panda, 3, joint_type="prismatic"))
    # xArm7 with axis 4 through the shoulder point (a3 = d4 = 0 and d3 = 0): a degenerate elbow.
    flat = with_row(with_row(arm_table("xarm7"), 3, a=0.0), 2, d=0.0)
    with pytest.raises(StructureError, match="shoulder point lies on axis 4"):
        spherical_shoulder7(flat)


# ---------------------------------------------------------------------------------------------
# Stage 0 of the numeric solver


@pytest.mark.parametrize("name", ["panda", "xarm7"])
def test_numeric_solver_takes_this_closed_form_for_panda_and_xarm7(name):
    """The numeric solver's free-joint closed form: this one for Panda and xArm7, SevenDofIK first."""
    assert isinstance(NumericIK(kin.load_robot(name)).closed_form, SphericalShoulder7RIK)
    assert isinstance(NumericIK(kin.load_robot("humanoid7")).closed_form, SevenDofIK)
    assert NumericIK(kin.load_robot(name), closed_form=False).closed_form is None


@pytest.mark.parametrize("name", ["panda", "xarm7"])
def test_numeric_solver_answers_full_poses_in_closed_form_verified_by_numpy(name):
    """Full poses of 200 random q within the limits: most answered by closed_form_free_joint;
    every success reaches the target by a plain NumPy DH product and is inside the limits."""
    robot = kin.load_robot(name)
    solver = NumericIK(robot)
    numpy_table = load_reference(get_robot(name).table_path)
    rng = np.random.default_rng(23)
    q = rng.uniform(robot.lower, robot.upper, (200, 7))
    poses = fk_frames(numpy_table, q)[:, -1]
    seed = np.clip(np.zeros(7), robot.lower, robot.upper)
    methods, answers = [], []
    for pose in poses:
        result = solver.solve(NumericTarget(pose[:3, 3], pose[:3, :3]), seed=seed, timeout=NO_CAP)
        assert result.success, f"{name=} {result.message=}"
        methods.append(result.method)
        answers.append(result.solutions[0].q)
    assert methods.count("closed_form_free_joint") >= 0.95 * len(poses), f"{name=} {methods=}"
    found = np.array(answers)
    reached = fk_frames(numpy_table, found)[:, -1]
    assert np.linalg.norm(reached[:, :3, 3] - poses[:, :3, 3], axis=1).max() < 1e-5, f"{name=}"
    assert rotation_angle(reached[:, :3, :3], poses[:, :3, :3]).max() < 1e-4, f"{name=}"
    assert np.all((found >= robot.lower) & (found <= robot.upper)), f"{name=}"


def test_position_targets_go_to_the_numeric_stages():
    """This structure takes full poses only: a position target on Panda is answered numerically."""
    robot = kin.load_robot("panda")
    solver = NumericIK(robot)
    assert solver.closed_form is not None
    assert solver.closed_form.prepare(np.zeros(3), None) is None
    q = np.array([0.3, -0.6, 0.4, -1.8, -1.1, 1.4, 0.5])
    position = kin.Configuration(robot).fk(q).translation
    result = solver.solve(NumericTarget(position, None), timeout=NO_CAP)
    assert result.success and result.method != "closed_form_free_joint", f"{result.method=}"


def test_first_keeps_the_start_q7_when_it_has_a_branch_and_scans_otherwise():
    """From a solution the same q7 (and q) come back; from a far q7 the scan finds the nearest one."""
    robot = kin.load_robot("panda")
    ik = solver_of("panda")
    ref = reference("panda")
    q = np.array([0.3, -0.6, 0.4, -1.8, -1.1, 1.4, 0.5])
    target = ref.fk(q)
    prepared = ik.prepare(target.translation, target.rotation)
    out = np.empty(7)
    assert ik.first(prepared, q[None], out, 0.0) == 0
    np.testing.assert_allclose(out, q, atol=1e-9)
    starts = np.array([[np.nan] * 7, q + np.array([0, 0, 0, 0, 0, 0, 0.3])])
    assert ik.first(prepared, starts, out, 0.05) == 1
    # The answer's q7 is on the scan grid from the start's, and no nearer grid value has a branch.
    start7 = q[6] + 0.3
    steps = round((out[6] - start7) / 0.05)
    assert abs(out[6] - (start7 + steps * 0.05)) < 1e-12, f"{out[6]=} off the grid"
    nearer = [start7 + k * 0.05 for k in range(-abs(steps) + 1, abs(steps))]
    for q7 in nearer:
        start = np.array([*q[:6], q7])
        assert ik.first(prepared, start[None], np.empty(7), 0.0) == -1, f"{q7=} has a branch"
    assert np.all((out >= robot.lower) & (out <= robot.upper))
    assert max(ref.errors(out, target)) < TOL
    assert ik.first(None, q[None], out, 0.05) == -1
