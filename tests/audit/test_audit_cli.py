"""The audit command: JSON and text reports, --check, and one-line errors for bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from kin.commands.audit import main

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data" / "audit"
SCRIPT = ROOT / "scripts" / "audit_dh.py"
HOME = str(DATA / "ned5_home.csv")

#: name -> (sample file text for ned5 (5 joints), what the error line must say).
BAD_SAMPLES = {
    "columns": (
        "q1,q2,q3,q4,q5,x,y,z\n0,0,0,0,0,43.8,0,1\n0,0,0,0,0,43.8,0\n",
        "line 3: expected 8 comma-separated values",
    ),
    "empty": ("", "empty sample file"),
    "comments_only": ("# nothing printed\n\n", "empty sample file"),
    "header_only": ("q1,q2,q3,q4,q5,x,y,z\n", "line 1: no samples after the header"),
    "not_a_number": (
        "# home\nlabel,q1,q2,q3,q4,q5,x,y,z\nhome,0,0,0,zero,0,43.8,0,1\n",
        "line 3: column 'q4': not a finite number: 'zero'",
    ),
    "infinite": ("q1,q2,q3,q4,q5,x,y,z\n0,0,0,0,0,43.8,inf,1\n", "column 'y': not a finite"),
    "joint_count": ("q1,q2,q3,x,y,z\n0,0,0,1,2,3\n", "line 1: the header names joint columns"),
    "unknown_column": ("q1,q2,q3,q4,q5,x,y,z,w\n0,0,0,0,0,1,1,1,1\n", "unknown: w"),
    "missing_z": ("q1,q2,q3,q4,q5,x,y\n0,0,0,0,0,1,1\n", "missing: z"),
    "rpy_and_matrix": (
        "q1,q2,q3,q4,q5,x,y,z,roll,r11\n0,0,0,0,0,1,1,1,1,1\n",
        "roll, pitch, yaw or as r11..r33",
    ),
}


@pytest.mark.parametrize("name", sorted(BAD_SAMPLES))
def test_bad_sample_file_is_one_line_naming_file_and_line(tmp_path, capsys, name):
    """Exit 2 and exactly one stderr line naming the file (and the line where there is one)."""
    text, expected = BAD_SAMPLES[name]
    path = tmp_path / f"{name}.csv"
    path.write_text(text, encoding="utf-8")
    assert main(["ned5", "--samples", str(path)]) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1, f"{name=} {captured.err!r}"
    assert lines[0].startswith(f"dh2urdf audit: error: {path}"), lines[0]
    assert expected in lines[0], f"{name=} {lines[0]!r}"
    assert captured.out == ""


def test_bad_input_through_the_script_has_no_traceback(tmp_path):
    """The script in a fresh interpreter: exit 2, one stderr line, no traceback."""
    path = tmp_path / "bad.csv"
    path.write_text("q1,q2,q3,q4,q5,x,y,z\n0,0,0,0,0,1,2\n", encoding="utf-8")
    result = subprocess.run(
        [sys.executable, str(SCRIPT), "ned5", "--samples", str(path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 2
    assert result.stderr.splitlines() == [
        f"audit_dh.py: error: {path} line 2: expected 8 comma-separated values "
        "(q1, q2, q3, q4, q5, x, y, z), got 7"
    ]


@pytest.mark.parametrize(
    ("urdf_text", "frame", "expected"),
    [
        (None, "tool9", "no frame 'tool9'; available frames: base_link"),
        ("<robot", "tool0", "not valid XML"),
        ("<model/>", "tool0", "not a URDF: the root element is <model>"),
    ],
)
def test_bad_urdf_is_one_line(tmp_path, capfd, urdf_text, frame, expected):
    """A URDF without the frame, or not a URDF: exit 2, one line naming the frame or file."""
    from dh2urdf import get_robot

    path = get_robot("ur5").urdf_path
    if urdf_text is not None:
        path = tmp_path / "bad.urdf"
        path.write_text(urdf_text, encoding="utf-8")
    assert main(["ur5", "--urdf", str(path), "--frame", frame]) == 2
    lines = capfd.readouterr().err.splitlines()
    assert len(lines) == 1 and expected in lines[0], lines


@pytest.mark.parametrize(
    "argv",
    [
        ["ur5", "--urdf", "x.urdf"],
        ["ur5", "--frame", "tool0", "--samples", HOME],
        ["ur5", "--samples", HOME, "--urdf", "x.urdf", "--frame", "tool0"],
        ["ur5"],
        ["nosuchrobot", "--samples", HOME],
        ["ur5", "--urdf", "/no/such/file.urdf", "--frame", "tool0"],
    ],
)
def test_bad_arguments_are_one_line(capsys, argv):
    """Missing or conflicting options, unknown robot, missing file: exit 2, one line."""
    try:
        code = main(argv)
    except SystemExit as stop:  # argparse errors exit, the others return
        code = stop.code
    assert code == 2, argv
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and "error:" in lines[0], lines


def test_json_readings_best_first(capsys):
    """--json: readings best first; changes empty for the table as written; SI residuals."""
    table = str(DATA / "ned5_as_printed.toml")
    assert main([table, "--samples", HOME, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    readings = record["readings"]
    assert readings[0]["changes"] == ["convention: modified -> standard"]
    assert readings[0]["edits"] == ['convention = "standard"']
    assert (readings[0]["reproduced"], readings[0]["samples"]) == (1, 1)
    assert readings[0]["max_residual_m"] < 1e-9
    written = next(r for r in readings if r["changes"] == [])
    assert written["reproduced"] == 0 and written["max_residual_m"] > 0.1
    assert {"length_unit", "angle_unit", "table", "samples_file"} <= set(record)


def test_text_report_and_check(capsys):
    """Text: ranked readings and the implied edit; --check exits 1 only when a change is best."""
    table = str(DATA / "ned5_as_printed.toml")
    assert main([table, "--samples", HOME, "--top", "3", "--check"]) == 1
    out = capsys.readouterr().out
    assert "the best reading implies:" in out
    assert 'convention: modified -> standard: convention = "standard"' in out
    assert main(["ned5", "--samples", HOME, "--check"]) == 0
    assert "the best reading is the table as written: no edit" in capsys.readouterr().out


def test_json_has_per_sample_residuals(capsys):
    """--json: every reading lists its reproduced samples and one residual [m] per sample."""
    assert main(["pickplace3", "--samples", str(DATA / "pickplace3_table4.csv"), "--json"]) == 0
    best = json.loads(capsys.readouterr().out)["readings"][0]
    assert best["reproduced_samples"] == ["case 2"]
    assert len(best["residuals_m"]) == 2
    assert abs(best["residuals_m"][0] - 0.394) < 1e-9  # case 1: Pz 367 mm printed, -27 mm ours
    assert best["residuals_m"][1] < 1e-6


def test_package_names():
    """kin.audit's __all__ is sorted, without duplicates, and every name exists."""
    import kin.audit

    names = list(kin.audit.__all__)
    assert names == sorted(names) and len(names) == len(set(names))
    assert all(hasattr(kin.audit, name) for name in names)


def test_quoted_labels_comments_and_bom(tmp_path, capsys):
    """A spreadsheet's file: BOM, quoted label with a comma, comments, blank and empty cells."""
    path = tmp_path / "home.csv"
    path.write_text(
        '\ufefflabel,q1,q2,q3,q4,q5,x,y,z  # header\n\n"home, Fig. 10",0,0,0,0,0,43.8,,1\n',
        encoding="utf-8",
    )
    assert main(["ned5", "--samples", str(path), "--json"]) == 0
    best = json.loads(capsys.readouterr().out)["readings"][0]
    assert best["reproduced_samples"] == ["home, Fig. 10"]
    assert (best["values_reproduced"], best["values"]) == (2, 2)


def test_dh2urdf_dispatches_audit(capsys):
    """``dh2urdf audit ...`` runs this command (the installed program, composed in kin)."""
    from kin.commands import dh2urdf_program as command

    table = str(DATA / "ned5_as_printed.toml")
    assert command.main(["audit", table, "--samples", HOME, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["readings"][0]["changes"] == ["convention: modified -> standard"]
