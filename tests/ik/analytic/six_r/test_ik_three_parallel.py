"""Closed-form IK of 6R arms with three parallel axes 2-4 (kin.ik.analytic.six_r.three_parallel).

Round trips on every branch against Pinocchio's FK of the table's URDF: every branch that exists
reaches the target to 1e-9 m / 1e-9 rad, and the original q is among the branches (modulo 2 pi).
Arms: seeded random tables of the general family (``a5 != 0``, random twists of joints 1, 4, 5;
``classic``: wrist twists +-90 deg) and of the intersecting family (``a5 = 0``), in both
conventions, with random lengths, offsets, base and tool; UR5, compared with
:class:`~kin.ik.analytic.six_r.ur_wrist.URWrist6R`, the other implementation.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from support.arm_tables import (
    TOL,
    Reference,
    assert_round_trips,
    make_table,
    wrapped_gap,
)
from support.three_parallel_arms import arm_table

import kin
from dh2urdf import DHRow, DHTable, get_robot, load_table
from kin.ik import PoseTarget
from kin.ik.analytic import registry
from kin.ik.analytic.six_r.general_6r import General6R
from kin.ik.analytic.six_r.three_parallel import NEAR_MEET, ThreeParallel6R
from kin.ik.analytic.six_r.ur_wrist import URWrist6R
from kin.ik.exceptions import StructureError, TargetError

SAMPLES = 100
PI = math.pi
ARMS = ("general_standard_0", "general_standard_1", "general_modified_0", "general_modified_1",
        "classic_standard_0", "classic_modified_0", "intersecting_modified_0", "ur5",
        "ur5_moved")  # fmt: skip


@functools.cache
def reference(name: str) -> Reference:
    return Reference(arm_table(name))


def existing(found: np.ndarray) -> np.ndarray:
    """The rows of ``found`` (B, 6) that are not NaN."""
    return found[~np.isnan(found[:, 0])]


@pytest.mark.parametrize("arm", ARMS)
def test_every_branch_reaches_the_target_and_q_is_among_them(arm):
    """Every existing branch reaches FK(q) within 1e-9 m / 1e-9 rad; q is one of the branches."""
    assert_round_trips(
        ThreeParallel6R.recognise(arm_table(arm)), reference(arm), SAMPLES, 17, f"{arm=}"
    )


@pytest.mark.parametrize("arm", ("general_standard_0", "classic_modified_0"))
def test_q_is_recovered_on_10000_random_targets(arm):
    """Batched, 10000 random q: q is among the branches to 1e-9 rad on 99.8 % of them and to
    1e-6 rad on 99.95 % (the misses are near the singular wrist, |sin t5| < 0.02, where close
    roots of the quartic lose digits), and every branch reaches its target to 1e-9."""
    table = arm_table(arm)
    solver = ThreeParallel6R.recognise(table)
    q = np.random.default_rng(23).uniform(-PI, PI, (10000, 6))
    poses = kin.batch_forward_kinematics(table, q)
    found = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    gap = np.abs(np.remainder(found - q[:, None, :] + PI, 2 * PI) - PI).max(axis=2)
    gap = np.nan_to_num(gap, nan=np.inf).min(axis=1)
    strict, loose = np.mean(gap < TOL), np.mean(gap < 1e-6)
    assert strict >= 0.998 and loose >= 0.9995, f"{arm=} {strict=} {loose=}"
    exist = ~np.isnan(found[:, :, 0])
    reached = kin.batch_forward_kinematics(table, found[exist])
    wanted = np.repeat(poses[:, None], 8, axis=1)[exist]
    assert np.abs(reached - wanted).max() < TOL, f"{arm=}"


def test_general_arms_come_in_ascending_q1_with_two_elbows_each():
    """General family: the slots hold the real roots in ascending q1, the two elbows of a slot
    share its q1 and q5 and differ in the sign of sin t3; targets with 8 branches occur."""
    table = arm_table("general_standard_1")
    solver = ThreeParallel6R.recognise(table)
    assert solver.family == "general"
    assert solver.branch_labels[:3] == (
        "arm 1 (q1 ascending), elbow up",
        "arm 1 (q1 ascending), elbow down",
        "arm 2 (q1 ascending), elbow up",
    )
    q = np.random.default_rng(4).uniform(-PI, PI, (400, 6))
    poses = kin.batch_forward_kinematics(table, q)
    found = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    assert (~np.isnan(found).any(axis=(1, 2))).sum() >= 10
    for t in found:
        slots = np.where(np.isnan(t[::2]), t[1::2], t[::2])  # (4, 6)
        q1 = slots[~np.isnan(slots[:, 0]), 0]
        assert np.all(np.diff(q1) >= 0.0), f"{q1=}"
        both = ~np.isnan(t[::2, 0]) & ~np.isnan(t[1::2, 0])
        np.testing.assert_array_equal(t[::2][both][:, [0, 4, 5]], t[1::2][both][:, [0, 4, 5]])
        t3 = t[:, 2] + solver.offsets[2]
        up, down = np.sin(t3[::2][both]), np.sin(t3[1::2][both])
        assert np.all(up >= -1e-12) and np.all(down <= 1e-12)


@pytest.mark.parametrize("arm", ("ur5", "ur5_moved"))
def test_ur5_gives_the_ur_wrist_branches(arm):
    """UR5 (a5 = 0, the intersecting family): the same 8 rows as URWrist6R under the same
    labels, slot by slot and as sets, to 1e-9 rad."""
    table = arm_table(arm)
    ours, theirs = ThreeParallel6R.recognise(table), URWrist6R.recognise(table)
    assert ours.family == "intersecting"
    assert ours.branch_labels == URWrist6R.branch_labels
    q = np.random.default_rng(9).uniform(-PI, PI, (500, 6))
    poses = kin.batch_forward_kinematics(table, q)
    a = ours.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    for compiled in (True, False):
        b = theirs.solve_batch(poses[:, :3, 3], poses[:, :3, :3], compiled=compiled)
        np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
        assert np.nanmax(np.abs(np.remainder(a - b + PI, 2 * PI) - PI)) < TOL
    for mine, other in zip(a[:50], b[:50]):
        mine, other = existing(mine), existing(other)
        assert len(mine) == len(other)
        for row in other:
            assert wrapped_gap(mine, row).min() < TOL


@pytest.mark.parametrize("arm", ARMS[::2])
def test_batch_gives_the_same_numbers_as_solve(arm):
    """solve_batch equals solve row by row (NaN where solve has NaN) to rounding."""
    table = arm_table(arm)
    solver = ThreeParallel6R.recognise(table)
    q = np.random.default_rng(3).uniform(-PI, PI, (300, 6))
    poses = kin.batch_forward_kinematics(table, q)
    poses[:20, :3, 3] *= 5.0  # some targets out of reach
    batch = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    scalar = np.array([solver.solve(T[:3, 3], T[:3, :3]) for T in poses])
    assert batch.shape == (300, 8, 6)
    np.testing.assert_array_equal(np.isnan(batch), np.isnan(scalar))
    np.testing.assert_allclose(batch, scalar, rtol=0.0, atol=1e-9, equal_nan=True)
    assert np.isnan(batch[:20]).mean() > 0.5


@pytest.mark.parametrize("arm", ("general_standard_0", "classic_modified_0", "ur5"))
def test_out_of_reach_gives_nan_rows(arm):
    """A target far beyond the reach has no branch, scalar and batched."""
    solver = ThreeParallel6R.recognise(arm_table(arm))
    assert np.isnan(solver.solve(np.array([30.0, 0.0, 0.5]), np.eye(3))).all()
    assert np.isnan(solver.solve_batch(np.array([[30.0, 0.0, 0.5]]), np.eye(3)[None])).all()


def test_full_pose_and_shapes_are_required():
    """A position target and mismatched batch shapes raise TargetError."""
    solver = ThreeParallel6R.recognise(arm_table("general_standard_0"))
    with pytest.raises(TargetError, match="needs a full pose"):
        solver.solve(np.zeros(3), None)
    with pytest.raises(TargetError, match=r"got \(2, 3\) and \(3, 3, 3\)"):
        solver.solve_batch(np.zeros((2, 3)), np.zeros((3, 3, 3)))


@pytest.mark.parametrize("arm", ("classic_standard_0", "classic_modified_0"))
def test_singular_wrist_takes_the_free_value_and_still_reaches(arm):
    """a5 != 0, wrist twists +-90 deg, t5 = 0 (axis 6 parallel to axes 2-4): q6 = free in the
    singular rows, and every branch reaches the pose."""
    ref, solver = reference(arm), ThreeParallel6R.recognise(arm_table(arm))
    q = np.array([0.4, -1.0, 1.2, -0.5, -solver.offsets[4], 0.7])  # t5 = 0
    target = ref.fk(q)
    for free in (0.7, 0.75):
        found = solver.solve(target.translation, target.rotation, free=free)
        exist = existing(found)
        singular = np.abs(np.sin(exist[:, 4] + solver.offsets[4])) < 1e-9
        assert singular.any(), f"{arm=} {free=}"
        np.testing.assert_allclose(exist[singular, 5], free, atol=1e-12)
        for branch in exist:
            assert max(ref.errors(branch, target)) < TOL, f"{arm=} {branch=}"
        batch = solver.solve_batch(target.translation[None], target.rotation[None], free=free)
        np.testing.assert_allclose(batch[0], found, atol=1e-9, equal_nan=True)


# ---------------------------------------------------------------------------------------------
# Recognition


def test_ur5_table_is_recognised_with_its_numbers():
    """The shipped UR5 table is the intersecting family with the maker's numbers."""
    solver = ThreeParallel6R.recognise(load_table(get_robot("ur5").table_path))
    assert solver.family == "intersecting" and solver.a5 == 0.0
    assert (solver.a2, solver.a3) == (-0.425, -0.39225)
    assert (solver.d1, solver.lateral, solver.d5, solver.d6) == (0.089159, 0.10915, 0.09465, 0.0823)
    assert ThreeParallel6R.name == "three_parallel" and ThreeParallel6R.dof == 6
    assert ThreeParallel6R.target_kinds == (PoseTarget,)


def general_with(row: int, **changes: float) -> DHTable:
    """general_standard_0 with a changed row (1-based)."""
    table = arm_table("general_standard_0")
    rows = list(table.rows)
    fields = {f: getattr(rows[row - 1], f) for f in ("a", "alpha", "d", "theta")}
    fields.update(changes)
    rows[row - 1] = DHRow(row, rows[row - 1].name, "revolute", fields["a"], fields["alpha"],
                          fields["d"], fields["theta"], -PI, PI, 1.0, 1.0)  # fmt: skip
    return DHTable("variant", "", "", "standard", tuple(rows))


PUMA = make_table([0, 0.4318, 0.0203, 0, 0, 0], [PI / 2, 0, -PI / 2, PI / 2, -PI / 2, 0],
                  [0, 0, 0.15005, 0.4318, 0, 0], [0] * 6, name="puma560")  # fmt: skip


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        (general_with(2, alpha=math.radians(0.1)), ["row 2 ('j2'): alpha = 0.1 deg",
                                                    "expected 0 deg"]),
        (general_with(3, alpha=PI), ["row 3 ('j3'): alpha = 180 deg, expected 0 deg"]),
        (general_with(3, a=0.0), ["row 3 ('j3'): a = 0 m, expected non-zero"]),
        (general_with(2, a=0.0), ["row 2 ('j2'): a = 0 m, expected non-zero"]),
        (general_with(1, alpha=0.0), ["row 1 ('j1'): alpha = 0 deg", "other than 0"]),
        (general_with(4, alpha=PI), ["row 4 ('j4'): alpha = 180 deg", "other than 0"]),
        (general_with(5, alpha=0.0), ["row 5 ('j5'): alpha = 0 deg", "other than 0"]),
        (general_with(5, a=1e-6), ["row 5 ('j5'): a = 1e-06 m, expected 0 or at least",
                                   "nearly meet"]),
        (PUMA, ["row 3 ('j3'): alpha = -90 deg, expected 0 deg"]),
    ],
    ids=["alpha2=0.1", "alpha3=180", "a3=0", "a2=0", "alpha1=0", "alpha4=180", "alpha5=0",
         "a5=1um", "puma560"],
)  # fmt: skip
def test_near_misses_are_refused_naming_row_and_parameter(table, expected):
    """A table without three parallel axes 2-4, with a2 or a3 zero, with infinitely many
    solutions or nearly meeting axes 5 and 6 raises StructureError naming the row and field."""
    with pytest.raises(StructureError) as info:
        ThreeParallel6R.recognise(table)
    for text in expected:
        assert text in str(info.value), str(info.value)
    assert info.value.solver == "6R three parallel axes"


def test_a5_at_the_threshold_is_solved():
    """a5 just above NEAR_MEET (|a2| + |a3|) is the general family and keeps the round trip."""
    base = arm_table("general_standard_0")
    least = NEAR_MEET * (abs(base.rows[1].a) + abs(base.rows[2].a))
    table = general_with(5, a=1.01 * least)
    solver = ThreeParallel6R.recognise(table)
    assert solver.family == "general"
    ref = Reference(table)
    for q in np.random.default_rng(6).uniform(-PI, PI, (20, 6)):
        target = ref.fk(q)
        ref.check_branches(existing(solver.solve(target.translation, target.rotation)), q,
                           target, "a5 at the threshold")  # fmt: skip


def test_modified_near_miss_names_the_modified_row():
    """In Craig's convention joint 2's twist is in row 3: the error names row 3."""
    table = arm_table("general_modified_0")
    rows = list(table.rows)
    r = rows[2]
    rows[2] = DHRow(3, "j3", "revolute", r.a, math.radians(0.1), r.d, 0.0, -PI, PI, 1.0, 1.0)
    with pytest.raises(StructureError, match=r"row 3 \('j3'\): alpha \(modified convention"):
        ThreeParallel6R.recognise(DHTable("bad", "", "", "modified", tuple(rows)))


# ---------------------------------------------------------------------------------------------
# Registry


@pytest.mark.parametrize("arm", ("general_standard_0", "general_modified_1", "classic_standard_0"))
def test_no_other_registered_structure_takes_the_general_family(arm):
    """A table with a5 != 0 is refused by every other registered 6R structure: the registry
    raises StructureError until ThreeParallel6R is registered, then it gives ThreeParallel6R."""
    table = arm_table(arm)
    # General6R (registered last) takes any 6R table: not one of the others.
    others = [
        s for s in registry.CLOSED_FORMS if s.dof == 6 and s not in (ThreeParallel6R, General6R)
    ]
    assert len(others) >= 2  # Pieper6R (with its spherical-wrist case), Reversed6R
    for structure in others:
        with pytest.raises(StructureError):
            structure.recognise(table)
    if ThreeParallel6R in registry.CLOSED_FORMS:
        assert isinstance(registry.recognise(table), ThreeParallel6R)
    else:
        with pytest.raises(StructureError):
            registry.recognise(table)
