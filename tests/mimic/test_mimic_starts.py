"""kin/mimic/starts.py: the sampled poses a mimic chain's search starts from, held to Pinocchio's
own mimic model of the file (not to the table's DH product they come from)."""

from __future__ import annotations

import numpy as np
import pytest
from support.mimic_reference import _pinocchio_mimic_fk, _urdf

import kin
from kin.ik import PoseTarget
from kin.mimic.solver import MimicSolver
from kin.mimic.starts import sample_table


@pytest.mark.parametrize("multiplier", [0.5, -1.3])
def test_the_samples_poses_are_pinocchios(tmp_path, multiplier):
    """Every sample inside the limits, its tool pose Pinocchio's mimic FK of the URDF."""
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(multiplier), encoding="utf-8")
    arm = kin.load_arm(path)
    table = sample_table(arm, size=60, seed=3)
    assert table.q.shape == (60, arm.nq)
    assert np.all(table.q >= arm.lower) and np.all(table.q <= arm.upper)
    for q, position, rotation in zip(table.q, table.positions, table.rotations, strict=True):
        expected = _pinocchio_mimic_fk(path, q)
        np.testing.assert_allclose(position, expected[:3, 3], atol=1e-12)
        np.testing.assert_allclose(rotation.reshape(3, 3), expected[:3, :3], atol=1e-12)


def test_a_target_away_from_the_seed_starts_from_the_samples(tmp_path):
    """A sampled pose far from q = 0: found within the seed and the near starts, on target."""
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(0.5), encoding="utf-8")
    arm = kin.load_arm(path)
    solver = MimicSolver(arm)
    table = sample_table(arm)
    far = int(np.argmax(np.linalg.norm(table.q, axis=1)))
    goal = _pinocchio_mimic_fk(path, table.q[far])
    result = solver.solve(PoseTarget(goal[:3, 3], goal[:3, :3]), np.zeros(arm.nq))
    assert result.success and result.method in ("damped_least_squares", "seed_table")
    reached = _pinocchio_mimic_fk(path, result.solutions[0].q)
    np.testing.assert_allclose(reached[:3, 3], goal[:3, 3], atol=1e-5)
