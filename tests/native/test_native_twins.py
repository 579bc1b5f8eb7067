"""The compiled twins: one table, sources laid out like their modules, one loader, a parity test each.

Read from the sources themselves (setup.py's extensions, the ``#include`` lines, the Python
modules' text), not from the loader's own table alone: a twin declared but without its source, a
header its extension does not depend on, a C file no twin builds, a module that imports a twin by
itself, or a twin without a parity test fails here.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import re
import runpy
from pathlib import Path

import pytest

from kin import _native
from kin._native import PARITY_TESTS, PURE_PYTHON_VARIABLE, TWINS, twin, why_missing

ROOT = Path(__file__).resolve().parents[2]  # the repository: setup.py
#: Where the package is installed (the sources in an editable install, site-packages from a
#: wheel, which ships the C files too): the folder that paths like ``kin/_native/x.c`` are under.
SITE = Path(_native.__file__).resolve().parents[2]
NATIVE = SITE / "kin" / "_native"
SHARED = NATIVE / "include"
#: setup.py's extensions (its build runs only as ``__main__``) as it finds them in the installed
#: package (which holds the registry and the C files, a wheel's too), each by module name.
EXTENSIONS = {
    ext["name"]: ext for ext in runpy.run_path(str(ROOT / "setup.py"))["twin_extensions"](SITE)
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)
#: A twin imported by name, not through the loader: ``from ._closed7 import``, ``import _x``.
DIRECT = re.compile(
    r"^\s*(from\s+[\w.]*\b(?P<a>_\w+)\s+import|from\s+[\w.]+\s+import\s+(?P<b>_\w+)\b|import\s+[\w.]*\b(?P<c>_\w+)\b)",
    re.MULTILINE,
)


def _includes(path: Path) -> dict[str, Path]:
    """A C file's quoted includes, each found beside it, else in the shared folder (as gcc does)."""
    found = {}
    for name in INCLUDE.findall(path.read_text()):
        beside = path.parent / name
        found[name] = beside if beside.is_file() else SHARED / name
    return found


def _headers_reached(source: Path) -> set[Path]:
    """The headers a C file includes, directly or through other headers (quoted includes)."""
    seen: set[Path] = set()
    stack = [source]
    while stack:
        for header in _includes(stack.pop()).values():
            if header not in seen:
                seen.add(header)
                stack.append(header)
    return seen


def _module_path(module: str) -> str:
    """``kin.ik.targets._pose_check`` -> ``ik/targets/_pose_check``: the module's path below ``kin``."""
    return module.removeprefix("kin.").replace(".", "/")


def test_every_c_file_of_the_package_sits_in_the_native_folder():
    """No C source or header in kin/ outside kin/_native/, and the folder holds one .c per twin."""
    outside = [
        str(p.relative_to(SITE))
        for p in (SITE / "kin").rglob("*")
        if p.suffix in {".c", ".h"} and NATIVE not in p.parents
    ]
    assert outside == []
    assert len(list(NATIVE.rglob("*.c"))) == len(EXTENSIONS) == len(TWINS) >= 9


@pytest.mark.parametrize("name", sorted(TWINS))
def test_each_twin_s_source_sits_where_its_module_does(name):
    """kin.a.b._x is built from kin/_native/a/b/_x.c, and the Python package a.b exists."""
    module = TWINS[name]
    ext = EXTENSIONS[module]
    assert ext["sources"] == [f"kin/_native/{_module_path(module)}.c"], f"{name=}"
    assert Path(ext["sources"][0]).stem == name == module.rsplit(".", 1)[1], f"{name=}"
    assert (SITE / "kin" / Path(_module_path(module)).parent / "__init__.py").is_file()


@pytest.mark.parametrize("name", sorted(EXTENSIONS))
def test_each_extension_depends_on_exactly_the_headers_it_reaches(name):
    """setup.py's depends are the headers its source reaches, every include is found, optional."""
    ext = EXTENSIONS[name]
    (source,) = ext["sources"]
    reached = _headers_reached(SITE / source)
    assert all(h.is_file() for h in reached), f"{name=} includes a missing header"
    assert {SITE / d for d in ext["depends"]} == reached, f"{name=}"
    assert ext["include_dirs"] == ["kin/_native/include"] and ext["optional"] is True


def test_every_file_of_the_folder_is_built_or_included():
    """Each .c is one extension's source, each .h is included by some source: no stray file."""
    sources = {SITE / ext["sources"][0] for ext in EXTENSIONS.values()}
    assert set(NATIVE.rglob("*.c")) == sources
    included = set().union(*(_headers_reached(s) for s in sources))
    assert set(NATIVE.rglob("*.h")) == included


def test_a_header_sits_beside_its_twins_or_in_the_shared_folder():
    """A header of one folder's twins sits in that folder; include/ holds those folders share."""
    users: dict[Path, set[Path]] = {}
    for ext in EXTENSIONS.values():
        source = SITE / ext["sources"][0]
        for header in _headers_reached(source):
            users.setdefault(header, set()).add(source.parent)
    for header, folders in users.items():
        expected = folders.pop() if len(folders) == 1 else SHARED
        assert header.parent == expected, f"{header.relative_to(NATIVE)} used from {folders}"
    assert {h.name for h in SHARED.glob("*.h")} == {"_results.h", "_twin.h"}


def test_the_loader_knows_exactly_the_declared_extensions():
    """The loader's table is the one setup.py builds from, and each twin has its parity test."""
    assert sorted(TWINS.values()) == sorted(EXTENSIONS)
    assert sorted(PARITY_TESTS) == sorted(TWINS)


@pytest.mark.parametrize("name", sorted(TWINS))
def test_the_loader_finds_each_twin_when_built(name, monkeypatch):
    """Built (a compiled file importlib finds): the loader returns it; else None with the reason."""
    monkeypatch.delenv(PURE_PYTHON_VARIABLE, raising=False)
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
    monkeypatch.delenv(PURE_PYTHON_VARIABLE, raising=False)
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
