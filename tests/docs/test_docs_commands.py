"""Every command the README and docs/*.md show with its output prints that output.

A shown command is a ``$ kin ...`` or ``$ dh2urdf ...`` line inside a ```console block; the lines
after it, up to the next ``$`` line or the end of the block, are its output (stdout, then stderr).
Each command runs as ``python -m`` of its console script's module (``kin``,
``kin.commands.dh2urdf_program``: the installed ``dh2urdf`` with kin's ``audit`` and
``calibrate``) in a fresh temporary folder that
holds a link to the repository's ``examples/`` (so ``-o`` files land there, and nothing is
written in the checkout).

Normalisation rule (applied to the shown and the real output alike): each line is compared as
its whitespace-separated words (column alignment is free); a number of magnitude below 1e-9
compares as 0 (rounding residues such as ``2.24e-16`` and signed zeros vary by platform); a
number followed by a time unit (``s``, ``ms``, ``us``, e.g. ``time: 0.222 ms``) compares as any
time. Everything else, branch labels, joint values, counts and file names, must match exactly.
"""

from __future__ import annotations

import filecmp
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
#: Each project command and the module its console script runs (pyproject.toml [project.scripts]).
COMMANDS = {"kin": "kin", "dh2urdf": "kin.commands.dh2urdf_program"}
TIME_UNIT = re.compile(r"^(s|ms|us)[;,.]?$")


def _shown_commands() -> list[tuple[str, str, list[str]]]:
    """(where, command line, shown output lines) of every ``$`` line in a ```console block."""
    found = []
    for document in DOCUMENTS:
        text = document.read_text(encoding="utf-8")
        for block in re.finditer(r"```console\n(.*?)```", text, re.S):
            line_number = text.count("\n", 0, block.start()) + 2
            for offset, line in enumerate(block.group(1).splitlines()):
                if line.startswith("$ "):
                    where = f"{document.relative_to(ROOT)}:{line_number + offset}"
                    found.append((where, line[2:], []))
                elif found and found[-1][0].startswith(str(document.relative_to(ROOT))):
                    found[-1][2].append(line)
    return found


SHOWN = _shown_commands()


def _number(word: str) -> float | None:
    """The value of ``word`` (trailing punctuation aside), else None."""
    try:
        return float(word.rstrip(",;:)").lstrip("("))
    except ValueError:
        return None


def normalise(lines: list[str]) -> list[list[str]]:
    """The lines as the docstring's rule compares them (blank lines dropped)."""
    result = []
    for line in lines:
        words = line.split()
        if not words:
            continue
        for i, word in enumerate(words):
            value = _number(word)
            if value is None:
                continue
            if i + 1 < len(words) and TIME_UNIT.match(words[i + 1]):
                words[i] = "<time>"
            elif abs(value) < 1e-9:
                words[i] = "0"
        result.append(words)
    return result


def test_docs_show_commands():
    """The README's quick start and the guides' examples are found (the parser is not silent)."""
    places = {where.split(":")[0] for where, _, _ in SHOWN}
    assert {"README.md", "docs/partial-poses.md", "docs/reach-maps.md"} <= places, places
    assert all(output for _, _, output in SHOWN), "a shown command without its output"


def test_normalise_keeps_what_matters():
    """Residues and times are equalised; a changed joint value or label is not."""
    assert normalise(["iterations: 0, time: 0.222 ms", "ok  6.94e-14  -0.000000"]) == normalise(
        ["iterations: 0,   time: 9.9 ms", "ok  1.2e-13  +0.000000"]
    )
    assert normalise(["elbow left  10.1529"]) != normalise(["elbow left  10.1530"])
    assert normalise(["elbow left  10.1529"]) != normalise(["elbow right  10.1529"])


def test_examples_match_the_test_data():
    """examples/cobra600.toml is the tested table (tests/data/toolbox/cobra600.toml)."""
    assert filecmp.cmp(
        ROOT / "examples" / "cobra600.toml",
        ROOT / "tests" / "data" / "toolbox" / "cobra600.toml",
        shallow=False,
    )


@pytest.mark.parametrize(("where", "command", "shown"), SHOWN, ids=[s[0] for s in SHOWN])
def test_shown_command_prints_its_output(where, command, shown, tmp_path):
    """The command prints what the document shows (the module docstring's rule)."""
    argv = shlex.split(command, comments=True)
    assert argv[0] in COMMANDS, f"{where}: {argv[0]!r} is not a project command"
    (tmp_path / "examples").symlink_to(ROOT / "examples", target_is_directory=True)
    run = subprocess.run(
        [sys.executable, "-m", COMMANDS[argv[0]], *argv[1:]],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert run.returncode in (0, 1), f"{where}: exit {run.returncode}: {run.stderr}"
    printed = (run.stdout + run.stderr).splitlines()
    assert normalise(printed) == normalise(shown), f"{where}:\n{run.stdout}{run.stderr}"
