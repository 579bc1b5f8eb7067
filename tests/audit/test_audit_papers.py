"""The audit on the papers' printed numbers finds the readings our table files document.

The sample files in ``tests/data/audit/`` hold the papers' printed numbers as stored in
``reproduction/`` (``generate_samples.py --check`` proves it); the verdicts below are those of
``docs/reproduction.md``: 000 prints DH angles and follows L2 = 28.7 cm in two columns and
28.77 cm in the other two, 001's table is standard DH, 003's Table 3 flips alpha1 and d2 against
its equations, 002's 'measured' positions are no FK of its angles, 004's 0T5 is its table.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from kin.audit import audit_samples

DATA = Path(__file__).resolve().parents[1] / "data" / "audit"


def kinds(score) -> set[tuple]:
    """The changes of a score as (kind, row)."""
    return {(c.kind, c.row) for c in score.reading.changes}


def test_sample_files_are_the_printed_numbers():
    """generate_samples.py --check: every sample file is what reproduction/'s printed data give."""
    result = subprocess.run(
        [sys.executable, str(DATA / "generate_samples.py"), "--check"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr


#: 000 column -> the L2 [cm] that docs/reproduction.md says the column follows.
HUMANOID7_L2 = {
    "dh_solution": "28.7",
    "peter_corke": "28.7",
    "roboanalyzer": "28.77",
    "uv_solution": "28.77",
}


@pytest.mark.parametrize("column", sorted(HUMANOID7_L2))
def test_humanoid7_cases_print_dh_angles_and_another_l2(column):
    """000: offsets not applied, digits truncated, L2 refitted to the column's length."""
    audit = audit_samples("humanoid7", DATA / f"humanoid7_{column}.csv")
    best = audit.best
    assert {"offsets", "truncated", "length"} == {c.kind for c in best.reading.changes}, (
        f"{column=} {best.reading.label}"
    )
    refit = next(c for c in best.reading.changes if c.kind == "length")
    assert (refit.row, refit.text) == (3, f"d3: 28.774 -> {HUMANOID7_L2[column]} cm"), column
    assert best.count >= 4, f"{column=} {best.count=}"
    # docs: "q = printed angle with Table I offsets added: gives 4 of 84 cells, all zeros"
    assert audit.as_written().count == 0
    assert audit.as_written().values_reproduced == 1, column
    # docs: "printed angles taken as radians: gives 0 of 84 cells"
    radians = next(s for s in audit.scores if kinds(s) == {("offsets", None), ("angle_unit", None)})
    assert radians.values_reproduced == 0, column


def test_humanoid7_best_reading_without_refit_is_offsets():
    """000 without refitting a length: the offsets reading still ranks first (L2 aside)."""
    audit = audit_samples("humanoid7", DATA / "humanoid7_dh_solution.csv", refit=False)
    assert ("offsets", None) in kinds(audit.best), audit.best.reading.label
    assert audit.best.max_residual_m < 1e-3  # the L2 difference, 0.074 cm at most
    assert audit.as_written().max_residual_m > 0.1


def test_ned5_table_is_standard_not_modified():
    """001: the header's modified reading misses the home; the convention change gives it."""
    printed = audit_samples(DATA / "ned5_as_printed.toml", DATA / "ned5_home.csv")
    assert [c.text for c in printed.best.reading.changes] == ["convention: modified -> standard"]
    assert printed.best.count == 1
    assert printed.as_written().count == 0
    ours = audit_samples("ned5", DATA / "ned5_home.csv")
    assert ours.best.reading.changes == () and ours.best.count == 1


def test_pickplace3_table3_flips_alpha1_and_d2():
    """003: the literal Table 3 gives case 1 only (q2 outside the range); its equations' reading
    (alpha1 = +90, d2 = -10 mm) gives case 2 and ranks first."""
    literal = audit_samples(DATA / "pickplace3_table3.toml", DATA / "pickplace3_table4.csv")
    assert kinds(literal.best) == {("twist", 1), ("d_sign", 2)}, literal.best.reading.label
    assert [c.edit for c in literal.best.reading.changes] == [
        "row 1: alpha = 90",
        "row 2: d = -10",
    ]
    assert literal.best.reproduced.tolist() == [False, True]
    assert literal.as_written().reproduced.tolist() == [True, False]
    ours = audit_samples("pickplace3", DATA / "pickplace3_table4.csv")
    assert ours.best.reading.changes == ()
    assert ours.best.reproduced.tolist() == [False, True]
    assert not ours.best.within_limits[0]  # case 1: q2 = -90 deg, range [-20, 120] deg


def test_lab5_angles_give_targets_not_measured_positions():
    """002: the printed angles give the targets; no reading gives the 'measured' positions."""
    targets = audit_samples("lab5", DATA / "lab5_table2_targets.csv")
    assert targets.best.reading.changes == () and targets.best.count == 4
    measured = audit_samples("lab5", DATA / "lab5_table2_measured.csv")
    assert max(s.count for s in measured.scores) == 0
    assert measured.as_written().max_residual_m < 0.3e-3  # 0.24 mm: rounding, not geometry


def test_scorbot_0t5_is_its_table():
    """004: the printed 0T5 (position and rotation matrix) is the table as written."""
    audit = audit_samples("scorbot", DATA / "scorbot_0t5.csv")
    assert audit.best.reading.changes == ()
    assert audit.best.count == 2 and audit.best.values_reproduced == audit.best.values == 24


def _docs_humanoid7_cells() -> list[tuple[str, str, str]]:
    """(column, verdict, reason) of each 000 cell row of docs/reproduction.md."""
    text = (DATA.parents[2] / "docs" / "reproduction.md").read_text(encoding="utf-8")
    section = text.split("## 000 Tables II-VIII")[1].split("\n## ")[0]
    cells = []
    for line in section.splitlines():
        if line.startswith("| Table ") and "(case" in line:
            parts = [p.strip() for p in line.strip("|").split("|")]
            column = parts[0].rsplit(", ", 1)[1]
            cells.append((column, parts[4].strip("*"), parts[5]))
    return cells


@pytest.mark.parametrize("column", sorted(HUMANOID7_L2))
def test_humanoid7_cell_counts_agree_with_the_reproduction_report(column):
    """000, per column: the offsets reading reproduces (rounded) exactly the cells the report
    marks reproduced; with truncation, at least those plus its 'printed truncated' cells."""
    name = {"dh_solution": "DH solution", "uv_solution": "UV solution"}.get(
        column, column.replace("_", " ").title().replace("Roboanalyzer", "RoboAnalyzer")
    )
    cells = [c for c in _docs_humanoid7_cells() if c[0] == name]
    assert len(cells) == 21, f"{column=} {len(cells)=}"
    reproduced = sum(1 for _, verdict, _ in cells if verdict == "reproduced")
    truncated = sum(1 for _, _, reason in cells if reason.startswith("printed truncated"))
    audit = audit_samples("humanoid7", DATA / f"humanoid7_{column}.csv", refit=False)
    offsets = next(s for s in audit.scores if kinds(s) == {("offsets", None)})
    both = next(s for s in audit.scores if kinds(s) == {("offsets", None), ("truncated", None)})
    assert offsets.values_reproduced == reproduced, column
    assert both.values_reproduced >= reproduced + truncated, column
