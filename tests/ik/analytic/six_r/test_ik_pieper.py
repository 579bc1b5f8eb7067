"""Closed-form IK of 6R arms with a spherical wrist and any first three joints (kin.ik.analytic.six_r.pieper).

Round trips on every branch against Pinocchio's FK of the table's URDF: every branch that exists
reaches the target to 1e-9 m / 1e-9 rad, and the original q is among the branches (modulo 2 pi).
Arms: seeded random tables of each family (axes 1-2 intersecting, axes 1-2 parallel, general
with skew twists) in both conventions, with random lengths, twists, joint offsets, base and
tool, and PUMA 560 (a table of the spherical-wrist family), compared with
:class:`~kin.ik.analytic.six_r.spherical_wrist.SphericalWrist6R`, the other implementation.
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
from support.pieper_arms import arm_table
from support.spherical_wrist_arms import PUMA_A, PUMA_ALPHA, PUMA_D, random_pieper_table

import kin
from dh2urdf import DHRow, DHTable
from kin.ik import ClosedFormSolver, PoseTarget, get_solver
from kin.ik.analytic.registry import CLOSED_FORMS
from kin.ik.analytic.six_r.pieper import Pieper6R
from kin.ik.analytic.six_r.spherical_wrist import SphericalWrist6R
from kin.ik.exceptions import StructureError

SAMPLES = 200
PI = math.pi
FAMILIES = ("intersecting", "parallel", "general")
ARMS = tuple(f"{family}_{convention}_{seed}" for family in FAMILIES
             for convention in ("standard", "modified") for seed in (0, 1)) + ("puma560_moved",)  # fmt: skip


def puma_with(**changes: float) -> DHTable:
    """PUMA 560 with changed parameters, named field and 1-based row: ``puma_with(a3=0.0)``."""
    values = {"a": list(PUMA_A), "alpha": list(PUMA_ALPHA), "d": list(PUMA_D)}
    for key, value in changes.items():
        values[key.rstrip("0123456789")][int(key.lstrip("adlph")) - 1] = value
    return make_table(values["a"], values["alpha"], values["d"], [0] * 6, name="puma_variant")


@functools.cache
def reference(name: str) -> Reference:
    return Reference(arm_table(name))


def existing(found: np.ndarray) -> np.ndarray:
    """The rows of ``found`` (B, 6) that are not NaN."""
    return found[~np.isnan(found[:, 0])]


@pytest.mark.parametrize("arm", ARMS)
def test_every_branch_reaches_the_target_and_q_is_among_them(arm):
    """Every existing branch reaches FK(q) within 1e-9 m / 1e-9 rad; q is one of the branches."""
    assert_round_trips(Pieper6R.recognise(arm_table(arm)), reference(arm), SAMPLES, 17, f"{arm=}")


@pytest.mark.parametrize(
    ("arm", "family"),
    [(f"{f}_{c}_0", f) for f in FAMILIES for c in ("standard", "modified")]
    + [("puma560_moved", "intersecting")],
)
def test_the_family_is_read_from_the_table(arm, family):
    """Axes 1-2 meeting (a1 = 0), parallel (alpha1 = 0 or 180 deg) or neither: the family (of
    PUMA 560 too, read without its spherical-wrist case)."""
    solver = Pieper6R.read(arm_table(arm))
    assert solver.family == family
    assert len(solver.branch_labels) == 8 and len(set(solver.branch_labels)) == 8
    assert all(label.endswith(("wrist no flip", "wrist flip")) for label in solver.branch_labels)
    assert (
        Pieper6R.name == "pieper" and Pieper6R.dof == 6 and Pieper6R.target_kinds == (PoseTarget,)
    )


def test_general_arms_come_in_ascending_q3_and_reach_8_branches():
    """General family: the arm slots hold the real roots in ascending q3 (a slot whose wrist
    does not reach is NaN), the two wrists of a slot share its arm, and generic targets with 4
    arm solutions (8 branches) occur."""
    table = arm_table("general_standard_0")
    solver = Pieper6R.recognise(table)
    q = np.random.default_rng(4).uniform(-PI, PI, (400, 6))
    poses = kin.batch_forward_kinematics(table, q)
    found = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    full = ~np.isnan(found).any(axis=(1, 2))
    assert full.sum() >= 10, f"{full.sum()=}"
    for t in found:
        arms = np.where(np.isnan(t[::2, :3]), t[1::2, :3], t[::2, :3])  # (4, 3)
        q3 = arms[~np.isnan(arms[:, 2]), 2]
        assert np.all(np.diff(q3) > 0), f"{q3=}"
    for t in found[full]:
        np.testing.assert_array_equal(t[::2, :3], t[1::2, :3])


def test_puma_gives_the_spherical_wrist_branches_slot_by_slot():
    """PUMA 560 (a1 = 0, a2 > 0): the same 8 rows as SphericalWrist6R, under the same labels."""
    table = arm_table("puma560_moved")
    ours, theirs = Pieper6R.read(table), SphericalWrist6R.recognise(table)
    assert ours.family == "intersecting"
    assert ours.branch_labels == SphericalWrist6R.branch_labels
    q = np.random.default_rng(9).uniform(-PI, PI, (500, 6))
    poses = kin.batch_forward_kinematics(table, q)
    a = ours.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    b = theirs.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
    gap = np.abs(np.remainder(a - b + PI, 2 * PI) - PI)
    assert np.nanmax(gap) < 1e-9


@pytest.mark.parametrize("seed", [100, 101, 110, 111])
def test_spherical_wrist_tables_have_the_same_branches(seed):
    """Random tables of the spherical-wrist family (a1 != 0, skew twists; the general family
    here): the branches are those of SphericalWrist6R, in another order."""
    table = random_pieper_table(seed, "standard" if seed < 110 else "modified", skew=True)
    ours, theirs = Pieper6R.read(table), SphericalWrist6R.recognise(table)
    assert ours.family == "general"
    q = np.random.default_rng(seed).uniform(-PI, PI, (100, 6))
    poses = kin.batch_forward_kinematics(table, q)
    a = ours.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    b = theirs.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    for mine, other, qi in zip(a, b, q):
        mine, other = existing(mine), existing(other)
        assert len(mine) == len(other), f"{seed=} {qi=}"
        for row in other:
            assert wrapped_gap(mine, row).min() < 1e-8, f"{seed=} {qi=} {row=}"


@pytest.mark.parametrize("arm", ARMS[::2] + ("general_modified_1",))
def test_batch_gives_the_same_numbers_as_solve(arm):
    """solve_batch equals solve row by row (NaN where solve has NaN) to rounding."""
    table = arm_table(arm)
    solver = Pieper6R.recognise(table)
    rng = np.random.default_rng(3)
    q = rng.uniform(-PI, PI, (300, 6))
    poses = kin.batch_forward_kinematics(table, q)
    poses[:20, :3, 3] *= 5.0  # some targets out of reach
    batch = solver.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    scalar = np.array([solver.solve(T[:3, 3], T[:3, :3]) for T in poses])
    assert batch.shape == (300, 8, 6)
    np.testing.assert_array_equal(np.isnan(batch), np.isnan(scalar))
    np.testing.assert_allclose(batch, scalar, rtol=0.0, atol=1e-9, equal_nan=True)


@pytest.mark.parametrize(
    "arm", ("intersecting_standard_0", "parallel_modified_0", "general_standard_1")
)
def test_out_of_reach_gives_nan_rows(arm):
    """A target far beyond the reach has no branch, scalar and batched."""
    solver = Pieper6R.recognise(arm_table(arm))
    assert np.isnan(solver.solve(np.array([30.0, 0.0, 0.5]), np.eye(3))).all()
    assert np.isnan(solver.solve_batch(np.array([[30.0, 0.0, 0.5]]), np.eye(3)[None])).all()


@pytest.mark.parametrize("arm", ("general_modified_0", "parallel_standard_1"))
def test_singular_wrist_takes_the_free_value_and_still_reaches(arm):
    """Axes 4 and 6 aligned (t5 = 0 with 90-deg wrist twists): q4 = free, branches still reach."""
    base = arm_table(arm)
    rows = list(base.rows)
    j = 0 if base.convention == "standard" else 1
    for i in (3 + j, 4 + j):  # wrist twists +-90 deg: t5 = 0 lines up axes 4 and 6
        r = rows[i]
        rows[i] = DHRow(
            r.index, r.name, "revolute", r.a, PI / 2, r.d, r.theta, -2 * PI, 2 * PI, 1.0, 1.0
        )
    table = DHTable(
        f"{arm}_90", "", "", base.convention, tuple(rows), base.T_world_base, base.T_last_tool
    )
    ref, solver = Reference(table), Pieper6R.recognise(table)
    q = np.array([0.4, -0.5, 0.3, 0.9, -solver.offsets[4], 0.7])  # t5 = 0
    target = ref.fk(q)
    for free in (0.0, -0.3):
        found = solver.solve(target.translation, target.rotation, free=free)
        exist = existing(found)
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


@pytest.mark.parametrize(
    ("table", "family"),
    [(puma_with(alpha2=math.radians(89.9)), "intersecting"),
     (puma_with(a1=0.05, alpha1=math.radians(0.1)), "general"),
     (puma_with(a1=0.05, alpha1=math.radians(179.9)), "general")],
    ids=["alpha2=89.9", "alpha1=0.1", "alpha1=179.9"],
)  # fmt: skip
def test_near_family_twists_are_solved_as_given_not_rounded(table, family):
    """alpha2 = 89.9 deg (SphericalWrist6R needs 0) and alpha1 = 0.1 deg (the parallel family
    needs 0) are solved as given: the round trip stays at 1e-9 and q is among the branches
    (read without the spherical-wrist case, which takes the alpha1 tables)."""
    solver = Pieper6R.read(table)
    assert solver.family == family
    ref = Reference(table)
    for q in np.random.default_rng(2).uniform(-PI, PI, (20, 6)):
        target = ref.fk(q)
        exist = existing(solver.solve(target.translation, target.rotation))
        ref.check_branches(exist, q, target, f"{family=}")


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        (puma_with(a4=1e-4), ["row 4 ('j4'): a = 0.0001 m, expected 0"]),
        (puma_with(a5=-1e-3), ["row 5 ('j5'): a = -0.001 m, expected 0"]),
        (puma_with(d5=0.01), ["row 5 ('j5'): d = 0.01 m, expected 0"]),
        (puma_with(alpha4=0.0), ["row 4 ('j4'): alpha = 0 deg, expected an angle other than"]),
        (puma_with(alpha5=PI), ["row 5 ('j5'): alpha = 180 deg"]),
        (puma_with(a3=0.0, d4=0.0), ["row 3 ('j3'): a and row 4 ('j4'): d", "zero forearm"]),
        (puma_with(alpha1=0.0), ["row 1 ('j1'): a = 0 m, expected non-zero",
                                   "axes 1 and 2 are parallel"]),
        (puma_with(a2=0.0, alpha2=PI), ["row 2 ('j2'): a = 0 m", "axes 2 and 3 are one line"]),
        (puma_with(a2=0.0), ["row 2 ('j2'): a = 0 m", "axes 2 and 3 are one line"]),
        (puma_with(a2=0.0, alpha2=PI / 2), ["row 2 ('j2'): d = 0 m",
                                             "axes 1, 2 and 3 meet in one point"]),
        (puma_with(a1=0.1, alpha1=0.0), ["row 2 ('j2'): alpha = 0 deg",
                                          "axis 3 must not be parallel to them"]),
    ],
    ids=["a4=0.1mm", "a5=-1mm", "d5=1cm", "alpha4=0", "alpha5=180", "zero_forearm",
         "axes12_one_line", "axes23_antiparallel", "axes23_one_line", "spherical_shoulder",
         "three_parallel"],
)  # fmt: skip
def test_near_misses_are_refused_naming_row_and_parameter(table, expected):
    """A table without a spherical wrist or with a 3R arm of infinitely many solutions raises
    StructureError naming the row and the parameter."""
    with pytest.raises(StructureError) as info:
        Pieper6R.recognise(table)
    for text in expected:
        assert text in str(info.value), str(info.value)
    assert info.value.solver == "6R Pieper"


def test_modified_near_miss_names_the_modified_row():
    """In Craig's convention a5 (joint 5's normal) is in row 6: the error names row 6."""
    table = arm_table("general_modified_0")
    rows = list(table.rows)
    r = rows[5]
    rows[5] = DHRow(6, "j6", "revolute", 1e-4, r.alpha, r.d, r.theta, -PI, PI, 1.0, 1.0)
    bad = DHTable("bad", "", "", "modified", tuple(rows))
    with pytest.raises(StructureError, match=r"row 6 \('j6'\): a \(modified convention"):
        Pieper6R.recognise(bad)


def test_ur5_and_prismatic_are_refused():
    """A UR arm (offset wrist) or a prismatic joint is not this family."""
    from dh2urdf import get_robot, load_table

    with pytest.raises(StructureError, match=r"row 5 \('wrist_2_joint'\): d = 0.09465 m"):
        Pieper6R.recognise(load_table(get_robot("ur5").table_path))
    rows = list(arm_table("general_standard_0").rows)
    r = rows[1]
    rows[1] = DHRow(2, r.name, "prismatic", r.a, r.alpha, r.d, r.theta, 0.0, 1.0, 1.0, 1.0)
    with pytest.raises(StructureError, match=r"row 2 \('j2'\) is prismatic"):
        Pieper6R.recognise(DHTable("p", "", "", "standard", tuple(rows)))


# ---------------------------------------------------------------------------------------------
# Registry and solver


def test_the_spherical_wrist_is_the_family_s_first_case():
    """Pieper6R is registered once and gives PUMA-like arms (axes 2, 3 parallel) its
    spherical-wrist case before its general equations (answers keep the name spherical_wrist)."""
    assert Pieper6R in CLOSED_FORMS and SphericalWrist6R not in CLOSED_FORMS
    assert Pieper6R.cases == (SphericalWrist6R,)
    structure = Pieper6R.recognise(arm_table("puma560_moved"))
    assert type(structure) is SphericalWrist6R and structure.family == "parallel23"
    assert structure.name == "spherical_wrist"


@pytest.mark.parametrize(
    ("arm", "name"),
    [("intersecting_standard_0", "pieper"), ("parallel_modified_1", "pieper"),
     ("general_standard_1", "pieper"), ("general_modified_0", "pieper"),
     ("puma560_moved", "spherical_wrist")],
)  # fmt: skip
def test_dispatch_picks_pieper_for_its_tables(arm, name):
    """get_solver gives the closed form closed_form:pieper; PUMA keeps closed_form:spherical_wrist."""
    solver = get_solver(reference(arm).robot)
    assert isinstance(solver, ClosedFormSolver), f"{arm=}"
    assert solver.name == f"closed_form:{name}", f"{arm=}"


@pytest.mark.parametrize("arm", ("parallel_standard_0", "general_modified_1"))
def test_closed_form_solver_returns_verified_solutions(arm):
    """ClosedFormSolver.solve on a Pieper arm: success, every solution on target within
    1e-9 m / 1e-9 rad by Pinocchio, one per existing branch (limits +-2 pi), q among them."""
    ref = reference(arm)
    solver = ClosedFormSolver(ref.robot)
    structure = Pieper6R.recognise(arm_table(arm))
    for q in np.random.default_rng(8).uniform(-PI, PI, (15, 6)):
        target = ref.fk(q)
        result = solver.solve(PoseTarget(target.translation, target.rotation), seed=np.zeros(6))
        assert result.success and result.solver == "closed_form:pieper", f"{arm=} {result.message=}"
        branches = existing(structure.solve(target.translation, target.rotation))
        assert len(result.solutions) == len(branches), f"{arm=} {q=}"
        for solution in result.solutions:
            assert solution.position_error < TOL and solution.rotation_error < TOL
            assert solution.branch in structure.branch_labels
            assert max(ref.errors(solution.q, target)) < TOL
        assert wrapped_gap(np.array([s.q for s in result.solutions]), q).min() < 1e-8


def test_a_puma_with_an_89_9_deg_alpha2_goes_to_pieper():
    """alpha2 = 89.9 deg: SphericalWrist6R refuses it (it needs 0), the registry gives Pieper6R."""
    table = puma_with(alpha2=math.radians(89.9))
    with pytest.raises(StructureError, match=r"row 2 \('j2'\): alpha = 89.9 deg"):
        SphericalWrist6R.recognise(table)
    solver = get_solver(kin.robot_from_table(table))
    assert isinstance(solver, ClosedFormSolver) and solver.name == "closed_form:pieper"
