"""A closed output pipe (`| head -1`) or a closed stdout (`>&-`) keeps the command's own exit
code: 1 stays 1, 0 stays 0, and nothing is printed on stderr. Stdout on a full device
(`> /dev/full`) is one line on stderr and exit 1."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from support.cli_helper import kin_command

ROOT = Path(__file__).resolve().parents[2]

CASES = [
    # An unreachable target: exit 1 with or without a reader.
    (["ik", "--robot", "ur5", "--target", "3", "0", "0"], 1),
    (["ik", "--robot", "ur5", "--target", "0.3", "0", "0.3"], 0),
    # A path that stops at a sample it cannot reach: exit 1.
    (
        [
            "path",
            "--robot",
            "ur5",
            "--from",
            "0.4",
            "0",
            "0.3",
            "--rpy",
            "180",
            "0",
            "0",
            "--to",
            "2.4",
            "0.2",
            "0.3",
            "--rpy",
            "180",
            "0",
            "0",
            "--deg",
            "--steps",
            "50",
        ],
        1,
    ),
    (["fk", "--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0"], 0),
]


@pytest.mark.parametrize(("argv", "code"), CASES)
def test_reader_that_closes_early_keeps_the_exit_code(argv, code):
    """`kin ... | head -c 1`: the kin process exits with the code it has without a reader."""
    writer = subprocess.Popen(
        [*kin_command(), *argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    reader = subprocess.Popen(["head", "-c", "1"], stdin=writer.stdout, stdout=subprocess.PIPE)
    writer.stdout.close()  # only the reader holds the pipe now
    reader.communicate(timeout=120)
    err = writer.stderr.read()
    writer.stderr.close()
    assert writer.wait(timeout=120) == code and err == b"", (argv, err)
    alone = subprocess.run([*kin_command(), *argv], capture_output=True, timeout=120)
    assert alone.returncode == code


def test_stream_with_a_failed_line_keeps_exit_1(tmp_path):
    """`kin ik --stdin | head -c 1` whose first line is unreachable: exit 1, and it stops."""
    lines = ['{"target": [3, 0, 0]}'] + ['{"target": [0.39, 0.08, 0.3]}'] * 20000
    source = tmp_path / "targets.jsonl"
    source.write_text("\n".join(lines) + "\n")
    with source.open("rb") as stdin:
        writer = subprocess.Popen(
            [*kin_command(), "ik", "--robot", "pickplace3", "--stdin"],
            stdin=stdin,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
        )
        reader = subprocess.Popen(["head", "-c", "1"], stdin=writer.stdout, stdout=subprocess.PIPE)
        writer.stdout.close()
        reader.communicate(timeout=120)
        err = writer.stderr.read()
        writer.stderr.close()
        assert writer.wait(timeout=120) == 1 and err == b""


def dh2urdf_command() -> list[str]:
    """The ``dh2urdf`` console script next to the interpreter, else ``python -m dh2urdf``."""
    script = Path(sys.executable).with_name("dh2urdf")
    return [str(script)] if script.exists() else [sys.executable, "-m", "dh2urdf"]


REACH = ["reach", "--robot", "ur5", "--voxel", "0.3", "--orientations", "4", "--quiet"]
#: Command -> (argv after the program, with {tmp}; stdin text or None).
FULL_STDOUT = {
    "kin fk": (["fk", "--robot", "ur5", "--q", *["0"] * 6], None),
    "kin fk --json": (["fk", "--robot", "ur5", "--json", "--q", *["0"] * 6], None),
    "kin reach --json": ([*REACH, "-o", "{tmp}/map.npz", "--json"], None),
    "kin ik --stdin": (["ik", "--robot", "ur5", "--stdin"], '{"target": [0.3, 0, 0.3]}\n' * 50),
    "dh2urdf -o -": (["--robot", "ur5", "-o", "-"], None),
    "dh2urdf from-urdf -o -": (
        ["from-urdf", str(ROOT / "urdf" / "planar2.urdf"), "-o", "-"],
        None,
    ),
}


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize("name", sorted(FULL_STDOUT))
def test_stdout_on_a_full_device_is_one_line_and_exit_1(name, tmp_path):
    """`... > /dev/full`: exit 1, one line on stderr naming standard output, no traceback."""
    argv, stdin = FULL_STDOUT[name]
    program = dh2urdf_command() if name.startswith("dh2urdf") else kin_command()
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    with open("/dev/full", "w") as full:
        done = subprocess.run(
            [*program, *argv],
            input=stdin or "",
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            timeout=120,
        )
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 1, (name, done.stderr)
    assert len(lines) == 1 and "Traceback" not in done.stderr, (name, done.stderr)
    assert "cannot write to standard output: No space left on device" in lines[0], lines


@pytest.mark.parametrize(
    ("program", "argv"),
    [
        ("kin", ["fk", "--robot", "ur5", "--q", *["0"] * 6]),
        ("dh2urdf", ["--robot", "ur5", "-o", "-"]),
    ],
)
def test_closed_stdout_is_quiet_and_keeps_exit_0(program, argv):
    """`... >&-`: nothing on stderr, exit 0, as for a reader that left."""
    command = dh2urdf_command() if program == "dh2urdf" else kin_command()
    done = subprocess.run(
        [*command, *argv],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        preexec_fn=lambda: os.close(1),  # noqa: PLW1509 (no threads started yet)
        timeout=120,
    )
    assert (done.returncode, done.stderr) == (0, b""), (program, done.stderr)
