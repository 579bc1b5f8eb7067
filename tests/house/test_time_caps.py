"""The tests run without the library's default wall-clock caps (support.time_caps), all of them.

A default cap left out of conftest's list would let a busy machine turn a test's verdict into
``timeout`` again: every module-level constant of ``kin`` named like a default time cap must be
in the list, and the fixture must make each one infinite (and leave it alone under the marker).
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import math
import re
from pathlib import Path

import pytest
from support.time_caps import DEFAULT_CAPS, child_environment

KIN = Path(importlib.util.find_spec("kin").origin).resolve().parent  # type: ignore[arg-type]

#: Names of module constants that hold a default time cap [s] by the house's naming.
CAP_NAME = re.compile(r"^(DEFAULT_TIMEOUT|NUMERIC_CAP|\w*_TIMEOUT)$")


def _caps_in_source() -> set[tuple[str, str]]:
    """(module, name) of every module-level numeric assignment of a cap-like name in ``kin``."""
    found = set()
    for path in KIN.rglob("*.py"):
        parts = path.relative_to(KIN.parent).with_suffix("").parts
        module = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.Assign) and isinstance(node.value, ast.Constant):
                for target in node.targets:
                    if isinstance(target, ast.Name) and CAP_NAME.match(target.id):
                        if isinstance(node.value.value, (int, float)):
                            found.add((module, target.id))
    return found


def test_every_default_cap_is_lifted_in_the_tests():
    assert _caps_in_source() <= set(DEFAULT_CAPS), _caps_in_source() - set(DEFAULT_CAPS)


@pytest.mark.parametrize(("module", "name"), DEFAULT_CAPS)
def test_the_fixture_makes_each_cap_infinite(module, name):
    assert getattr(importlib.import_module(module), name) == math.inf


@pytest.mark.default_cap
@pytest.mark.parametrize(("module", "name"), DEFAULT_CAPS)
def test_the_marker_keeps_the_library_cap(module, name):
    value = getattr(importlib.import_module(module), name)
    assert math.isfinite(value) and value > 0.0


def test_a_child_process_runs_without_the_caps_too():
    """A child process (conftest puts the hook on every test's PYTHONPATH): its caps are infinite
    once their modules are imported; without the hook they are the library's."""
    import json
    import subprocess
    import sys

    names = json.dumps([list(cap) for cap in DEFAULT_CAPS])
    code = (
        "import importlib, json, sys\n"
        f"caps = json.loads({names!r})\n"
        "print(json.dumps([getattr(importlib.import_module(m), n) for m, n in caps]))"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout) == [math.inf] * len(DEFAULT_CAPS)
    bare = {k: v for k, v in child_environment().items() if k != "PYTHONPATH"}
    plain = subprocess.run([sys.executable, "-c", code], env=bare, capture_output=True, text=True)
    assert all(math.isfinite(v) for v in json.loads(plain.stdout)), plain.stdout
