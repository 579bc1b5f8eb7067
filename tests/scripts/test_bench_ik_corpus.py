"""scripts/bench_ik_corpus.py's chains with mimic joints: timed through ``kin.load_arm`` and
judged by Pinocchio's own mimic model of the file (not by the solver's table)."""

from __future__ import annotations

import math

from support.mimic_reference import _urdf
from support.scripts_helper import load_script


def test_a_mimic_chain_is_timed_and_judged_by_pinocchios_mimic_model(tmp_path):
    """A general 6R with a mimic joint: every target solved, TRAC-IK not compared (NaN)."""
    module = load_script("bench_ik_corpus")
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(0.5))
    row = module.bench_arm(module.Arm("mimic6r.urdf", path, None, "tip"), 12, 1, 0)
    assert isinstance(row, module.Row), row
    assert (row.joints, row.targets, row.ours_ok) == (6, 12, 12)
    assert row.solver and row.ours_us > 0 and math.isnan(row.peer_us)
