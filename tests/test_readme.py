"""The README's usage example prints what the README says it prints."""

import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).resolve().parent.parent / "README.md"


def test_usage_example_prints_documented_output():
    """Running the ```python block of 'Usage' prints the ``` block that follows it."""
    text = README.read_text(encoding="utf-8")
    usage = text.split("## Usage", 1)[1].split("\n## ", 1)[0]
    code = re.search(r"```python\n(.*?)```", usage, re.S).group(1)
    expected = re.search(r"prints\s*\n\s*```\n(.*?)```", usage, re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, str(README), "exec"), {})
    assert out.getvalue().split() == expected.split()


def test_quick_start_has_two_commands():
    """The quick start is two commands: setup + main job, then the tests."""
    text = README.read_text(encoding="utf-8")
    block = re.search(r"## Quick start.*?```bash\n(.*?)```", text, re.S).group(1)
    commands = [line for line in block.splitlines() if line.strip()]
    assert len(commands) == 2
    assert commands[1].strip() == ".venv/bin/python -m pytest"
