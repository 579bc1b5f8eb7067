"""6R arms solved through their chain read from the tool (kin.ik.analytic.six_r.reversed_chain).

- :func:`reverse_table` against the plain NumPy DH product: ``FK_rev(-q reversed) = FK(q)^-1`` on
  random tables of both conventions and several joint counts, and reversing twice gives the
  table back;
- arms whose special axes are at the base (the reversal of random tables of the UR, spherical
  wrist and general Pieper families: a spherical shoulder, three parallel axes 3-5, ...): the
  registry gives them ``reversed``, every branch reaches FK(q) to 1e-9 m / 1e-9 rad against
  Pinocchio, q is among the branches, batched equals scalar, and ``ClosedFormSolver`` returns
  verified solutions;
- the shipped arms keep their forward families; a 6R table that fits no family either way goes
  to the numeric solver, and the error names the reversed reading.
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
    random_pose,
    wrapped_gap,
)
from support.pieper_arms import random_table as random_pieper_family
from support.spherical_wrist_arms import random_pieper_table
from support.ur_wrist_arms import random_ur_table

import kin
from dh2urdf import DHRow, DHTable, get_robot, load_table
from kin.ik import ClosedFormSolver, PoseTarget, get_solver
from kin.ik.analytic.registry import CLOSED_FORMS, recognise
from kin.ik.analytic.six_r.general_6r import General6R
from kin.ik.analytic.six_r.reversed_chain import Reversed6R, reverse_table
from kin.ik.exceptions import StructureError

PI = math.pi
SAMPLES = 150
#: Arms with their special axes at the base: name -> (forward table reversed, inner family).
ARMS = {
    "shoulder_standard": ("spherical_wrist", "standard"),
    "shoulder_modified": ("spherical_wrist", "modified"),
    "ur_standard": ("ur_wrist", "standard"),
    "ur_modified": ("ur_wrist", "modified"),
    "general_standard": ("pieper", "standard"),
    "general_modified": ("pieper", "modified"),
}


@functools.cache
def arm_table(name: str) -> DHTable:
    """The arm: a random forward-family table read from its tool end."""
    family, convention = ARMS[name]
    if family == "spherical_wrist":
        forward = random_pieper_table(7, convention, skew=True)
    elif family == "ur_wrist":
        forward = random_ur_table(3, convention)
    else:
        forward = random_pieper_family("general", convention, 4)
    return reverse_table(forward)


def random_table(n: int, convention: str, seed: int) -> DHTable:
    rng = np.random.default_rng(seed)
    return make_table(rng.uniform(-0.5, 0.5, n), rng.uniform(-PI, PI, n),
                      rng.uniform(-0.5, 0.5, n), rng.uniform(-PI, PI, n), convention,
                      random_pose(rng), random_pose(rng))  # fmt: skip


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("n", [3, 6, 7])
def test_reversed_table_is_the_inverse_chain(n, convention):
    """FK of the reversed table at ``-q`` read backwards is the inverse of FK(q) (NumPy DH)."""
    table = random_table(n, convention, 10 * n)
    reversed_table = reverse_table(table)
    assert reversed_table.convention != table.convention
    q = np.random.default_rng(n).uniform(-PI, PI, (200, n))
    forward = kin.batch_forward_kinematics(table, q)
    backward = kin.batch_forward_kinematics(reversed_table, -q[:, ::-1])
    np.testing.assert_allclose(backward, np.linalg.inv(forward), rtol=0.0, atol=1e-12)
    twice = reverse_table(reversed_table)
    assert twice.convention == table.convention
    for a, b in zip(twice.rows, table.rows):
        assert (a.a, a.alpha, a.d, a.theta, a.lower, a.upper) == (
            b.a, b.alpha, b.d, b.theta, b.lower, b.upper)  # fmt: skip
    np.testing.assert_allclose(
        kin.batch_forward_kinematics(twice, q), forward, rtol=0.0, atol=1e-12
    )


def test_reversed_limits_are_negated_and_swapped():
    """Joint j of the reversed table is -q of joint n + 1 - j: limits [-upper, -lower]."""
    table = load_table(get_robot("ur5").table_path)
    rows = list(table.rows)
    rows[0] = DHRow(1, rows[0].name, "revolute", rows[0].a, rows[0].alpha, rows[0].d,
                    rows[0].theta, -1.0, 2.0, 1.0, 1.0)  # fmt: skip
    reversed_table = reverse_table(DHTable("ur5", "", "", "standard", tuple(rows)))
    assert (reversed_table.rows[-1].lower, reversed_table.rows[-1].upper) == (-2.0, 1.0)
    assert reversed_table.rows[-1].name == rows[0].name


@pytest.mark.parametrize("arm", ARMS)
def test_registry_reads_the_arm_from_the_tool(arm):
    """No forward family fits the arm; read from the tool, its family does."""
    table = arm_table(arm)
    structure = recognise(table)
    assert isinstance(structure, Reversed6R)
    assert structure.inner.name == ARMS[arm][0]
    assert get_solver(kin.robot_from_table(table)).name == "closed_form:reversed"
    assert CLOSED_FORMS[-2:] == [Reversed6R, General6R]  # the general 6R form after it


@pytest.mark.parametrize("arm", ARMS)
def test_every_branch_reaches_the_target_and_q_is_among_them(arm):
    """Every existing branch reaches FK(q) within 1e-9 m / 1e-9 rad; q is one of the branches."""
    table = arm_table(arm)
    assert_round_trips(Reversed6R.recognise(table), Reference(table), SAMPLES, 21, f"{arm=}")


@pytest.mark.parametrize("arm", ["shoulder_modified", "general_standard"])
def test_batch_gives_the_same_numbers_as_solve(arm):
    """solve_batch equals solve row by row (NaN alike), targets in and out of reach."""
    table = arm_table(arm)
    structure = Reversed6R.recognise(table)
    q = np.random.default_rng(3).uniform(-PI, PI, (300, 6))
    poses = kin.batch_forward_kinematics(table, q)
    poses[:30, :3, 3] *= 6.0
    batch = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    scalar = np.array([structure.solve(T[:3, 3], T[:3, :3]) for T in poses])
    np.testing.assert_array_equal(np.isnan(batch), np.isnan(scalar))
    np.testing.assert_allclose(batch, scalar, rtol=0.0, atol=1e-9, equal_nan=True)
    with pytest.raises(kin.ik.TargetError):
        structure.solve_batch(poses[:, :3, 3], poses[:5, :3, :3])


@pytest.mark.parametrize("arm", ["shoulder_standard", "ur_modified"])
def test_closed_form_solver_returns_verified_solutions(arm):
    """Through ClosedFormSolver (Pinocchio judge): verified, within limits, q recovered."""
    table = arm_table(arm)
    solver = ClosedFormSolver(kin.robot_from_table(table))
    ref = Reference(table)
    for q in np.random.default_rng(5).uniform(-PI, PI, (40, 6)):
        target = ref.fk(q)
        result = solver.solve(PoseTarget(target.translation, target.rotation), q)
        assert result.success and result.solver == "closed_form:reversed"
        for solution in result.solutions:
            assert solution.position_error < TOL and solution.rotation_error < TOL
            assert "from the tool" in solution.branch
        assert wrapped_gap(np.array([result.best.q]), q)[0] < ref.joint_tolerance(q)


def test_shipped_arms_keep_their_forward_families():
    """UR5 and PUMA 560 are solved forward, as before."""
    for name, family in (("ur5", "ur_wrist"), ("puma560", "spherical_wrist")):
        assert recognise(load_table(get_robot(name).table_path)).name == family


def test_a_table_fitting_no_family_either_way_goes_to_the_general_6r_closed_form():
    """A random 6R table: StructureError naming the reversed reading; the registry then gives
    the general 6R closed form (it went to the numeric solver before that was registered)."""
    table = random_table(6, "standard", 99)
    with pytest.raises(StructureError) as info:
        Reversed6R.recognise(table)
    assert "read from the tool" in str(info.value)
    assert isinstance(recognise(table), General6R)
    assert get_solver(kin.robot_from_table(table)).name == "closed_form:general_6r"


def test_prismatic_and_wrong_joint_count_are_refused():
    """A prismatic joint cannot be read backwards into a DH row; 5 joints is not 6R."""
    table = load_table(get_robot("ur5").table_path)
    rows = list(table.rows)
    r = rows[2]
    rows[2] = DHRow(3, r.name, "prismatic", r.a, r.alpha, r.d, r.theta, 0.0, 1.0, 1.0, 1.0)
    with pytest.raises(StructureError, match=r"row 3 \('elbow_joint'\) is prismatic"):
        Reversed6R.recognise(DHTable("p", "", "", "standard", tuple(rows)))
    with pytest.raises(StructureError, match="5 joints"):
        Reversed6R.recognise(DHTable("five", "", "", "standard", table.rows[:5]))
