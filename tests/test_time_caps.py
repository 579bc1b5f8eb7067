"""The tests run without the library's default wall-clock caps (tests/conftest.py), all of them.

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
from conftest import DEFAULT_CAPS

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
