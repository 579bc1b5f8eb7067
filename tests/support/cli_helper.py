"""Helpers of the ``kin`` command tests: a prismatic test table, subprocess runs, exit codes."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

#: A SCARA-like arm: revolute, revolute, prismatic (a length in mm), revolute; mm and degrees.
RRPR4_TOML = """
name = "rrpr4"
description = "SCARA-like test arm: two revolute joints, a prismatic one, a wrist roll"
source = "tests/support/cli_helper.py: invented for the units rule"
convention = "standard"
length_unit = "mm"
angle_unit = "deg"

[[joints]]
name = "shoulder"
type = "revolute"
a = 200.0
alpha = 0.0
d = 300.0
theta = 0.0
limits = [-150.0, 150.0]

[[joints]]
name = "elbow"
type = "revolute"
a = 150.0
alpha = 180.0
d = 0.0
theta = 0.0
limits = [-150.0, 150.0]

[[joints]]
name = "slide"
type = "prismatic"
a = 0.0
alpha = 0.0
d = 20.0
theta = 0.0
limits = [0.0, 200.0]

[[joints]]
name = "roll"
type = "revolute"
a = 0.0
alpha = 0.0
d = 50.0
theta = 0.0
limits = [-180.0, 180.0]
"""


def write_rrpr4(folder: Path) -> Path:
    """Write the prismatic test table into ``folder`` and return its path."""
    path = folder / "rrpr4.toml"
    path.write_text(RRPR4_TOML, encoding="utf-8")
    return path


def kin_command() -> list[str]:
    """The ``kin`` console script next to the interpreter, else ``python -m kin``."""
    script = Path(sys.executable).with_name("kin")
    return [str(script)] if script.exists() else [sys.executable, "-m", "kin"]


def run(
    argv: list[str], stdin: str | None = None, module: bool = True
) -> subprocess.CompletedProcess:
    """Run ``python -m kin argv`` (or the console script) and capture its text output."""
    command = [sys.executable, "-m", "kin"] if module else kin_command()
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run(
        command + argv, input=stdin, capture_output=True, text=True, timeout=120, env=env
    )


def call(main, argv: list[str]) -> int:  # noqa: ANN001
    """Exit code of ``main(argv)``, whether it returns it or argparse raises SystemExit."""
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)


def assert_one_line_error(code: int, err: str, needle: str = "") -> None:
    """Bad input: exit 2, exactly one line on stderr (containing ``needle``), no traceback."""
    assert code == 2, (code, err)
    assert len(err.strip().splitlines()) == 1 and err.endswith("\n"), err
    assert "Traceback" not in err and needle in err, err
