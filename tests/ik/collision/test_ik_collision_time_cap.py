"""The time cap of the distance-bounded solve (kin/ik/collision/collision_bound.py) and of the
collision-aware search over it: checked inside a run too, a run it stops gives ``timeout`` (never
an answer), the time reported is the time the call took, and no cap that does not fire changes an
answer. A clock of the test's own (1 ms a reading) stops a run at a known step, whatever the
machine's speed or load; the real clock only checks the reported time against the call's own
measure, under a cap every machine reaches.
"""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from support.blocked_case import TIP, URDF, _blocked_case
from support.solver_caps import NO_CAP
from support.urdf_reference import erd

import kin
from kin.ik.collision import collision_bound
from kin.ik.collision.collision_aware import CollisionAwareSolver
from kin.ik.collision.collision_bound import DistanceBoundedIK
from kin.ik.numeric.solver import NumericIK


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    """(robot, target, seed, plain answer, checker): Panda, a box through the plain answer's forearm."""
    robot = kin.load_robot(erd(URDF), None, TIP)
    path, base, _ = robot.urdf_source
    panda = (robot, Path(path).read_text(encoding="utf-8"), Path(path), base)
    target, seed, answer, checker, _, _ = _blocked_case(panda, tmp_path_factory.mktemp("cap"))
    return robot, target, seed, answer, checker


class _Clock:
    """A clock that reads 1 ms later at every reading [s]."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        self.now += 1e-3
        return self.now


def test_the_cap_stops_a_run_between_steps(case, monkeypatch):
    """A cap of 5.5 readings: timeout after a few steps of the first run, not at its end."""
    robot, target, seed, answer, checker = case
    solver = DistanceBoundedIK(robot, checker)
    idle = solver.solve(target, [answer, seed])
    assert idle.status == "ok", idle.message
    first_run = solver.run(target, answer).iterations
    assert first_run > 5  # the idle run takes more steps than the cap lets it
    clock = _Clock()
    monkeypatch.setattr(collision_bound, "time", SimpleNamespace(perf_counter=clock))
    stopped = solver.solve(target, [answer, seed], timeout=0.0055)
    assert stopped.status == "timeout", stopped.message
    assert not stopped.solutions and stopped.rejected  # the run so far kept as the nearest
    # readings at 1 ms (the start: cap at 6.5 ms), 2 (before the first run), then one before
    # each step: 3, 4, 5 and 6 ms let four steps go, 7 ms stops the run
    assert stopped.iterations == 4
    assert stopped.time == pytest.approx(clock.now - 1e-3)  # the reported time is the clock's


def test_a_cap_that_does_not_fire_changes_no_answer(case):
    """No cap, or one far above the work's time: the same answer, steps and status."""
    robot, target, seed, answer, checker = case
    solver = DistanceBoundedIK(robot, checker)
    free = solver.solve(target, [answer, seed])
    capped = solver.solve(target, [answer, seed], timeout=NO_CAP)
    assert free.status == capped.status == "ok"
    assert free.iterations == capped.iterations
    np.testing.assert_array_equal(free.solutions[0].q, capped.solutions[0].q)


@pytest.mark.parametrize("cap", [0.0, 1e-4, 2e-3])
def test_collision_aware_tiny_cap_says_timeout(case, monkeypatch, cap):
    """A tiny cap on the collision-aware numeric call, on the test's clock (every module's
    ``time.perf_counter``): timeout, the reported time between the cap and the call's span."""
    robot, target, seed, answer, checker = case
    aware = CollisionAwareSolver(NumericIK(robot, closed_form=False), checker)
    aware.solve(target, answer, timeout=NO_CAP)  # warm: the seed table and the first loads
    clock = _Clock()
    monkeypatch.setattr(time, "perf_counter", clock)
    begin = clock()
    result = aware.solve(target, answer, timeout=cap)
    span = clock() - begin
    assert result.status == "timeout", f"{cap=}: {result.message}"
    assert not result.solutions
    assert cap <= result.time < span, f"{cap=}"


def test_collision_aware_zero_cap_reports_its_real_time(case):
    """A zero cap (every machine reaches it at the first check) on the real clock: timeout, the
    reported time within the call's own measure."""
    robot, target, seed, answer, checker = case
    aware = CollisionAwareSolver(NumericIK(robot, closed_form=False), checker)
    aware.solve(target, answer, timeout=NO_CAP)  # warm: the seed table and the first loads
    begin = time.perf_counter()
    result = aware.solve(target, answer, timeout=0.0)
    wall = time.perf_counter() - begin
    assert result.status == "timeout" and not result.solutions, result.message
    assert 0.0 <= result.time <= wall
    assert wall < 60.0  # a guard against a hang only: the cap is checked before every step


def test_the_bounded_solve_is_loaded_with_the_solver_not_in_a_capped_call():
    """Building a collision-aware solver imports the bounded solve (10-15 ms cold), not its first call."""
    code = (
        "import sys, kin\n"
        "from kin.collision import CollisionChecker, load_collision_model\n"
        "from kin.ik import get_solver\n"
        "name = 'kin.ik.collision.collision_bound'\n"
        "robot = kin.load_robot('humanoid7')\n"
        "checker = CollisionChecker(load_collision_model(robot))\n"
        "before = name in sys.modules\n"
        "get_solver(robot, collisions=checker)\n"
        "print(before, name in sys.modules)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert done.stdout.split() == ["False", "True"], done.stderr
