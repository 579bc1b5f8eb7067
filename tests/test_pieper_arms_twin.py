"""The compiled twin of the Pieper family's intersecting and parallel cases (``_pieper_arms.c``).

Against the family's NumPy algorithm (``compiled=False``), on seeded random tables of both
families in both conventions (random lengths, twists, offsets, base and tool; targets the FK of
random q, a tenth moved out of reach):

- ``solve``: the same 8 branches to 1e-10 rad, NaN rows alike (the twin's libm and NumPy's
  differ in the last bits; near a singular wrist of the random skew twists a few targets in 300
  grow that to 2.4e-12 rad; most agree within 1e-13);
- ``solve_batch``: the twin's ``solve`` of each target, and the NumPy batch to 1e-9 rad;
- :class:`ClosedFormSolver`'s compiled path (the twin's verify, the table's DH product as the
  judge) returns what its Python path (Pinocchio as the judge) returns, with narrow limits too.

Skipped when the twin is not built (no C compiler at install).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from arm_tables import assert_layout_matches
from test_ik_pieper import random_table
from test_six_r_twins import assert_same_result, narrow_limits, targets

import kin
from kin.ik import ClosedFormSolver, PoseTarget
from kin.ik.analytic.six_r import pieper
from kin.ik.analytic.six_r.pieper import Pieper6R

PI = math.pi
TWIN = pieper._ARMS_TWIN
pytestmark = pytest.mark.skipif(TWIN is None, reason="the _pieper_arms twin is not built")
ARMS = [(family, convention, seed) for family in ("intersecting", "parallel")
        for convention in ("standard", "modified") for seed in (0, 1)]  # fmt: skip


def structure(arm: tuple[str, str, int]):
    table = random_table(*arm)
    found = Pieper6R.recognise(table)
    assert found.family == arm[0] and found.compiled_twin is TWIN, f"{arm=}"
    return table, found


@pytest.mark.parametrize("arm", ARMS)
def test_twin_solve_equals_numpy(arm):
    """The twin's branches are the NumPy algorithm's, target by target (1e-10 rad, NaN alike)."""
    table, found = structure(arm)
    reached = 0
    for T in targets(table, 300, 5):
        numpy = found.solve(T[:3, 3], T[:3, :3], compiled=False)
        twin = found.solve(T[:3, 3], T[:3, :3])
        np.testing.assert_array_equal(np.isnan(twin), np.isnan(numpy), err_msg=f"{arm=}")
        np.testing.assert_allclose(twin, numpy, rtol=0.0, atol=1e-10, equal_nan=True)
        reached += int(not np.isnan(twin[:, 0]).all())
    assert 200 <= reached < 300, f"{arm=} {reached=}"


@pytest.mark.parametrize("arm", ARMS)
def test_twin_batch_equals_numpy_batch(arm):
    """The twin's solve_batch is its solve target by target, and the NumPy batch to 1e-9 rad."""
    table, found = structure(arm)
    poses = targets(table, 1000, 6)
    p, r = poses[:, :3, 3], poses[:, :3, :3]
    twin, numpy = found.solve_batch(p, r), found.solve_batch(p, r, compiled=False)
    one = np.array([found.solve(p[k], r[k]) for k in range(0, 1000, 7)])
    np.testing.assert_array_equal(twin[::7], one)
    np.testing.assert_array_equal(np.isnan(twin), np.isnan(numpy))
    np.testing.assert_allclose(twin, numpy, rtol=0.0, atol=1e-9, equal_nan=True)
    assert np.isnan(twin[:100]).mean() > 0.5 and not np.isnan(twin[100:, 0]).all()


@pytest.mark.parametrize("arm", ARMS[::3])
@pytest.mark.parametrize("narrow", [False, True])
def test_compiled_solver_equals_python_solver(arm, narrow):
    """ClosedFormSolver's compiled path returns what its Python path (Pinocchio judge) returns.

    Narrow limits force the ``2 pi`` copies and rejections; seeds random, or none.
    """
    table, _ = structure(arm)
    rng = np.random.default_rng(17)
    robot = kin.robot_from_table(narrow_limits(table, rng) if narrow else table)
    solvers = ClosedFormSolver(robot), ClosedFormSolver(robot, compiled=False)
    assert solvers[0]._twin is not None and solvers[1]._twin is None
    rejected = 0
    for k, T in enumerate(targets(robot.table, 60, 7)):
        seeds = (None, rng.uniform(-2 * PI, 2 * PI, 6))
        ours, theirs = (s.solve(PoseTarget(T[:3, 3], T[:3, :3]), seeds[k % 2]) for s in solvers)
        assert_same_result(ours, theirs, f"{arm=} {narrow=} {k=}")
        rejected += len(ours.rejected)
    assert rejected > 0 or not narrow, "the narrow limits rejected no branch"


def test_layout_matches_the_python_fields():
    """The twin's LAYOUT is the fields Pieper6R packs, in order and size."""
    _, found = structure(ARMS[0])
    assert_layout_matches(found, TWIN)


def test_general_family_stays_in_numpy():
    """A general-family arm has no twin (its quartic is solved in NumPy)."""
    found = Pieper6R.recognise(random_table("general", "standard", 0))
    assert found.family == "general" and found.compiled_twin is not TWIN
    with pytest.raises(RuntimeError, match="not built"):
        found.c_params
