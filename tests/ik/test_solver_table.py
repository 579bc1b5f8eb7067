"""The solver table (kin.ik.solver_table) and the closed-form registry's precedence: the same arms
get the same solvers as before the table, every front end reads it, and the docs' worked example
of adding a closed form runs."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from support.urdf_reference import ARMS, erd

from dh2urdf import ROBOTS
from kin import load_robot
from kin.commands.solver_choice import COMMAND, choose_solver
from kin.ik import IKError, PoseTarget, PositionTarget, StructureError, get_solver, solve_batch
from kin.ik.analytic import registry
from kin.ik.solver_table import (
    CHOICES,
    FRONT_ENDS,
    SOLVERS,
    choose,
    front_end_solver,
    vectorized_solver,
)
from kin.path import PathError, path_solver

DOCS = Path(__file__).resolve().parents[2] / "docs" / "adding-a-closed-form.md"

# Recorded by hand from the output of the code before the solver table (commit 8b6147a, where
# get_solver, the CLI's if-chain, path_solver and batch_solve each chose on their own): robot ->
# (get_solver's class, its structure class or None, the batch's vectorized structure name for
# poses, for positions). The refactor is checked against this old behaviour.
BEFORE = {
    "humanoid7": ("NumericIK", None, None, None),
    "lab5": ("ClosedFormSolver", "FiveDof", "fivedof", None),
    "ned5": ("ClosedFormSolver", "FiveDof", "fivedof", None),
    "panda": ("NumericIK", None, None, None),
    "pickplace3": ("ClosedFormSolver", "Offset3R", None, "offset3r"),
    "planar2": ("ClosedFormSolver", "Planar2R", None, "planar2r"),
    "puma560": ("ClosedFormSolver", "SphericalWrist6R", "spherical_wrist", None),
    "scorbot": ("ClosedFormSolver", "FiveDof", "fivedof", None),
    "ur10": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "ur3": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "ur5": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "xarm7": ("NumericIK", None, None, None),
    "urdf:ur3": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "urdf:ur5": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "urdf:ur10": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "urdf:ur5_limited": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "urdf:panda": ("NumericIK", None, None, None),
    "urdf:xarm7": ("NumericIK", None, None, None),
    "urdf:kinova": ("ClosedFormSolver", "SphericalWrist6R", "spherical_wrist", None),
    "urdf:z1": ("ClosedFormSolver", "URWrist6R", "ur_wrist", None),
    "urdf:so100": ("ClosedFormSolver", "FiveDof", "fivedof", None),
    "urdf:so101": ("NumericIK", None, None, None),
    "urdf:baxter_left": ("NumericIK", None, None, None),
    "urdf:baxter_right": ("NumericIK", None, None, None),
    "urdf:tiago": ("NumericIK", None, None, None),
    "urdf:double_pendulum": ("ClosedFormSolver", "ParallelAxes2", "parallel_axes", "parallel_axes"),
    "urdf:asr_twodof": ("ClosedFormSolver", "Planar2R", None, "planar2r"),
}

#: The registry's order before the precedence field (the list CLOSED_FORMS, recorded by hand).
ORDER_BEFORE = (
    "Planar2R",
    "ParallelAxes2",
    "Offset3R",
    "ParallelAxes3",
    "Wrist3",  # added after the precedence field (45): a wrist alone, three axes through a point
    "ParallelAxes",
    "YawPlanar",
    "YawPlanarRoll",
    "FiveDof",
    "URWrist6R",
    "SphericalWrist6R",
    "Pieper6R",
    "ThreeParallel6R",
    "Reversed6R",
    "General6R",
)

#: A special case merged into its family (issue 34 item 3): the family is registered once, where
#: its first case stood, and its ``recognise`` gives the case (same answers, same name).
MERGED_INTO = {"URWrist6R": "ThreeParallel6R", "SphericalWrist6R": "Pieper6R"}


def _merged_order(order: tuple[str, ...]) -> tuple[str, ...]:
    """``order`` with each merged case named by its family, each family at its first place."""
    out: list[str] = []
    for name in order:
        name = MERGED_INTO.get(name, name)
        if name not in out:
            out.append(name)
    return tuple(out)


def _load(name: str):
    if name.startswith("urdf:"):
        relative, base, tip = ARMS[name[5:]]
        return load_robot(erd(relative), base, tip)
    return load_robot(name)


def _structure_name(solver) -> str | None:
    structure = getattr(solver, "structure", None)
    return None if structure is None else type(structure).__name__


def _vectorized_name(robot, kind) -> str | None:
    batch = vectorized_solver(robot, kind)
    return None if batch is None else batch.structure.name


def test_every_robot_is_recorded():
    """The recorded mapping covers every shipped robot and every example-robot-data arm."""
    assert set(BEFORE) == set(ROBOTS) | {f"urdf:{arm}" for arm in ARMS}


@pytest.mark.parametrize("name", list(BEFORE))
def test_same_solver_as_before_the_table(name):
    """get_solver, kin ik, paths and batches give each arm the solver they gave before."""
    robot = _load(name)
    kind, structure, poses, positions = BEFORE[name]
    solver = get_solver(robot)
    assert (type(solver).__name__, _structure_name(solver)) == (kind, structure), f"{name=}"
    if structure is not None:
        assert solver.name == f"closed_form:{solver.structure.name}", f"{name=}"
    command = choose_solver(robot)
    path = path_solver(robot)
    for other in (command, path):
        assert (type(other).__name__, _structure_name(other)) == (kind, structure), f"{name=}"
    assert type(choose_solver(robot, "mink")).__name__ == "NumericIK", f"{name=}"
    assert type(choose_solver(robot, "nr")).__name__ == "NewtonRaphsonSolver", f"{name=}"
    assert _vectorized_name(robot, PoseTarget) == poses, f"{name=}"
    assert _vectorized_name(robot, PositionTarget) == positions, f"{name=}"


def test_registry_order_is_the_old_list_order():
    """The precedences order the shipped structures as the old list did (merged cases named by
    their families); CLOSED_FORMS follows."""
    precedences = [entry.precedence for entry in registry.SHIPPED]
    assert precedences == sorted(precedences)
    assert len(set(precedences)) == len(precedences)
    names = tuple(entry.structure.__name__ for entry in registry.SHIPPED)
    assert names == _merged_order(ORDER_BEFORE)
    assert [entry.structure for entry in registry.entries()] == registry.CLOSED_FORMS
    assert registry.SHIPPED[-1].structure.__name__ == "General6R"
    assert all(entry.why for entry in registry.SHIPPED)


def test_table_is_consistent():
    """Every front end's choice tries rows of SOLVERS; so does every choice of the table."""
    for front in (*FRONT_ENDS.values(), COMMAND):
        for choice, rows in front.choices.items():
            assert rows and set(rows) <= set(SOLVERS), (front.name, choice)
    for choice, rows in CHOICES.items():
        assert rows and set(rows) <= set(SOLVERS), choice
    for name, row in SOLVERS.items():
        assert row.name == name and row.answers


def test_near_seed_per_front_end():
    """The commands and paths get the numeric solver with near_seed; the library without."""
    robot = load_robot("humanoid7")
    assert choose_solver(robot).near_seed is True
    assert path_solver(robot).near_seed is True
    assert path_solver(robot, "differential").near_seed is True
    assert get_solver(robot).near_seed is False


def test_unknown_choice_names_the_choices():
    """An unknown choice raises IKError listing the valid ones; paths a PathError."""
    robot = load_robot("planar2")
    with pytest.raises(IKError, match=r"unknown solver 'qp'; choose one of: auto, closed_form"):
        choose(robot, "qp")
    with pytest.raises(IKError, match=r"choose one of: auto, mink, nr$"):
        front_end_solver(robot, COMMAND, "differential")
    with pytest.raises(PathError, match=r"choose one of: auto, closed_form, differential"):
        path_solver(robot, "mink")


def test_closed_form_choice_refuses_an_arm_without_one():
    """closed_form on a 7R arm: StructureError from the table, a PathError from paths."""
    robot = load_robot("panda")
    with pytest.raises(StructureError):
        choose(robot, "closed_form")
    with pytest.raises(PathError, match="'panda' has no closed-form solver"):
        path_solver(robot, "closed_form")


def test_register_checks_parts_and_precedence(monkeypatch):
    """A class without the protocol's parts is refused; a taken precedence is refused."""
    monkeypatch.setattr(registry, "_entries", list(registry._entries))
    monkeypatch.setattr(registry, "CLOSED_FORMS", list(registry.CLOSED_FORMS))
    with pytest.raises(TypeError, match="not a closed-form structure"):
        registry.register(type("Nothing", (), {}))
    toy = _toy_structure()
    with pytest.raises(ValueError, match="precedence 10 is Planar2R's"):
        registry.register(toy, precedence=10)
    assert registry.register(toy, first=True).precedence == 0
    assert registry.CLOSED_FORMS[0] is toy
    assert registry.register(toy).precedence == 0  # once only


def _docs_blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", DOCS.read_text(), flags=re.DOTALL)


def _toy_structure() -> type:
    namespace: dict = {}
    exec(compile(_docs_blocks()[0], str(DOCS), "exec"), namespace)  # noqa: S102 - our own docs
    return namespace["ToyPlanar2R"]


def test_docs_worked_example_adds_a_closed_form(monkeypatch):
    """The docs' toy 2R, registered at precedence 5, answers planar2 everywhere; its round trip
    against a NumPy DH product (the docs' test) passes; the registry is restored after."""
    monkeypatch.setattr(registry, "_entries", list(registry._entries))
    monkeypatch.setattr(registry, "CLOSED_FORMS", list(registry.CLOSED_FORMS))
    toy = _toy_structure()
    entry = registry.register(toy, precedence=5, why="the toy 2R, before the paper's planar 2R")
    assert registry.entries()[0] == entry
    robot = load_robot("planar2")
    assert get_solver(robot).name == "closed_form:toy_planar2r"
    assert path_solver(robot).name == "closed_form:toy_planar2r"
    assert _vectorized_name(robot, PositionTarget) == "toy_planar2r"
    exec(compile(_docs_blocks()[-1], str(DOCS), "exec"), {})  # noqa: S102 - the docs' test
    q = np.array([[0.4, -1.1], [-2.0, 0.7]])
    points = np.stack([_planar_point(robot, row) for row in q])
    batch = solve_batch(robot, points, seeds=q)
    assert batch.success.all()
    np.testing.assert_allclose(batch.q, q, atol=1e-9)
    other = load_robot("pickplace3")  # a 3-joint arm: the toy is not asked
    assert get_solver(other).name == "closed_form:offset3r"


def _planar_point(robot, q: np.ndarray) -> np.ndarray:
    """The tool point of a planar 2R arm (alpha = d = theta = 0) [m], by trigonometry."""
    a1, a2 = (row.a for row in robot.table.rows)
    return np.array(
        [
            a1 * np.cos(q[0]) + a2 * np.cos(q[0] + q[1]),
            a1 * np.sin(q[0]) + a2 * np.sin(q[0] + q[1]),
            0,
        ]
    )
