"""The general 6R closed form's compiled twin (kin/_native/ik/analytic/six_r/_general6r.c) against its NumPy path.

The twin repeats the first elimination's pass (the eigenproblem, the joints, the polish, the
merge) of :class:`~kin.ik.analytic.six_r.general_6r.General6R`; the NumPy path is the reference.
On random tables of both conventions (offsets, base and tool everywhere) and the makers' tables
of ``tests/data/six_r``: every branch on target to 1e-9 by the plain DH product of
``tests/support/dh_reference.py``; on every regular pose the same branch count, and the same branches to
``SAME_TOL`` (1e-7 [rad], one branch by the merge) but where a branch is near-singular itself; a
pose the twin cannot answer goes to the NumPy path.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from support.arm_tables import wrapped_gap
from support.dh_reference import ReferenceTable, fk_frames, load_reference, rotation_angle
from support.general_arms import NEAR_SINGULAR, random_arm, sigma_min

from dh2urdf import load_table
from kin._native import twin, why_missing
from kin.ik.analytic.six_r._general_6r_chain import SAME_TOL
from kin.ik.analytic.six_r.general_6r import General6R

PI = math.pi
SIX_R = Path(__file__).parents[1] / "data" / "six_r"
TWIN = twin("_general6r")
pytestmark = pytest.mark.skipif(TWIN is None, reason=f"{why_missing('_general6r')}")


def compare(table, reference: ReferenceTable, q: np.ndarray, label: str) -> int:
    """The twin's and the NumPy path's branches of FK(q): on target; equal unless the pose is
    near-singular (its solutions are not isolated: each path gives some of a continuum).
    Returns the branches counted on the regular poses."""
    compiled = General6R.recognise(table)
    if len(compiled.formulations) != 1:
        return 0  # two merged eliminations: the NumPy path answers alone
    assert compiled._twin is not None, label
    plain = dataclasses.replace(compiled, compiled=False)
    assert plain._twin is None
    poses = fk_frames(reference, q)[:, -1]
    ours = compiled.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    numpy_path = plain.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    count = (~np.isnan(ours[..., 0])).sum(axis=1)
    theirs = (~np.isnan(numpy_path[..., 0])).sum(axis=1)
    regular = 0
    for k in range(len(q)):
        a, b = ours[k, : count[k]], numpy_path[k, : theirs[k]]
        reached = fk_frames(reference, a)[:, -1]
        assert (np.linalg.norm(reached[:, :3, 3] - poses[k, :3, 3], axis=1) < 1e-9).all(), label
        assert (rotation_angle(reached[:, :3, :3], poses[k, :3, :3]) < 1e-9).all(), label
        if sigma_min(reference, q[k]) < NEAR_SINGULAR:
            continue
        assert count[k] == theirs[k], f"{label} pose {k} q={q[k]}: {count[k]} != {theirs[k]}"
        assert count[k], f"{label} pose {k}: no branch"
        for row in a:  # the same branch, but where it is near-singular itself (ill-defined)
            gap = wrapped_gap(b, row).min()
            assert gap < SAME_TOL or sigma_min(reference, row) < NEAR_SINGULAR, (
                f"{label} pose {k}: {row=} {gap=}"
            )
        assert wrapped_gap(a, q[k]).min() < 1e-6, f"{label} pose {k}: q lost"
        regular += int(count[k])
    return regular


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_random_tables_same_branches_as_the_numpy_path(convention):
    """20 random tables x 20 poses: the twin's branches are the NumPy path's, on target."""
    found = 0
    for seed in range(20):
        table, reference = random_arm(3000 + seed, convention)
        q = np.random.default_rng(seed).uniform(-PI, PI, (20, 6))
        found += compare(table, reference, q, f"{convention} {seed=}")
    assert found > 20 * 20 * 2  # most poses have several branches


@pytest.mark.parametrize("name", ["xarm6", "jaco2_6dof", "crx10ia"])
def test_makers_tables_same_branches_as_the_numpy_path(name):
    """The makers' tables, 100 random poses and 36 of round joint angles (multiple roots)."""
    table = load_table(SIX_R / f"{name}.toml")
    reference = load_reference(SIX_R / f"{name}.toml")
    rng = np.random.default_rng(11)
    angles = np.radians([0.0, 90.0, -90.0, 180.0, 45.0, -60.0])
    q = np.concatenate((rng.uniform(-PI, PI, (100, 6)), rng.choice(angles, (36, 6))))
    assert compare(table, reference, q, name) >= 136


def test_a_pose_the_twin_cannot_answer_goes_to_the_numpy_path(monkeypatch):
    """A pose answered -1 by the twin is solved by the NumPy path: the same branches."""
    table = load_table(SIX_R / "xarm6.toml")
    reference = load_reference(SIX_R / "xarm6.toml")
    structure = General6R.recognise(table)
    q = np.random.default_rng(2).uniform(-PI, PI, (4, 6))
    poses = fk_frames(reference, q)[:, -1]
    expected = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])

    class Refusing:
        @staticmethod
        def first_pass(block, T, out, roots):
            TWIN.first_pass(block, T, out, roots)
            roots[1] = -1.0
            out[1] = 0.0  # garbage the caller must not read

    module, block = structure._twin
    object.__setattr__(structure, "_twin", (Refusing, block))
    got = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    assert np.array_equal(np.isnan(got), np.isnan(expected))
    assert np.nanmax(np.abs(got - expected)) < 1e-9


def test_bad_blocks_are_refused():
    """The twin refuses a block or pose array of the wrong size with a TypeError, not a crash."""
    with pytest.raises(TypeError, match="arm"):
        TWIN.first_pass(np.zeros(3), np.zeros((1, 4, 4)), np.zeros((1, 16, 6)), np.zeros(1))
    structure = General6R.recognise(load_table(SIX_R / "xarm6.toml"))
    block = structure._twin[1]
    with pytest.raises(TypeError, match="T"):
        TWIN.first_pass(block, np.zeros((2, 4, 4)), np.zeros((1, 16, 6)), np.zeros(1))


def test_a_singular_pencil_goes_to_the_numpy_path():
    """Jaco 2 at q5 = 180 deg (its 55 deg wrist makes axes 4 and 6 parallel: some solutions of
    the pose form curves, M(x) is singular at every x and the eigenvalues depend on the BLAS
    kernel): the twin refuses the pose (-1); the q is among the answer's 12 branches."""
    table = load_table(SIX_R / "jaco2_6dof.toml")
    reference = load_reference(SIX_R / "jaco2_6dof.toml")
    structure = General6R.recognise(table)
    q = np.radians([45.0, -60.0, -60.0, -90.0, 180.0, 90.0])
    pose = fk_frames(reference, q[None])[:, -1]
    module, block = structure._twin
    out, roots = np.empty((1, 16, 6)), np.empty(1)
    module.first_pass(block, np.ascontiguousarray(pose), out, roots)
    assert roots[0] == -1.0
    found = structure.solve(pose[0, :3, 3], pose[0, :3, :3])
    found = found[~np.isnan(found[:, 0])]
    assert len(found) == 12 and wrapped_gap(found, q).min() < 1e-6


def test_solve_one_is_the_batch_of_one():
    """solve() takes the twin's one-pose call (solve_one): the batch's numbers on 30 poses; a
    pose it cannot take (wrong sizes, a NaN) answers False (the whole path)."""
    table = load_table(SIX_R / "crx10ia.toml")
    reference = load_reference(SIX_R / "crx10ia.toml")
    structure = General6R.recognise(table)
    q = np.random.default_rng(4).uniform(-PI, PI, (30, 6))
    poses = fk_frames(reference, q)[:, -1]
    batch = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    for k, pose in enumerate(poses):
        one = structure.solve(list(pose[:3, 3]), pose[:3, :3])  # a list: converted
        assert np.array_equal(np.isnan(one), np.isnan(batch[k])), k
        assert np.nanmax(np.abs(one - batch[k])) < 1e-12, k
    module, block = structure._twin
    out = np.empty((16, 6))
    assert module.solve_one(block, np.zeros(2), np.eye(3), structure.signs, out) is False
    assert module.solve_one(block, np.full(3, np.nan), np.eye(3), structure.signs, out) is False
