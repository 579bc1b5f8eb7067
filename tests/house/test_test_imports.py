"""No module of tests/ imports a test module; the test modules' names are unique (issue 46 item 5).

A helper that two test modules share lives in the ``support`` package (``tests/support/``:
``support.cli_helper``, ``support.plan_support``...) or, for a fixture, in ``conftest.py``: a test
module imported by another runs its module-level code twice, and moving or renaming it breaks the
other. Every import counts, the function-local ones too; a test module importing itself (to run a
check in a subprocess) is not another.

The test modules sit in folders that mirror the packages they test, without ``__init__.py`` files:
pytest's default ``prepend`` import mode imports each by its file name, so two test modules of one
name in two folders would clash ("import file mismatch"). ``tests/`` itself is on ``sys.path``
(it holds the top ``conftest.py``), so ``support`` is found from every folder.
"""

from __future__ import annotations

import ast
from collections import Counter
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
SUPPORT = TESTS / "support"


def python_files() -> list[Path]:
    """Every module below tests/ (data folders too: a stray module there counts), sorted."""
    return sorted(path for path in TESTS.rglob("*.py") if "__pycache__" not in path.parts)


def imported_test_modules(source: str, module: str) -> list[str]:
    """The ``test_*`` modules other than ``module`` that ``source`` imports (in order, repeated)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        else:
            continue
        found += [
            name
            for name in names
            if name.rpartition(".")[2].startswith("test_") and name.rpartition(".")[2] != module
        ]
    return found


def test_no_module_of_tests_imports_a_test_module():
    """Every module of tests/ takes shared helpers from ``support``, none from a test module."""
    found = {
        str(path.relative_to(TESTS)): imported
        for path in python_files()
        if (imported := imported_test_modules(path.read_text(encoding="utf-8"), path.stem))
    }
    assert found == {}, f"move the shared helpers into tests/support/ or conftest.py: {found}"


def test_test_module_names_are_unique():
    """No two test modules (or conftest-free helpers beside them) share a file name."""
    names = Counter(path.name for path in python_files() if path.name.startswith("test_"))
    assert [name for name, count in names.items() if count > 1] == []


def test_support_modules_sit_in_the_support_package():
    """Beside the test modules only ``conftest.py``; every shared helper is in ``tests/support/``,
    which holds no test module."""
    loose = [
        str(path.relative_to(TESTS))
        for path in python_files()
        if not path.name.startswith("test_")
        and path.name != "conftest.py"
        and SUPPORT not in path.parents
        and "data" not in path.relative_to(TESTS).parts
    ]
    assert loose == []
    assert sorted(path.name for path in SUPPORT.glob("test_*.py")) == []


def test_the_check_sees_every_kind_of_import():
    """The check itself: module-level and function-local imports of a test module, not itself."""
    source = (
        "import test_a\nimport os, test_b\nfrom test_c import x\nfrom support.plan_support import y\n"
        "def f():\n    from test_d import z\n    from test_self import w\n"
        "    from ik.test_e import v\n"
    )
    assert imported_test_modules(source, "test_self") == [
        "test_a",
        "test_b",
        "test_c",
        "test_d",
        "ik.test_e",
    ]
