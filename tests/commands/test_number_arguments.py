"""Numbers on the command line are written with the digits 0-9: ``1_000`` is refused, not 1000.

Python's ``float`` and ``int`` read ``1_000`` as 1000 (and digits of other scripts as numbers);
every numeric argument of every command goes through one converter that refuses them.
"""

from __future__ import annotations

import json

import pytest
from support.cli_helper import assert_one_line_error, call, run

from dh2urdf.command_line import finite_float, positive_int, whole_number
from kin.commands import main

POSE = ["--target", "0.4", "0.1", "0.3"]
LINE = ["--from", "0.4", "0", "0.3", "--to", "0.4", "0.2", "0.3"]


@pytest.mark.parametrize(
    "argv",
    [
        ["fk", "--robot", "ur5", "--q", "1_000", "0", "0", "0", "0", "0"],
        ["check", "--robot", "ur5", "--q", "0", "0", "0", "0", "0", "1_0"],
        ["ik", "--robot", "ur5", "--target", "0.4", "0.1", "0_3"],
        ["ik", "--robot", "ur5", *POSE, "--timeout", "1_000"],
        ["path", "--robot", "ur5", *LINE, "--steps", "1_0"],
        ["drives", "--robot", "scorbot", "--pulses", "1_000", "0", "0", "0", "0"],
        ["workspace", "--robot", "planar2", "--n", "1_000", "-o", "{tmp}/w.png"],
        ["workspace", "--robot", "planar2", "--n", "100", "--seed", "1_2", "-o", "{tmp}/w.png"],
        ["collisions", "--robot", "planar2", "--samples", "1_0", "--write-srdf", "{tmp}/a.srdf"],
        [
            "collisions",
            "--robot",
            "planar2",
            "--random-seed",
            "1_0",
            "--write-srdf",
            "{tmp}/a.srdf",
        ],  # fmt: skip
        ["preview", "--robot", "planar2", "--workspace", "1_0", "--html", "{tmp}/p.html"],
        ["fk", "--robot", "ur5", "--q", "\u0661", "0", "0", "0", "0", "0"],
    ],
)
def test_grouped_digits_are_refused_in_every_numeric_argument(argv, tmp_path, capsys):
    """`--q 1_000` ran as 1000: exit 2, one line naming the argument and the fix, no output."""
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    code = call(main, argv)
    captured = capsys.readouterr()
    assert_one_line_error(code, captured.err, "without '_' (1000, not 1_000)")
    assert "argument --" in captured.err and captured.out == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("converter", [finite_float, positive_int, whole_number])
def test_the_converters_read_plain_digits(converter):
    """The same converters read 1000 (and -3, 2.5 where they may) as before."""
    assert converter("1000") == 1000
    assert finite_float("-2.5e-3") == -2.5e-3 and whole_number("-3") == -3


def test_a_seed_q_of_text_in_a_stream_line_is_that_lines_error():
    """kin ik --stdin: "seed_q": ["1_000", ...] was read as 1000 (NumPy parses text): now the
    line's error; a seed of numbers on the next line is answered."""
    lines = (
        '{"target": [0.4, 0.1, 0.3], "seed_q": ["1_000", 0, 0, 0, 0, 0]}\n'
        '{"target": [0.4, 0.1, 0.3], "seed_q": [true, 0, 0, 0, 0, 0]}\n'
        '{"target": [0.4, 0.1, 0.3], "seed_q": [0.3, 0, 0, 0, 0, 0]}\n'
    )
    done = run(["ik", "--robot", "ur5", "--stdin"], stdin=lines)
    first, second, third = (json.loads(line) for line in done.stdout.splitlines())
    assert '"seed_q" must be numbers' in first["error"], first
    assert '"seed_q" must be numbers' in second["error"], second
    assert third["success"] is True
