"""The audit's tolerance counts the rounding of the printed joint values, not only that of the
printed position (issue: joint values to 6 decimals of degrees move the tool by ~1e-6 mm)."""

from __future__ import annotations

import numpy as np
from support.synthetic_tables import ROWS, table_toml

from dh2urdf import load_table
from kin import batch_forward_kinematics
from kin.audit import audit_samples
from kin.audit.report import sample_audit_text


def _case(tmp_path, q_places: int, xyz_places: int):
    """8 samples of the synthetic 7R table (cm, deg): the tool of the exact q, the q and the
    position each printed with their own number of decimals."""
    table = tmp_path / "table.toml"
    table.write_text(table_toml(ROWS), encoding="utf-8")
    q_deg = np.random.default_rng(3).uniform(-150, 150, size=(8, len(ROWS)))
    poses = batch_forward_kinematics(load_table(table), np.radians(q_deg))
    header = [f"q{i}" for i in range(1, len(ROWS) + 1)] + ["x", "y", "z"]
    lines = [",".join(header)]
    for q, pose in zip(q_deg, poses):
        cells = [f"{v:.{q_places}f}" for v in q] + [
            f"{v:.{xyz_places}f}" for v in pose[:3, 3] * 100
        ]
        lines.append(",".join(cells))
    samples = tmp_path / "samples.csv"
    samples.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return table, samples


def test_joint_values_to_six_decimals_reproduce_positions_to_seven(tmp_path):
    """q to 1e-6 deg, positions to 1e-7 cm: the table as written reproduces 8/8 (the half unit
    of the position alone, 5e-8 cm, is below what the q rounding moves the tool)."""
    table, samples = _case(tmp_path, q_places=6, xyz_places=7)
    audit = audit_samples(table, samples, pairs=False, refit=False)
    best = audit.best
    assert not best.reading.changes and best.count == 8
    slack = best.joint_slack[:, :3]
    assert slack.max() > 5e-8  # the joint rounding is what matters here
    assert slack.max() < 1e-4  # and stays small: a first-order bound, not a loophole
    assert best.max_residual_m < 1e-7
    text = sample_audit_text(audit)
    assert "plus the rounding of the printed joint values" in text


def test_without_the_joint_term_it_would_fail(tmp_path):
    """The same samples judged on the position's half unit alone reproduce fewer than 8: the
    test above cannot pass without the joint term."""
    table, samples = _case(tmp_path, q_places=6, xyz_places=7)
    audit = audit_samples(table, samples, pairs=False, refit=False)
    best = audit.best
    values = audit.samples.values[:, :3]
    unit = 10.0 ** (-audit.samples.decimals[:, :3].astype(float))
    residual = np.abs(values - np.round(values, 7))  # printed values are exact at 7 places
    assert residual.max() < 1e-12
    computed_error = best.position_residual_m  # [m], of the whole position
    assert (computed_error / 0.01 > unit.min() / 2).any()
