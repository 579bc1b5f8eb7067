"""The default run leaves out the marked tests, CI runs them, and the peers' tests carry `peer`.

The markers' rule is pyproject's ``addopts`` (``-m "not slow and not peer and not browser"``);
``.ci/run`` runs the README's command and then the complement, and the wheel runs everything.
The peer check reads the test files' syntax trees (no test is imported or run).
"""

from __future__ import annotations

import ast
import itertools
import re
import shlex
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
PYTEST = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["pytest"][
    "ini_options"
]
CI = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
MARKERS = ("slow", "peer", "browser")
#: The libraries the benchmarks compare with: a test that imports one is a peer test.
PEERS = {"ssik", "pytracik", "eaik", "roboticstoolbox", "trac_ik", "ur_analytic_ik"}


def default_expression() -> str:
    """The ``-m`` expression of pyproject's addopts."""
    args = PYTEST["addopts"]
    args = shlex.split(args) if isinstance(args, str) else list(args)
    return args[args.index("-m") + 1]


def selects(expression: str, marks: set[str]) -> bool:
    """Whether a test with ``marks`` is selected by a -m expression of names, not, and, or."""
    assert re.fullmatch(r"[\w\s()]*", expression), expression
    names = {name: name in marks for name in re.findall(r"\w+", expression)}
    names = {k: v for k, v in names.items() if k not in {"not", "and", "or"}}
    return bool(eval(expression, {"__builtins__": {}}, names)) if expression else True


def test_the_three_markers_are_registered():
    """slow, peer and browser are declared (an unknown marker would only warn)."""
    registered = {line.split(":")[0].strip() for line in PYTEST["markers"]}
    assert set(MARKERS) <= registered, registered


def test_the_default_run_and_ci_together_run_every_test_once():
    """For every combination of the three markers, exactly one of the README's command and
    .ci/run's second command selects the test; the wheel runs select all."""
    lines = [line.strip() for line in CI.splitlines()]
    assert ".venv/bin/python -m pytest" in lines
    second = [line for line in lines if line.startswith(".venv/bin/python -m pytest -m ")]
    assert len(second) == 1, second
    ci_expression = shlex.split(second[0])[-1]
    default = default_expression()
    for k in range(len(MARKERS) + 1):
        for marks in itertools.combinations(MARKERS, k):
            chosen = (selects(default, set(marks)), selects(ci_expression, set(marks)))
            assert sum(chosen) == 1, f"{marks=} {chosen=}"
    wheel = [line for line in lines if line.startswith('"$venv" -m pytest')]
    assert wheel and all(shlex.split(line.split("#")[0])[-2:] == ["-m", ""] for line in wheel)


def _marks(node: ast.FunctionDef) -> set[str]:
    """The pytest.mark.<name> decorators of a test function."""
    names = set()
    for decorator in node.decorator_list:
        target = decorator.func if isinstance(decorator, ast.Call) else decorator
        if isinstance(target, ast.Attribute) and ast.unparse(target).startswith("pytest.mark."):
            names.add(target.attr)
    return names


def _imported(node: ast.FunctionDef) -> set[str]:
    """Top-level module names the function imports or asks pytest.importorskip for."""
    names = set()
    for inner in ast.walk(node):
        if isinstance(inner, ast.Import):
            names |= {alias.name.split(".")[0] for alias in inner.names}
        elif isinstance(inner, ast.ImportFrom) and inner.module:
            names.add(inner.module.split(".")[0])
        elif (
            isinstance(inner, ast.Call)
            and ast.unparse(inner.func) == "pytest.importorskip"
            and isinstance(inner.args[0], ast.Constant)
        ):
            names.add(str(inner.args[0].value).split(".")[0])
    return names


def test_tests_that_import_a_peer_are_marked_peer():
    """Every test function that imports a peer library (or skips without it) carries `peer`."""
    unmarked, counted = [], 0
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.FunctionDef) and node.name.startswith("test_"):
                if _imported(node) & PEERS:
                    counted += 1
                    if "peer" not in _marks(node):
                        unmarked.append(f"{path.name}::{node.name}")
    assert counted >= 5, counted  # the check sees the peer tests at all
    assert not unmarked, unmarked


def test_the_check_reads_marks_and_imports():
    """The two readers above on a small source: a marked peer test and an unmarked one."""
    source = (
        "@pytest.mark.peer\n@pytest.mark.parametrize('a', [1])\n"
        "def test_a(a):\n    ssik = pytest.importorskip('ssik')\n\n"
        "def test_b():\n    from trac_ik.x import y\n"
    )
    first, second = ast.parse(source).body
    assert (_marks(first), _imported(first)) == ({"peer", "parametrize"}, {"ssik"})
    assert (_marks(second), _imported(second)) == (set(), {"trac_ik"})
