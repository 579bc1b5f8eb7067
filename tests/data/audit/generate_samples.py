"""Write the audit's sample files of the papers from the printed numbers stored in reproduction/.

Run from the repository root: ``python tests/data/audit/generate_samples.py [--check]``. Every
number comes from the papers' printed tables as ``reproduction/*.py`` stores them (as text, with
its printed decimals), never from our FK. ``--check`` exits 1 when a file differs;
``tests/test_audit_papers.py`` runs the check.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[2]))

from reproduction import humanoid7_fk, ik_papers, pickplace3_fk, scorbot_fk  # noqa: E402
from reproduction.ned5_fk import _HOME as NED5_HOME  # noqa: E402
from reproduction.printed import fmt  # noqa: E402


def _q_header(n: int) -> str:
    return ",".join(f"q{i}" for i in range(1, n + 1))


def _text(value: float) -> str:
    return f"{value:g}"


def humanoid7_files() -> dict[str, str]:
    """Paper 000 Tables II-VIII: one file per column; joint values are the printed DH angles."""
    out = {}
    for column, name in enumerate(humanoid7_fk._COLUMNS):
        lines = [
            f"# humanoid7, paper 000 Tables II-VIII, column '{name}': printed case angles [deg]",
            "# (the paper prints DH angles, offsets included) and tool position [cm]",
            f"label,{_q_header(7)},x,y,z",
        ]
        for case, ((table, angles), cells) in enumerate(
            zip(humanoid7_fk._CASES, humanoid7_fk._PRINTED, strict=True), start=1
        ):
            xyz = ",".join(cells[axis][column] for axis in range(3))
            q = ",".join(_text(a) for a in angles)
            lines.append(f"Table {table} case {case},{q},{xyz}")
        slug = name.lower().replace(" ", "_")
        out[f"humanoid7_{slug}.csv"] = "\n".join(lines) + "\n"
    return out


def ned5_files() -> dict[str, str]:
    """Paper 001: the home pose (43.8, 0, 1) cm at q = 0."""
    lines = [
        "# ned5, paper 001: home pose, text and Fig. 10 [cm] at q = 0 [deg]",
        f"label,{_q_header(5)},x,y,z",
        "home,0,0,0,0,0," + ",".join(NED5_HOME),
    ]
    return {"ned5_home.csv": "\n".join(lines) + "\n"}


def pickplace3_files() -> dict[str, str]:
    """Paper 003 Table 4, Theoretical column: case 1 (q as printed) and case 2."""
    lines = [
        "# pickplace3, paper 003 Table 4 (Theoretical): printed q [deg], tool position [mm]",
        "# case 1 prints q2 = -90 deg, outside the paper's own range [-20, 120] deg",
        f"label,{_q_header(3)},x,y,z",
        "case 1,"
        + ",".join(_text(v) for v in pickplace3_fk._PRINTED_Q1)
        + ","
        + ",".join(pickplace3_fk._CASE1),
        "case 2,"
        + ",".join(_text(v) for v in pickplace3_fk._Q2)
        + ","
        + ",".join(pickplace3_fk._CASE2),
    ]
    return {"pickplace3_table4.csv": "\n".join(lines) + "\n"}


def lab5_files() -> dict[str, str]:
    """Paper 002 Table 2: printed angles with the targets, and with the 'measured' positions."""
    out = {}
    for slug, what, pick in (
        ("targets", "target position", 0),
        ("measured", "'End-Effector Position Measured'", 2),
    ):
        lines = [
            f"# lab5, paper 002 Table 2: printed joint angles [deg] and {what} [mm]",
            f"label,{_q_header(5)},x,y,z",
        ]
        for case, row in enumerate(ik_papers._T2_CASES, start=1):
            q = ",".join(f"{v:.4f}" if v != int(v) else _text(v) for v in row[1])
            xyz = ",".join(f"{v:.4f}" if pick else _text(v) for v in row[pick])
            lines.append(f"case {case},{q},{xyz}")
        out[f"lab5_table2_{slug}.csv"] = "\n".join(lines) + "\n"
    return out


def scorbot_files() -> dict[str, str]:
    """Paper 004: its printed symbolic 0T5 evaluated at q = 0 (home) and at one other q."""
    lines = [
        "# scorbot, paper 004 section III: the printed 0T5 evaluated [mm, deg]; rotation rows",
        f"label,{_q_header(5)},x,y,z," + ",".join(f"r{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3)),
    ]
    for label, q, places in (
        ("home", (0.0,) * 5, 0),
        ("0T5 at q check", scorbot_fk._Q_CHECK, 4),
    ):
        matrix = scorbot_fk.paper_0t5(q)
        values = [*matrix[:3, 3], *matrix[:3, :3].reshape(-1)]
        lines.append(
            f"{label},{','.join(_text(v) for v in q)},{','.join(fmt(v, places) for v in values)}"
        )
    return {"scorbot_0t5.csv": "\n".join(lines) + "\n"}


def sample_files() -> dict[str, str]:
    """File name -> text of every generated sample file."""
    out: dict[str, str] = {}
    for part in (humanoid7_files, ned5_files, pickplace3_files, lab5_files, scorbot_files):
        out.update(part())
    return out


def main(argv: list[str] | None = None) -> int:
    """Write the files, or with ``--check`` return 1 when one differs from what is written."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 when a file is stale")
    args = parser.parse_args(argv)
    stale = []
    for name, text in sample_files().items():
        path = HERE / name
        if args.check:
            if not path.exists() or path.read_text(encoding="utf-8") != text:
                stale.append(name)
        else:
            path.write_text(text, encoding="utf-8")
    for name in stale:
        print(f"stale: {HERE / name}", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    raise SystemExit(main())
