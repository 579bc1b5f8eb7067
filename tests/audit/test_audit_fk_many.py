"""The audit's many-variant FK and its batched base/tool fit agree with the one-table versions."""

from __future__ import annotations

import numpy as np

from kin import batch_forward_kinematics
from kin.audit import candidate_readings, load_audited_table
from kin.audit.fk_many import many_tool_poses
from kin.audit.se3_fit import fit_base_tool, fit_base_tool_many


def test_many_tool_poses_equal_batch_fk_per_reading():
    """Every reading of panda (modified) and scorbot (standard), both conventions among them:
    the stacked FK equals kin.batch_forward_kinematics of each variant to 1e-14 (relative)."""
    rng = np.random.default_rng(5)
    for robot in ("panda", "scorbot", "humanoid7"):
        audited = load_audited_table(robot)
        readings = candidate_readings(audited, samples=False)
        q = rng.uniform(-2.0, 2.0, size=(len(readings), 9, audited.table.dof))
        stacked = many_tool_poses([r.table for r in readings], q)
        for k, reading in enumerate(readings):
            alone = batch_forward_kinematics(reading.table, q[k])
            scale = max(1.0, float(np.abs(alone).max()))  # a length-unit reading: arms of 100 m
            assert np.abs(stacked[k] - alone).max() < 1e-14 * scale, f"{robot=} {reading.label}"


def test_batched_fit_equals_single_fit():
    """fit_base_tool_many over R tables gives each table's fit_base_tool."""
    audited = load_audited_table("ur5")
    readings = candidate_readings(audited, samples=False, pairs=False)
    rng = np.random.default_rng(6)
    q = rng.uniform(-3.0, 3.0, size=(40, 6))
    reference = batch_forward_kinematics(audited.table, q)
    poses = many_tool_poses([r.table for r in readings], np.broadcast_to(q, (len(readings), 40, 6)))
    for k, fit in enumerate(fit_base_tool_many(poses, reference)):
        single = fit_base_tool(poses[k], reference)
        assert np.allclose(fit.T_ref_base, single.T_ref_base, atol=1e-12)
        assert abs(fit.position_residual_m - single.position_residual_m) < 1e-12
