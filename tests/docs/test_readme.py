"""The README's Python examples print what the README says they print; the quick start is two commands."""

import contextlib
import io
import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"
TEXT = README.read_text(encoding="utf-8")
#: Each ```python block followed by "prints" and the ``` block of its output.
EXAMPLES = re.findall(r"```python\n(.*?)```\s*prints\s*\n\s*```\n(.*?)```", TEXT, re.S)


def test_readme_has_the_fk_and_ik_examples():
    """Both examples (Usage: FK and Jacobian; IK in Python) are found with their outputs."""
    assert len(EXAMPLES) == 2, len(EXAMPLES)


@pytest.mark.parametrize(("code", "expected"), EXAMPLES, ids=["fk", "ik"])
def test_example_prints_documented_output(code, expected):
    """Running the block prints the block that follows it (whitespace-insensitive)."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, str(README), "exec"), {})
    assert out.getvalue().split() == expected.split()


def test_quick_start_has_two_commands():
    """The developers' quick start is two commands: setup + main job, then the tests."""
    block = re.search(r"## Develop.*?```bash\n(.*?)```", TEXT, re.S).group(1)
    commands = [line for line in block.splitlines() if line.strip()]
    assert len(commands) == 2
    assert commands[1].strip() == ".venv/bin/python -m pytest"
    assert "reproduce_papers.py" in commands[0] and "-c constraints.txt" in commands[0]


def test_ci_runs_the_quick_start():
    """.ci/run installs as the quick start does and runs the same test command."""
    ci = (README.parent / ".ci" / "run").read_text(encoding="utf-8")
    assert '-c constraints.txt -e ".[test]"' in ci and "\n.venv/bin/python -m pytest\n" in ci
