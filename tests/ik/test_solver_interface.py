"""One solver interface, no proxies, no towers (issue 46 items 1, 2 and 4).

- Every solver the solver table can build (each row of :data:`kin.ik.solver_table.SOLVERS` on
  arms it fits, each choice of the library's and the commands' front ends, and each of them
  wrapped by the collision checker) satisfies :class:`kin.ik.solver.IKSolver` (runtime check of
  its members) and takes the interface's keywords (``timeout``, ``all_branches``) by name: the
  signature is read here, by the test, so that no caller has to.
- No class of ``kin/`` defines ``__getattr__`` (module-level lazy loaders are functions, not
  classes), but :class:`kin.ik.result.IKSolution`, whose compiled twins leave its ``reason`` slot
  unset (a default, not a proxy: it forwards nothing).
- No project class hierarchy deeper than two project classes: tests/house/test_class_depth.py.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

import kin
from kin import load_robot
from kin.commands.solver_choice import COMMAND, choose_solver
from kin.ik import PositionTarget
from kin.ik.solver import IKSolver
from kin.ik.solver_table import CHOICES, FRONT_ENDS, SOLVERS, choose, with_collisions

#: Arms that cover every row: a closed form with a compiled twin (ur5), a small closed form
#: (planar2), a five-joint closed form (lab5), a 7R arm with a free-joint closed form
#: (humanoid7).
ARMS = ("ur5", "planar2", "lab5", "humanoid7")

#: Classes allowed a ``__getattr__`` (``module:class``), each with its reason.
GETATTR_ALLOWED: dict[str, str] = {}


def _solvers() -> list[tuple[str, object]]:
    """``(label, solver)`` of every row, library choice and command choice on :data:`ARMS`."""
    from kin.ik.exceptions import StructureError

    built = []
    for arm in ARMS:
        robot = load_robot(arm)
        for name, row in SOLVERS.items():
            try:
                built.append((f"{arm}:row:{name}", row.build(robot, False)))
            except StructureError:
                continue
        for front in (*FRONT_ENDS.values(), COMMAND):
            for choice in front.choices:
                try:
                    solver = choose(robot, choice, choices=front.choices)
                except StructureError:
                    continue
                built.append((f"{arm}:{front.name}:{choice}", solver))
    return built


def _project_modules() -> list[object]:
    modules = []
    for info in pkgutil.walk_packages(kin.__path__, "kin."):
        if info.name.endswith("__main__"):
            continue
        try:
            modules.append(importlib.import_module(info.name))
        except ImportError:  # an optional extra (a viewer's) not installed
            continue
    return modules


def _project_classes() -> list[type]:
    seen: dict[str, type] = {}
    for module in _project_modules():
        for value in vars(module).values():
            if inspect.isclass(value) and value.__module__ == module.__name__:  # type: ignore[attr-defined]
                seen[f"{value.__module__}:{value.__qualname__}"] = value
    return list(seen.values())


@pytest.mark.parametrize(("label", "solver"), _solvers(), ids=lambda value: str(value)[:40])
def test_every_solver_of_the_table_satisfies_the_interface(label, solver):
    assert isinstance(solver, IKSolver), label
    parameters = inspect.signature(solver.solve).parameters
    for keyword in ("timeout", "all_branches"):
        assert parameters[keyword].kind is inspect.Parameter.KEYWORD_ONLY, (label, keyword)
    assert isinstance(solver.name, str) and solver.name, label
    assert all(isinstance(kind, type) for kind in solver.target_kinds), label
    route = solver.batch_route()
    assert route is None or route.closed is not None, label


def test_the_collision_wrapper_satisfies_the_interface_and_has_no_batch_route():
    from kin.collision import CollisionChecker, load_collision_model

    robot = load_robot("ur5")
    checker = CollisionChecker(load_collision_model(robot))
    for solver in (
        choose(robot, "auto", collisions=checker),
        choose_solver(robot, "mink", collisions=checker, every=True),
        with_collisions(choose(robot, "numeric"), checker),
    ):
        assert isinstance(solver, IKSolver)
        assert solver.batch_route() is None
        result = solver.solve(PositionTarget([0.4, 0.1, 0.3]), None, timeout=2.0)
        assert result.solver == solver.name


def test_the_numeric_solver_gives_its_batch_route_through_the_interface():
    """A 7R arm with a free-joint closed form gives its route; a closed-form arm's table none."""
    humanoid7 = choose(load_robot("humanoid7"), "auto")
    route = humanoid7.batch_route()
    assert route is not None and route.steps == tuple(humanoid7.settings.closed_form_steps)  # type: ignore[attr-defined]
    assert choose(load_robot("ur5"), "auto").batch_route() is None
    assert choose(load_robot("ur5"), "numeric").batch_route() is None  # no free joint


def test_the_library_table_holds_no_command_line_names():
    """``mink`` is the commands' name (kin.commands.solver_choice), not the library's."""
    assert "mink" not in CHOICES and "command" not in FRONT_ENDS
    assert set(COMMAND.choices) == {"auto", "mink", "nr"}
    assert choose(load_robot("planar2"), "auto").solve(PositionTarget([0.4, 0.1, 0.0])).success


def test_no_class_forwards_attributes_with_getattr():
    found = {
        f"{cls.__module__}:{cls.__qualname__}"
        for cls in _project_classes()
        if "__getattr__" in vars(cls)
    }
    assert found <= set(GETATTR_ALLOWED), sorted(found - set(GETATTR_ALLOWED))
