"""A closed output pipe (`| head -1`) keeps the command's own exit code: 1 stays 1, 0 stays 0,
and nothing is printed on stderr."""

from __future__ import annotations

import subprocess

import pytest
from cli_helper import kin_command

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
