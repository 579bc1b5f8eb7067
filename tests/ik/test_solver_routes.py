"""Which part of a solver answers what, asked through the interface (issue 46 item 1).

The paths, the collision search and the reachability map ask a solver its
``closed_form_kinds``, ``numeric`` and ``partial`` (:class:`kin.ik.solver.IKSolver`) instead
of which class it is. Checked here: each solver of the table states them as its class does its
work (a closed form's kinds are its structure's, its numeric solver is a ``NumericIK`` of the same
robot; the numeric solver is its own; Newton-Raphson has none; the collision wrapper states its
solver's), and no module of ``kin/`` asks ``isinstance`` of a solver class.
"""

from __future__ import annotations

import ast
from pathlib import Path

import kin
from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.ik import NumericIK, PoseTarget, PositionTarget
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.partial_pose import PartialPoseIK
from kin.ik.solver_table import SOLVERS, with_collisions

#: The solver classes no module may test a solver against.
SOLVER_CLASSES = {
    "ClosedFormSolver",
    "NumericIK",
    "NewtonRaphsonSolver",
    "CollisionAwareSolver",
    "MimicSolver",
}


def test_a_closed_form_states_its_structure_kinds_and_its_numeric_solver():
    robot = load_robot("ur5")
    solver = SOLVERS["closed_form"].build(robot, False)
    assert isinstance(solver, ClosedFormSolver)
    assert solver.closed_form_kinds == tuple(solver.structure.target_kinds)
    assert PoseTarget in solver.closed_form_kinds
    numeric = solver.numeric
    assert isinstance(numeric, NumericIK) and numeric.robot is robot
    assert numeric.closed_form_kinds == () and numeric.numeric is numeric
    assert isinstance(solver.partial, PartialPoseIK)
    assert solver.partial is not numeric.partial  # the closed form's takes its branches


def test_the_numeric_solver_is_its_own_and_newton_raphson_has_none():
    robot = load_robot("humanoid7")
    numeric = SOLVERS["numeric"].build(robot, False)
    assert numeric.closed_form_kinds == ()
    assert numeric.numeric is numeric
    assert numeric.partial is numeric.partial is not None
    nr = SOLVERS["nr"].build(robot, False)
    assert nr.closed_form_kinds == () and nr.numeric is None and nr.partial is None
    assert PositionTarget in nr.target_kinds


def test_the_collision_wrapper_states_its_solvers_parts():
    robot = load_robot("ur5")
    inner = SOLVERS["closed_form"].build(robot, False)
    aware = with_collisions(inner, CollisionChecker(load_collision_model(robot)))
    assert aware is not inner
    assert aware.closed_form_kinds == inner.closed_form_kinds
    assert aware.numeric is inner.numeric
    assert aware.partial is inner.partial


def test_no_module_asks_which_solver_class_a_solver_is():
    root = Path(kin.__file__).parent
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if not (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Name)
                and node.func.id == "isinstance"
                and len(node.args) == 2
            ):
                continue
            kinds = node.args[1]
            names = kinds.elts if isinstance(kinds, ast.Tuple) else [kinds]
            for name in names:
                label = name.id if isinstance(name, ast.Name) else getattr(name, "attr", "")
                if label in SOLVER_CLASSES:
                    found.append(f"{path.relative_to(root.parent)}:{node.lineno} {label}")
    assert not found, found


def test_only_the_solver_table_wraps_a_solver_in_the_collision_checker():
    """``with_collisions`` is the one place that builds the collision-aware solver."""
    root = Path(kin.__file__).parent
    table = root / "ik" / "solver_table.py"
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Call):
                func = node.func
                name = func.id if isinstance(func, ast.Name) else getattr(func, "attr", "")
                if name == "CollisionAwareSolver" and path != table:
                    found.append(f"{path.relative_to(root.parent)}:{node.lineno}")
    assert not found, found
