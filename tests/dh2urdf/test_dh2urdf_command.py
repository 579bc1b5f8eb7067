"""The ``dh2urdf`` command: URDF/MJCF export, stdout, format from the suffix, one-line errors."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from support.scripts_helper import load_script

from dh2urdf import ROBOTS, __version__
from dh2urdf.command import INSTALLED_ONLY, INSTALLED_PROGRAM, output_format

CONSOLE = Path(sys.executable).parent / "dh2urdf"


def run(*argv: str, command: tuple[str, ...] = (sys.executable, "-m", "dh2urdf")):
    """Run the command in a subprocess; returns the CompletedProcess (text)."""
    return subprocess.run([*command, *argv], capture_output=True, text=True, check=False)


def test_table_file_to_urdf_equals_the_committed_file(tmp_path):
    """dh2urdf TABLE.toml -o arm.urdf writes the committed URDF and one line naming it."""
    out = tmp_path / "arm.urdf"
    done = run(str(ROBOTS["scorbot"].table_path), "-o", str(out))
    assert done.returncode == 0, done.stderr
    assert done.stdout == f"wrote {out} (URDF, scorbot, 5 joints, meters/radians)\n"
    assert out.read_text() == ROBOTS["scorbot"].urdf_path.read_text()
    assert oct(out.stat().st_mode & 0o644) == oct(0o644)  # readable, not a private temp file


def test_robot_to_mjcf_by_suffix_and_stdout():
    """--robot with -o - prints the URDF; --format mjcf prints MJCF with the tool site."""
    urdf = run("--robot", "planar2", "-o", "-")
    assert urdf.returncode == 0 and '<robot name="planar2">' in urdf.stdout
    assert urdf.stdout == ROBOTS["planar2"].urdf_path.read_text()
    mjcf = run("--robot", "planar2", "--format", "mjcf", "-o", "-")
    assert mjcf.returncode == 0 and '<mujoco model="planar2">' in mjcf.stdout
    assert '<site name="tool"' in mjcf.stdout


@pytest.mark.parametrize(
    ("output", "chosen", "expected"),
    [
        ("a.xml", None, "mjcf"),
        ("a.MJCF", None, "mjcf"),
        ("a.urdf", None, "urdf"),
        ("-", None, "urdf"),
        ("a.xml", "urdf", "urdf"),
    ],
)
def test_output_format_from_suffix(output, chosen, expected):
    """.xml/.mjcf choose MJCF, anything else URDF; --format wins."""
    assert output_format(output, chosen) == expected


def test_version_and_console_script():
    """dh2urdf --version from the console script installed by pip."""
    assert CONSOLE.exists(), "run: pip install -e . --no-deps"
    done = run("--version", command=(str(CONSOLE),))
    assert (done.returncode, done.stdout) == (0, f"dh2urdf {__version__}\n")


def test_console_script_writes_mjcf(tmp_path):
    """The console script writes arm.xml as MJCF."""
    out = tmp_path / "ur5.xml"
    done = run("--robot", "ur5", "-o", str(out), command=(str(CONSOLE),))
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"wrote {out} (MJCF, ur5, 6 joints")
    assert '<mujoco model="ur5">' in out.read_text()


def test_command_does_not_import_kin():
    """dh2urdf is the lower layer: exporting a URDF and an MJCF loads no kin module."""
    code = (
        "import sys, io, contextlib\n"
        "from dh2urdf.command import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    main(['--robot', 'ur5', '-o', '-']); main(['--robot', 'ur5', '--format', 'mjcf', '-o', '-'])\n"
        "print(sorted(m for m in sys.modules if m == 'kin' or m.startswith('kin.')))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout == "[]\n"


BAD_TABLE = 'convention = "standard"\nlength_unit = "m"\nangle_unit = "rad"\n'


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["missing.toml", "-o", "{out}"], "cannot read the file"),
        (["{bad}", "-o", "{out}"], "at least one [[joints]] row"),
        (["--robot", "nope", "-o", "{out}"], "invalid choice: 'nope'"),
        (["--robot", "ur5", "-o", "{tmp}/no/such/arm.urdf"], "does not exist"),
        (["--robot", "ur5", "--format", "mjcf", "-o", "{tmp}/no/arm.xml"], "does not exist"),
        (["--robot", "ur5"], "required: -o/--output"),
        (["--robot", "ur5", "-o", "{tmp}"], "is a folder"),
        (["audit", "{tmp}/missing.toml", "--samples", "{tmp}/none.csv"], "missing.toml"),
    ],
)
def test_bad_input_exits_2_with_one_line_and_no_file(tmp_path, argv, words):
    """Bad input: exit 2, exactly one stderr line, no traceback, nothing written."""
    bad = tmp_path / "bad.toml"
    bad.write_text(BAD_TABLE)
    out = tmp_path / "arm.urdf"
    argv = [a.format(out=out, bad=bad, tmp=tmp_path) for a in argv]
    # python -m dh2urdf runs dh2urdf's own forms; the installed program's module, kin's too
    package = "dh2urdf" if argv[0] not in INSTALLED_ONLY else INSTALLED_PROGRAM
    for command in ((sys.executable, "-m", package), (str(CONSOLE),)):
        done = run(*argv, command=command)
        assert done.returncode == 2, f"{argv=} {done.stderr}"
        assert len(done.stderr.splitlines()) == 1, f"{argv=} {done.stderr}"
        assert "Traceback" not in done.stderr and words in done.stderr, done.stderr
        assert done.stdout == ""
        assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"], f"{argv=}"


@pytest.mark.parametrize("name", INSTALLED_ONLY)
def test_python_m_dh2urdf_says_where_kins_subcommands_are(name, tmp_path):
    """python -m dh2urdf (the lower package alone) names the installed program for audit and
    calibrate: one line, exit 2; the installed program's help lists them."""
    done = run(name, "x.toml", "-o", str(tmp_path / "x.urdf"))
    assert done.returncode == 2 and done.stdout == "", done.stderr
    assert done.stderr.splitlines() == [
        f"dh2urdf: error: '{name}' comes with kin: run the installed program "
        f"(dh2urdf {name} ...) or python -m {INSTALLED_PROGRAM} {name} ..."
    ]
    shown = run("--help", command=(str(CONSOLE),)).stdout
    assert f"dh2urdf {name} " in shown and "dh2urdf from-urdf" in shown


def test_export_urdf_script_is_a_shim(tmp_path, capsys):
    """scripts/export_urdf.py main is dh2urdf's: same file, same line."""
    out = tmp_path / "lab5.urdf"
    assert load_script("export_urdf").main(["--robot", "lab5", "-o", str(out)]) == 0
    assert out.read_text() == ROBOTS["lab5"].urdf_path.read_text()
    assert capsys.readouterr().out.startswith(f"wrote {out} (URDF, lab5, 5 joints")


def test_mujoco_remark_is_one_warning_line_and_no_log_file(tmp_path, monkeypatch, capsys):
    """Equal joint limits (MuJoCo ignores them): the MJCF is written, MuJoCo's remark is one
    'dh2urdf: warning:' line naming the table, and no MUJOCO_LOG.TXT lands in the working folder."""
    from dh2urdf.command import main

    text = (ROBOTS["ur5"].table_path).read_text(encoding="utf-8")
    old = "limits = [-3.141592653589793, 3.141592653589793]"
    assert old in text
    table = tmp_path / "fixed_elbow.toml"
    text = text.split("\n[states]")[0]  # the maker's named states are outside that limit
    table.write_text(text.replace(old, "limits = [0.5, 0.5]"), encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert main([str(table), "-o", "arm.xml"]) == 0
    err = capsys.readouterr().err
    # MuJoCo 4 remarks on the equal limits; 3.17 (Python 3.10's lock) says nothing: either way
    # at most that one line, and never a log file.
    expected = (
        f"dh2urdf: warning: {table}: MuJoCo: joint 'elbow_joint' has equal lower and upper "
        "limits, limit ignored"
    )
    assert err.splitlines() in ([expected], []), err
    assert (tmp_path / "arm.xml").exists() and not (tmp_path / "MUJOCO_LOG.TXT").exists()
