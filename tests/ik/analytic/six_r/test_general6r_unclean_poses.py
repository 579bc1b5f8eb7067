"""The general 6R poses that the compiled first pass leaves unclean are solved again in the twin.

A pose whose first pass has fewer distinct branches than real roots, or an odd number, is asked
of the fallback eliminations and of every cut at nearby poses, all in the twin
(``kin/ik/analytic/six_r/_general_6r_compiled.py``); the NumPy path (careful passes, nudges in
NumPy) is the reference: the same branch count and the same branches (to ``SAME_TOL``), every
branch on target by the plain DH product of ``tests/support/dh_reference.py`` or the robot's FK; no
random pose of ssik's PiPER chain (about 1.5 % unclean) is left to the NumPy path.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from support.arm_tables import wrapped_gap
from support.dh_reference import fk_frames, load_reference, rotation_angle
from support.general_arms import NEAR_SINGULAR, sigma_min

from dh2urdf import load_table
from kin._native import twin, why_missing
from kin.ik.analytic.six_r import _general_6r_compiled as compiled
from kin.ik.analytic.six_r._general_6r_chain import SAME_TOL
from kin.ik.analytic.six_r.general_6r import General6R

PI = math.pi
SIX_R = Path(__file__).parents[3] / "data" / "six_r"
pytestmark = pytest.mark.skipif(twin("_general6r") is None, reason=f"{why_missing('_general6r')}")


def counted_numpy_path(monkeypatch) -> list[int]:
    """Patch General6R._numpy_path to count the poses it is given (a list of one count)."""
    count = [0]
    original = General6R._numpy_path

    def counting(self, T, finite):
        count[0] += T.shape[0]
        return original(self, T, finite)

    monkeypatch.setattr(General6R, "_numpy_path", counting)
    return count


def unclean_first_pass(structure: General6R, poses: np.ndarray) -> np.ndarray:
    """The poses (indices) that the twin's first pass answers but leaves unclean (-2 included:
    unclean at a multiple root)."""
    module, block = structure._twin
    n = poses.shape[0]
    out, roots = np.empty((n, 16, 6)), np.empty(n)
    module.first_pass(block, np.ascontiguousarray(poses), out, roots)
    return np.nonzero((compiled.unclean(out, roots) & (roots >= 0.0)) | (roots == -2.0))[0]


def assert_same_branches(
    ours: np.ndarray, reference: np.ndarray, label: str, more: bool = False
) -> None:
    """Equal branch counts per pose, each of ours within SAME_TOL of one of the reference's.

    ``more``: ours may have more branches (all on target, checked by the caller), but every
    branch of the reference's is among them.
    """
    count = (~np.isnan(ours[..., 0])).sum(axis=1)
    theirs = (~np.isnan(reference[..., 0])).sum(axis=1)
    if more:
        assert (count >= theirs).all(), f"{label}: {count=} {theirs=}"
        ours, reference, count, theirs = reference, ours, theirs, count  # theirs among ours
    else:
        np.testing.assert_array_equal(count, theirs, err_msg=label)
    for k in np.nonzero(count)[0]:
        gaps = [wrapped_gap(reference[k, : theirs[k]], row).min() for row in ours[k, : count[k]]]
        assert max(gaps) < SAME_TOL, f"{label} pose {k}: {gaps=}"


def test_round_poses_of_the_makers_arms_are_the_numpy_paths(monkeypatch):
    """CRX-10iA and xArm6 at round joint angles (multiple roots): the unclean first passes end
    with the NumPy path's branches, on target (but where the pose is near-singular: its
    solutions are not isolated, each path gives some of a continuum)."""
    rng = np.random.default_rng(3)
    angles = np.radians([0.0, 90.0, -90.0, 180.0, 45.0, -60.0])
    checked = 0
    for name in ("crx10ia", "xarm6"):
        table = load_table(SIX_R / f"{name}.toml")
        reference = load_reference(SIX_R / f"{name}.toml")
        structure = General6R.recognise(table)
        plain = dataclasses.replace(structure, compiled=False)
        q = rng.choice(angles, (60, 6))
        poses = fk_frames(reference, q)[:, -1]
        unclean = unclean_first_pass(structure, poses)
        ours = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
        expected = plain.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
        regular = np.array(
            [k for k in unclean if sigma_min(reference, q[k]) >= NEAR_SINGULAR], dtype=int
        )
        for k in regular:
            rows = ours[k][~np.isnan(ours[k, :, 0])]
            reached = fk_frames(reference, rows)[:, -1]
            assert (np.linalg.norm(reached[:, :3, 3] - poses[k, :3, 3], axis=1) < 1e-9).all()
            assert (rotation_angle(reached[:, :3, :3], poses[k, :3, :3]) < 1e-9).all()
            assert wrapped_gap(rows, q[k]).min() < 1e-6, f"{name} pose {k}: q lost"
        assert_same_branches(ours[regular], expected[regular], name)
        checked += regular.size
    assert checked >= 10


@pytest.mark.peer
def test_no_random_pose_of_ssiks_piper_leaves_the_twin(monkeypatch, tmp_path):
    """ssik's PiPER chain, 1000 poses inside the limits: about 10 unclean first passes, all
    solved in the twin, every branch of the NumPy path's among theirs (at one pose, two more:
    the first pass's own, which the NumPy path misses), each on target by the robot's FK."""
    pytest.importorskip("ssik")
    sys.path.insert(0, str(Path(__file__).resolve().parents[4] / "scripts"))
    from ssik_chains import write_ssik_arm

    from kin import batch_forward_kinematics, load_robot
    from kin.ik import PoseTarget
    from kin.ik.solver_table import vectorized_solver

    robot = load_robot(write_ssik_arm("agilex.piper_ik", tmp_path)[0])
    structure = vectorized_solver(robot, PoseTarget).structure
    assert isinstance(structure, General6R) and structure._twin is not None
    q = np.random.default_rng(0).uniform(robot.lower, robot.upper, (1000, 6))
    poses = batch_forward_kinematics(robot.table, q)
    unclean = unclean_first_pass(structure, poses)
    assert unclean.size >= 5
    count = counted_numpy_path(monkeypatch)
    ours = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    assert count[0] == 0
    monkeypatch.undo()
    plain = dataclasses.replace(structure, compiled=False)
    expected = plain.solve_batch(poses[unclean, :3, 3], poses[unclean, :3, :3])
    assert_same_branches(ours[unclean], expected, "piper", more=True)
    rows = ours[unclean][~np.isnan(ours[unclean, :, 0])]
    which = np.repeat(unclean, (~np.isnan(ours[unclean, :, 0])).sum(axis=1))
    reached = batch_forward_kinematics(robot.table, rows)
    assert np.abs(reached[:, :3, 3] - poses[which, :3, 3]).max() < 1e-9
    assert rotation_angle(reached[:, :3, :3], poses[which, :3, :3]).max() < 1e-9
