"""The routes: which part of a solver answers each target kind, decided once (issue 46, item 1).

Two checks. The route tables of :mod:`kin.ik.routing` against what is known of each arm, written
here by hand (a UR5's pose goes to its compiled twin, a five-joint arm's closed form takes whole
poses, a planar 2R's closed form solves positions only, a SCARA's projects poses, ...). And each
solver against its own table: every part a route names is replaced by a spy, and a solve must
call exactly the part its route names (the partial-pose solver after the branches for
``BRANCHES``), no other.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from kin import load_robot
from kin._native import twin
from kin.collision import CollisionChecker, load_collision_model
from kin.ik import AxisTarget, PitchTarget, PoseTarget, PositionTarget
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.numeric.numeric_target import NumericTarget
from kin.ik.result import IKResult
from kin.ik.routing import BRANCHES, CLOSED, NUMERIC, PARTIAL, REFUSED, SHORT, TWIN
from kin.ik.solver_table import SOLVERS, with_collisions

ROOT = Path(__file__).resolve().parents[2]
P, R = [0.3, 0.1, 0.2], np.eye(3)
#: One target of each kind (a masked pose apart), in the order of the tables below.
TARGETS = {
    "position": PositionTarget(P),
    "pose": PoseTarget(P, R),
    "masked": PoseTarget(P, R, mask=(1, 1, 1, 0, 0, 1)),
    "axis": AxisTarget(P, [0.0, 0.0, 1.0]),
    "pitch": PitchTarget(P, 0.3),
    "numeric": NumericTarget.from_arrays(P, R),
}
T, C, B, S, A, N, X = TWIN, CLOSED, BRANCHES, SHORT, PARTIAL, NUMERIC, REFUSED
#: The UR wrist's compiled twin is built (not under DH_KINEMATICS_PURE_PYTHON=1, or without a C
#: compiler): a UR5's pose goes to it.
UR_TWIN = twin("_three_parallel") is not None
#: (arm, solver row, compiled twin) -> routes of position, pose, masked, axis, pitch, numeric.
EXPECTED = {
    # a 6R UR wrist: poses in its twin (or the Python closed form), a position is redundant
    ("ur5", "closed_form", True): (N, T if UR_TWIN else C, A, A, X, X),
    ("ur5", "closed_form", False): (N, C, A, A, X, X),
    # a five-joint closed form takes whole poses (its own reasons) and a pitch
    ("lab5", "closed_form", True): (N, C, A, A, C, X),
    # position-only closed forms (2R, offset 3R): a pose on their branches first
    ("planar2", "closed_form", True): (C, B, A, A, X, X),
    ("pickplace3", "closed_form", True): (C, B, A, A, X, X),
    # a SCARA's closed form projects a pose on what the arm reaches
    ("examples/cobra600.toml", "closed_form", True): (C, B, A, A, X, X),
    # the numeric pipeline: a whole pose on fewer than six joints is a partial pose's
    ("humanoid7", "numeric", True): (N, N, A, A, X, N),
    ("lab5", "numeric", True): (N, S, A, A, X, N),
    # the paper's Newton-Raphson: positions only
    ("ur5", "nr", True): (N, X, X, X, X, X),
}


def _solver(arm: str, row: str, compiled: bool):
    robot = load_robot(ROOT / arm if "/" in arm else arm)
    if row == "closed_form":
        return ClosedFormSolver(robot, compiled=compiled)
    return SOLVERS[row].build(robot, False)


@pytest.mark.parametrize("case", sorted(EXPECTED), ids=lambda case: "-".join(map(str, case)))
def test_each_solvers_routes_are_the_arms(case):
    solver = _solver(*case)
    got = tuple(solver.route(target) for target in TARGETS.values())
    assert got == EXPECTED[case], dict(zip(TARGETS, got))
    taken = [kind for kind, route in zip(TARGETS, got) if route is not REFUSED]
    assert {type(TARGETS[kind]) for kind in taken} <= set(solver.target_kinds), case


def test_the_collision_wrapper_routes_as_its_solver():
    robot = load_robot("ur5")
    inner = ClosedFormSolver(robot)
    aware = with_collisions(inner, CollisionChecker(load_collision_model(robot)))
    for target in TARGETS.values():
        assert aware.route(target) is inner.route(target)


class _Called(Exception):
    """A spy was called (its part's name)."""


def _spy(part: str, calls: list[str], answer=None):
    def spy(*args, **kwargs):
        calls.append(part)
        if answer is _Called:
            raise _Called(part)
        return answer

    return spy


#: What each route calls, as the spies below name them.
CALLS = {
    TWIN: ["twin"],
    CLOSED: ["closed"],
    BRANCHES: ["branches", "partial"],
    SHORT: ["partial"],
    PARTIAL: ["partial"],
    NUMERIC: ["numeric"],
}


@pytest.mark.parametrize(
    "case",
    [case for case in sorted(EXPECTED) if case[1] != "nr"],
    ids=lambda case: "-".join(map(str, case)),
)
def test_a_solve_calls_the_part_its_route_names(case, monkeypatch):
    solver = _solver(*case)
    calls: list[str] = []
    done = IKResult(False, "spy", "not_found", "a spy's answer")
    monkeypatch.setattr(solver.partial, "solve", _spy("partial", calls, done))
    if isinstance(solver, ClosedFormSolver):
        monkeypatch.setattr(solver, "_solutions", _spy("twin", calls, done))
        monkeypatch.setattr(solver, "_solve_closed", _spy("closed", calls, done))
        monkeypatch.setattr(solver.handlers, "pose_from_branches", _spy("branches", calls))
        monkeypatch.setattr(solver.handlers, "solve_numeric", _spy("numeric", calls, done))
    else:
        monkeypatch.setattr(solver, "_solve", _spy("numeric", calls, done))
    for kind, target in TARGETS.items():
        calls.clear()
        route = solver.route(target)
        if route is REFUSED:
            with pytest.raises(Exception, match="takes a"):
                solver.solve(target, None)
            assert calls == [], (case, kind)
            continue
        solver.solve(target, None)
        assert calls == CALLS[route], (case, kind, route)
