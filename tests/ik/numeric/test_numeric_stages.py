"""The numeric pipeline as stages over a context (issue #20): no import circle, the seed checked
once, the stages an ordered list that can be changed."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest
from support.solver_caps import NO_CAP

from kin import Configuration, load_robot
from kin.ik import NumericIK, PoseTarget
from kin.ik.numeric.search import Stage
from kin.ik.numeric.starts import solve_from_starts

#: The installed package's numeric stages (sources in an editable install, site-packages from a wheel).
NUMERIC = Path(solve_from_starts.__code__.co_filename).resolve().parent


def _imports(path: Path) -> set[str]:
    """The sibling modules ``path`` imports (``from .x import``, ``from . import x``), typing too."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                found.add(node.module.split(".")[0])
            else:
                found.update(alias.name for alias in node.names)
    return found


def test_numeric_modules_import_no_circle():
    """The graph of kin/ik/numeric's imports of each other (TYPE_CHECKING ones included) has no
    cycle: a depth-first search finds no back edge."""
    graph = {path.stem: _imports(path) for path in NUMERIC.glob("*.py")}
    assert {"solver", "search", "starts", "restarts"} <= set(graph), NUMERIC  # not vacuous
    state: dict[str, int] = {}

    def visit(module: str, trail: list[str]) -> None:
        state[module] = 1
        for other in graph.get(module, ()):
            if state.get(other) == 1:
                raise AssertionError(f"import circle: {' -> '.join([*trail, module, other])}")
            if other in graph and not state.get(other):
                visit(other, [*trail, module])
        state[module] = 2

    for module in graph:
        if not state.get(module):
            visit(module, [])
    assert "solver" not in set().union(*(graph[m] for m in graph if m != "__init__"))


@pytest.fixture(scope="module")
def humanoid7():
    return load_robot("humanoid7")


def _pose(robot, q):
    pose = Configuration(robot).fk(np.asarray(q, dtype=float))
    return PoseTarget(pose.translation, pose.rotation)


def test_the_seed_is_checked_once_per_solve(humanoid7, monkeypatch):
    """Whichever stages run, the caller's seed is made a joint vector once, then handed down."""
    solver = NumericIK(humanoid7, closed_form=False)
    calls = []
    original = solver.seed_vector
    monkeypatch.setattr(solver, "seed_vector", lambda seed: calls.append(1) or original(seed))
    rng = np.random.default_rng(3)
    for _ in range(10):
        q = rng.uniform(humanoid7.lower, humanoid7.upper)
        calls.clear()
        result = solver.solve(_pose(humanoid7, q), list(q + 0.3), timeout=NO_CAP)
        assert result.success
        assert len(calls) == 1


def test_the_pipeline_is_an_ordered_list_of_stages(humanoid7):
    """The default stages, in order; a solver given the seed-table stage alone still solves, its
    answers named by that stage (or a failure, never another stage's answer)."""
    solver = NumericIK(humanoid7)
    names = [stage.name for stage in solver.stages]
    assert names == ["closed_form_free_joint", "seed_table", "random_restart", "mink_qp"]
    solver.stages = (Stage("seed_table", solve_from_starts),)
    rng = np.random.default_rng(4)
    methods = set()
    for _ in range(20):
        q = rng.uniform(humanoid7.lower, humanoid7.upper)
        result = solver.solve(_pose(humanoid7, q), timeout=0.2)
        methods.add(result.method if result.success else "")
    assert methods <= {"seed_table", "damped_newton", ""} and "seed_table" in methods


def test_building_a_numeric_solver_without_closed_form_imports_mink():
    """mink's import (about 0.3 s) is paid when such a solver is built, not by the first call
    that falls back to a QP run (issue 47 item 1); with a free-joint closed form it waits, and
    so does a numeric solver a closed form builds inside a call (no 0.3 s inside that call)."""
    import subprocess
    import sys

    code = (
        "import sys\n"
        "from kin import load_robot\n"
        "from kin.ik import NumericIK\n"
        "NumericIK(load_robot('humanoid7'))\n"
        "print('mink' in sys.modules)\n"
        "from kin.ik import PositionTarget, get_solver\n"
        "ur5 = get_solver(load_robot('ur5'))\n"  # a closed form: its numeric solver built in a call
        "print(ur5.solve(PositionTarget([1.0, 2.0, 3.0])).status, 'mink' in sys.modules)\n"
        "NumericIK(load_robot('ur5'), closed_form=False)\n"
        "print('mink' in sys.modules)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.split()
    assert out == ["False", "out_of_reach", "False", "True"]
