"""No module of tests/ imports a test module (issue 46 item 5).

A helper that two test modules share lives in a support module (``cli_helper.py``,
``plan_support.py``...) or, for a fixture, in ``conftest.py``: a test module imported by another
runs its module-level code twice, and moving or renaming it breaks the other. Every import counts,
the function-local ones too; a test module importing itself (to run a check in a subprocess) is
not another.
"""

from __future__ import annotations

import ast
from pathlib import Path

TESTS = Path(__file__).parent


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
        found += [name for name in names if name.startswith("test_") and name != module]
    return found


def test_no_module_of_tests_imports_a_test_module():
    """Every module of tests/ takes shared helpers from support modules, none from a test module."""
    found = {
        path.name: imported
        for path in sorted(TESTS.glob("*.py"))
        if (imported := imported_test_modules(path.read_text(encoding="utf-8"), path.stem))
    }
    assert found == {}, f"move the shared helpers into a support module or conftest.py: {found}"


def test_the_check_sees_every_kind_of_import():
    """The check itself: module-level and function-local imports of a test module, not itself."""
    source = (
        "import test_a\nimport os, test_b\nfrom test_c import x\nfrom plan_support import y\n"
        "def f():\n    from test_d import z\n    from test_self import w\n"
    )
    assert imported_test_modules(source, "test_self") == ["test_a", "test_b", "test_c", "test_d"]
