"""`import kin` and `kin fk` stay light: no scipy, mujoco, mink, yourdfpy or meshcat."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("scipy", "mujoco", "mink", "yourdfpy", "meshcat")

_PROBE = """
import contextlib, io, json, sys
{setup}
print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in {heavy!r})))
"""

_FK = """
from kin.commands import main
with contextlib.redirect_stdout(io.StringIO()):
    assert main(["fk", "--robot", "humanoid7", "--q", "0", "0", "0", "0", "0", "0", "0"]) == 0
"""


@pytest.mark.parametrize(
    "what, setup",
    [
        ("import kin", "import kin"),
        ("kin fk", _FK),
        (
            "kin robots",
            _FK.replace(
                '"fk", "--robot", "humanoid7", "--q", "0", "0", "0", "0", "0", "0", "0"', '"robots"'
            ),
        ),
    ],
)
def test_no_heavy_module_is_imported(what, setup):
    """The modules loaded by a fresh interpreter for this task include none of the heavy ones."""
    code = _PROBE.format(setup=setup, heavy=HEAVY)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.splitlines()[-1]) == [], what


def test_importtime_of_kin_fk_names_no_heavy_module():
    """`python -X importtime -m kin fk ...` lists no heavy module (the measurement bench_cli uses)."""
    argv = [
        sys.executable,
        "-X",
        "importtime",
        "-m",
        "kin",
        "fk",
        "--robot",
        "scorbot",
        "--q",
        *["0"] * 5,
    ]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and "position" in done.stdout
    imported = {
        line.split("|")[-1].strip().split(".")[0]
        for line in done.stderr.splitlines()
        if "|" in line
    }
    assert "pinocchio" in imported and imported.isdisjoint(HEAVY)


def test_a_table_file_builds_its_model_without_yourdfpy_or_trimesh(tmp_path):
    """A user's table (a shipped one copied elsewhere): load_robot, FK and `kin fk` import neither
    yourdfpy nor trimesh (nor lxml): only reading or checking a URDF needs them (issue 22.3)."""
    from dh2urdf import get_robot

    path = tmp_path / "my_arm.toml"
    path.write_bytes(get_robot("ur5").table_path.read_bytes())
    setup = f"""
from kin import Configuration, load_robot
from kin.commands import main
robot = load_robot({str(path)!r})
assert robot.table.path == {str(path)!r} and "<visual" in robot.urdf
Configuration(robot).fk([0.1] * 6)
with contextlib.redirect_stdout(io.StringIO()):
    assert main(["fk", "--robot", {str(path)!r}, "--q", *["0.1"] * 6]) == 0
"""
    heavy = (*HEAVY, "trimesh", "lxml")
    code = _PROBE.format(setup=setup, heavy=heavy)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.splitlines()[-1]) == []
