"""The compiled twins: every C file in ``kin/_native/``, one loader, a parity test for each.

Read from the sources themselves (pyproject.toml's ``ext-modules``, the ``#include`` lines, the
Python modules' text), not from the loader's own table alone: a twin declared but not in the
folder, a header left out of ``depends``, a module that imports a twin by itself, or a twin without
a parity test fails here.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import re
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from kin import _native
from kin._native import PARITY_TESTS, TWINS, twin, why_missing

ROOT = Path(__file__).resolve().parents[1]  # the repository: pyproject.toml
#: Where the package is installed (the sources in an editable install, site-packages from a
#: wheel, which ships the C files too): the folder that paths like ``kin/_native/x.c`` are under.
SITE = Path(_native.__file__).resolve().parents[2]
NATIVE = SITE / "kin" / "_native"
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
EXTENSIONS = {ext["name"]: ext for ext in PYPROJECT["tool"]["setuptools"]["ext-modules"]}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)
#: A twin imported by name, not through the loader: ``from ._closed7 import``, ``import _x``.
DIRECT = re.compile(
    r"^\s*(from\s+[\w.]*\b(?P<a>_\w+)\s+import|from\s+[\w.]+\s+import\s+(?P<b>_\w+)\b|import\s+[\w.]*\b(?P<c>_\w+)\b)",
    re.MULTILINE,
)


def _headers_reached(source: Path) -> set[str]:
    """The headers a C file includes, directly or through other headers (quoted includes)."""
    seen: set[str] = set()
    stack = [source]
    while stack:
        for name in INCLUDE.findall(stack.pop().read_text()):
            if name not in seen:
                seen.add(name)
                stack.append(NATIVE / name)
    return seen


def test_every_c_file_of_the_package_sits_in_the_native_folder():
    """No C source or header in kin/ outside kin/_native/, and the folder holds some."""
    outside = [
        str(p.relative_to(SITE))
        for p in (SITE / "kin").rglob("*")
        if p.suffix in {".c", ".h"} and p.parent != NATIVE
    ]
    assert outside == []
    assert len(list(NATIVE.glob("*.c"))) == len(EXTENSIONS) == 9


@pytest.mark.parametrize("name", sorted(EXTENSIONS))
def test_each_declared_extension_builds_from_the_native_folder(name):
    """Its one source and its depends are files of kin/_native/; depends are the headers it reaches."""
    ext = EXTENSIONS[name]
    (source,) = ext["sources"]
    files = [source, *ext.get("depends", [])]
    assert all(f.startswith("kin/_native/") and (SITE / f).is_file() for f in files), f"{name=}"
    assert Path(source).stem == name.rsplit(".", 1)[1], f"{name=}: the source is named for it"
    reached = _headers_reached(SITE / source)
    assert all((NATIVE / h).is_file() for h in reached), f"{name=} includes a missing header"
    assert {Path(d).name for d in ext.get("depends", [])} == reached, f"{name=}"


def test_every_file_of_the_folder_is_built_or_included():
    """Each .c is one extension's source, each .h is included by some source: no stray file."""
    sources = {Path(ext["sources"][0]).name for ext in EXTENSIONS.values()}
    assert {p.name for p in NATIVE.glob("*.c")} == sources
    included = set().union(*(_headers_reached(NATIVE / s) for s in sources))
    assert {p.name for p in NATIVE.glob("*.h")} == included


def test_the_loader_knows_exactly_the_declared_extensions():
    """The loader's table maps each C source's stem to the extension pyproject.toml declares."""
    declared = {Path(ext["sources"][0]).stem: name for name, ext in EXTENSIONS.items()}
    assert TWINS == declared
    assert sorted(PARITY_TESTS) == sorted(TWINS)


@pytest.mark.parametrize("name", sorted(TWINS))
def test_the_loader_finds_each_twin_when_built(name):
    """Built (a compiled file importlib finds): the loader returns it; else None with the reason."""
    spec = importlib.util.find_spec(TWINS[name])
    built = spec is not None and str(spec.origin).endswith(
        tuple(importlib.machinery.EXTENSION_SUFFIXES)
    )
    module = twin(name)
    if built:
        assert module is not None and module.__name__ == TWINS[name], f"{name=}"
        assert why_missing(name) is None
    else:  # pragma: no cover - no C compiler at install
        assert module is None
        assert TWINS[name] in why_missing(name)


def test_a_twin_not_built_is_none_and_says_why(monkeypatch):
    """A declared twin whose module is absent: None, and why_missing names it and the fallback."""
    monkeypatch.setitem(TWINS, "_absent", "kin._native._absent")
    monkeypatch.setattr(_native, "_MISSING", {})
    assert why_missing("_absent") is None
    assert twin("_absent") is None
    assert why_missing("_absent") == (
        "kin._native._absent is not built (No module named 'kin._native._absent'); "
        "the Python form runs alone"
    )


def test_an_unknown_twin_is_a_key_error_listing_the_twins():
    """A name that is not a twin fails at once, naming the twins there are."""
    with pytest.raises(KeyError, match="no compiled twin '_closed8'; the twins: _closed7, _damped"):
        twin("_closed8")


def test_no_python_module_imports_a_twin_by_itself():
    """Every import of a twin in kin/ goes through kin._native.twin (one loader, one fallback)."""
    offenders = []
    for path in (SITE / "kin").rglob("*.py"):
        for match in DIRECT.finditer(path.read_text()):
            if {match["a"], match["b"], match["c"]} & set(TWINS):
                offenders.append(f"{path.relative_to(SITE)}: {match[0].strip()}")
    assert offenders == []


@pytest.mark.parametrize("name", sorted(TWINS))
def test_each_twin_has_a_parity_test_file(name):
    """A test file compares the twin with its Python form: it names the twin and asserts."""
    path = ROOT / "tests" / PARITY_TESTS[name]
    text = path.read_text()
    assert name in text, f"{name=} is not named in {path.name}"
    assert len(re.findall(r"^\s*def test_", text, re.MULTILINE)) >= 3, f"{path.name}"
    assert "compiled" in text or "twin" in text, f"{path.name}"
