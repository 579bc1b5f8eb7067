"""Output files are checked before any work: a missing folder, an unwritable one or an unknown
suffix is one line and exit 2 at once; a known figure suffix is written in that format."""

from __future__ import annotations

import pytest
from support.cli_helper import assert_one_line_error

import kin.robot_model
from kin.commands import path, preview, workspace

PATH_ARGS = ["--robot", "ur5", "--from", "0.4", "0", "0.3", "--rpy", "180", "0", "0"]
PATH_ARGS += ["--to", "0.4", "0.2", "0.3", "--rpy", "180", "0", "0", "--deg", "--steps", "10"]


@pytest.mark.parametrize(
    ("main", "argv", "needle"),
    [
        (
            workspace.main,
            ["--robot", "ur5", "--n", "50000000", "-o", "{tmp}/nodir/ws.png"],
            "does not exist",
        ),
        (
            workspace.main,
            ["--robot", "ur5", "--n", "50000000", "-o", "{tmp}/ws.jpg"],
            "unknown file type '.jpg'",
        ),
        (workspace.main, ["--robot", "ur5", "--n", "50000000", "-o", "{tmp}"], "is a folder"),
        (path.main, [*PATH_ARGS, "--csv", "{tmp}/nodir/p.csv"], "does not exist"),
        (path.main, [*PATH_ARGS, "--csv", "{tmp}/p.txt"], "unknown file type"),
        (preview.main, ["--robot", "ur5", "--html", "{tmp}/nodir/x.html"], "does not exist"),
    ],
)
def test_bad_output_is_refused_before_any_work(main, argv, needle, tmp_path, capsys, monkeypatch):
    """50 million samples would take a minute: the refusal comes before the robot is loaded."""

    def started(*_: object) -> None:
        raise AssertionError("the robot was loaded before the output was checked")

    monkeypatch.setattr(kin.robot_model, "load_robot", started)
    argv = [arg.replace("{tmp}", str(tmp_path)) for arg in argv]
    code = main(argv)
    assert_one_line_error(code, capsys.readouterr().err, needle)
    assert sorted(p.name for p in tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("suffix", "magic"), [(".png", b"\x89PNG"), (".svg", b"<?xml"), (".pdf", b"%PDF")]
)
def test_figure_is_written_in_the_format_of_its_suffix(suffix, magic, tmp_path, capsys):
    """kin workspace -o ws.svg writes SVG, .pdf PDF, .png PNG."""
    out = tmp_path / f"ws{suffix}"
    assert workspace.main(["--robot", "planar2", "--n", "20000", "-o", str(out)]) == 0
    assert out.read_bytes().startswith(magic)
    assert [p.name for p in tmp_path.iterdir()] == [out.name]  # no temporary file left


def test_path_csv_is_written_whole(tmp_path, capsys):
    """kin path --csv: the header and one row per sample."""
    out = tmp_path / "p.csv"
    assert path.main([*PATH_ARGS, "--csv", str(out)]) == 0
    lines = out.read_text().splitlines()
    assert lines[0].startswith("sample,") and len(lines) == 12
