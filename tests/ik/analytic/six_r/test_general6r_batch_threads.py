"""The general 6R closed form's batch in threads: from PARALLEL_ROWS poses the compiled first
pass is cut into row blocks that the processors' threads take; each pose's branches must be
those of one unthreaded call, and on target by the plain DH product of tests/support/dh_reference.py."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle

from dh2urdf import load_table
from kin._native import twin, why_missing
from kin.ik.analytic import twin_support
from kin.ik.analytic.six_r import general_6r
from kin.ik.analytic.six_r.general_6r import General6R

SIX_R = Path(__file__).parents[3] / "data" / "six_r"
pytestmark = pytest.mark.skipif(twin("_general6r") is None, reason=f"{why_missing('_general6r')}")


def test_threaded_blocks_give_the_one_call_answers(monkeypatch):
    """600 xArm6 poses on two threads: the same branches, bit for bit, as one call."""
    path = SIX_R / "xarm6.toml"
    table, reference = load_table(path), load_reference(path)
    structure = General6R.recognise(table)
    assert structure._twin is not None
    module, block = structure._twin
    rng = np.random.default_rng(11)
    q = rng.uniform(-np.pi, np.pi, size=(600, 6))
    poses = fk_frames(reference, q)[:, -1]
    K = np.ascontiguousarray(poses)
    alone_out, alone_roots = np.empty((600, 16, 6)), np.empty(600)
    module.first_pass(block, K, alone_out, alone_roots)
    monkeypatch.setattr(twin_support, "batch_threads", lambda: 2)
    out, roots = np.empty((600, 16, 6)), np.empty(600)
    general_6r._in_threads(module.first_pass, block, K, out, roots)
    np.testing.assert_array_equal(roots, alone_roots)
    np.testing.assert_array_equal(out, alone_out)
    answers = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    found = 0
    for k in range(600):
        rows = answers[k][~np.isnan(answers[k, :, 0])]
        reached = fk_frames(reference, rows)[:, -1]
        assert (np.linalg.norm(reached[:, :3, 3] - poses[k, :3, 3], axis=1) < 1e-9).all()
        assert (rotation_angle(reached[:, :3, :3], poses[k, :3, :3]) < 1e-9).all()
        gap = np.abs(np.angle(np.exp(1j * (rows - q[k])))).max(axis=1)
        found += bool((gap < 1e-6).any())
    assert found == 600  # the joints that made each pose are among its branches


def test_merging_a_few_poses_again_leaves_the_others_and_merges_as_the_whole():
    """distinct_again of 3 of 40 poses: their branches are those of merging the whole batch
    (near copies dropped, ordered by joint 1: checked by hand below); the rest are untouched."""
    from kin.ik.analytic.six_r._general_6r_chain import SAME_TOL, distinct, distinct_again

    rng = np.random.default_rng(5)
    pose = rng.integers(0, 40, size=400)
    u = rng.uniform(-np.pi, np.pi, size=(400, 6))
    copies = rng.integers(0, 400, size=150)  # near copies (modulo 2 pi) of some rows
    pose = np.concatenate((pose, pose[copies]))
    u = np.concatenate((u, u[copies] + 0.1 * SAME_TOL + 2 * np.pi * rng.integers(-1, 2, (150, 6))))
    u = np.remainder(u + np.pi, 2 * np.pi) - np.pi
    which = np.array([3, 17, 31])
    out = np.full((40, 16, 6), 7.0)
    distinct_again(out, pose, u, which)
    np.testing.assert_array_equal(out[which], distinct(40, pose, u)[which])
    assert (np.delete(out, which, axis=0) == 7.0).all()
    for k in which.tolist():
        mine = u[pose == k]
        unique = [
            r
            for i, r in enumerate(mine)
            if not any(np.abs(np.angle(np.exp(1j * (r - s)))).max() <= SAME_TOL for s in mine[:i])
        ]
        expected = sorted(unique, key=lambda r: r[0])[:16]
        got = out[k][~np.isnan(out[k, :, 0])]
        np.testing.assert_allclose(got, np.array(expected), atol=0, rtol=0)
