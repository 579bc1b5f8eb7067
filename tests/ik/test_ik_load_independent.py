"""The answer does not depend on the machine's load (issue 32 item 3, issue 42 item 1): the
numeric pipeline and the mimic solver bound their search by work (starts, steps), and the timeout
is only a cap.

A busy machine is played by a clock that moves a fixed step at each reading
(``time.perf_counter`` monkeypatched): the time a solver measures counts its readings, the work
done, and stands for a machine many times slower than this one, the same on every run whatever
the real machine's load. The reference is a run on the real clock, with fresh solvers both times
(their cold loads, the seed table and the MuJoCo model, fall inside the calls). Both runs are
compared under a cap that neither reaches (:data:`NO_CAP`: thousands of readings on the
played clock, minutes on the real one), so no cap a loaded machine can reach enters the
comparison; that a cap reached says ``timeout`` is tested apart, on the played clock.
"""

from __future__ import annotations

import itertools
import re
import sys
import time
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.solver_caps import NO_CAP

from kin import Configuration, load_robot
from kin.ik import PoseTarget, PositionTarget
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.numeric.search import MAX_ATTEMPTS
from kin.ik.numeric.solver import DEFAULT_TIMEOUT, NumericIK
from kin.mimic.arm import load_mimic_arm
from kin.mimic.solver import DEFAULT_TIMEOUT as MIMIC_TIMEOUT
from kin.mimic.solver import MimicSolver

sys.path.insert(0, str(Path(__file__).parents[1]))
from support.mimic_reference import _urdf  # noqa: E402  (the mimic 6R arm of the mimic tests)

# NO_CAP (600 s) is 60,000 readings of NUMERIC_STEP and 6,000 of MIMIC_STEP; a call here takes
# under 2,000: no run here reaches it.

#: The played clock's step per reading for the numeric pipeline [s]: its longest calls here (over
#: a thousand readings, well under a second on an idle machine) seem to take over ten seconds.
NUMERIC_STEP = 0.01

#: The played clock's step for the mimic solver [s]: it reads the clock once per start (41 at
#: most), so its longest calls seem to take about four seconds.
MIMIC_STEP = 0.1


@contextmanager
def ticking_clock(monkeypatch: pytest.MonkeyPatch, step: float):
    """``time.perf_counter`` that moves ``step`` [s] at each reading, whatever the machine."""
    readings = itertools.count()
    origin = time.perf_counter()
    with monkeypatch.context() as patch:
        patch.setattr(time, "perf_counter", lambda: origin + step * next(readings))
        yield


def _answer(result) -> tuple:
    """What must not depend on the load: the verdict, the stage, every q (bit for bit)."""
    return (
        result.success,
        result.status,
        result.method,
        tuple(tuple(s.q.tolist()) for s in result.solutions),
        tuple(tuple(s.q.tolist()) for s in result.rejected),
    )


def _poses(name: str, count: int, seed: int, edge: bool = False) -> list[pin.SE3]:
    """Tool poses of random joint vectors inside the limits (``edge``: within 4 % of a limit)."""
    robot = load_robot(name)
    configuration = Configuration(robot)
    rng = np.random.default_rng(seed)
    span = robot.upper - robot.lower
    poses = []
    for _ in range(count):
        if edge:
            near = rng.uniform(0.0, 0.04, robot.nq) * span
            q = np.where(rng.integers(0, 2, robot.nq), robot.lower + near, robot.upper - near)
        else:
            q = rng.uniform(robot.lower, robot.upper)
        poses.append(configuration.fk(q))
    return poses


def _turned(pose: pin.SE3, rng: np.random.Generator) -> PoseTarget:
    """The pose's point with a random tool rotation (mostly not reachable: ``not_found``)."""
    return PoseTarget(pose.translation, pin.exp3(rng.normal(size=3)))


def _cases() -> list[tuple[str, Callable[[], object], object]]:
    """(solver's name, fresh solver, target): Panda's full poses and positions (free-joint closed
    form, then the stages), humanoid7's poses near the limits on the stages alone (restarts and
    QP runs), puma560's positions (a DH 6R arm whose closed form hands them to the numeric
    solver), and reached points with turned tools on each (the whole work, ``not_found``)."""
    rng = np.random.default_rng(32)
    cases: list[tuple[str, Callable[[], object], object]] = []

    def panda() -> NumericIK:
        return NumericIK(load_robot("panda"), prepare=False)

    def humanoid7() -> NumericIK:
        return NumericIK(load_robot("humanoid7"), closed_form=False, prepare=False)

    def puma560() -> ClosedFormSolver:
        return ClosedFormSolver(load_robot("puma560"))

    for pose in _poses("panda", 20, 1):
        cases.append(("panda", panda, PoseTarget(pose.translation, pose.rotation)))
    for pose in _poses("panda", 20, 2):
        cases.append(("panda", panda, PositionTarget(pose.translation)))
    for pose in _poses("panda", 3, 3):
        cases.append(("panda", panda, _turned(pose, rng)))
    for pose in _poses("humanoid7", 20, 4, edge=True):
        cases.append(("humanoid7", humanoid7, PoseTarget(pose.translation, pose.rotation)))
    for pose in _poses("humanoid7", 2, 5):
        cases.append(("humanoid7", humanoid7, _turned(pose, rng)))
    for pose in _poses("puma560", 15, 6):
        cases.append(("puma560", puma560, PositionTarget(pose.translation)))
    return cases


def _run(cases, **options) -> list:
    """Each case's answer, with one fresh solver per robot for the whole run."""
    solvers: dict[str, object] = {}
    answers = []
    for name, make, target in cases:
        if name not in solvers:
            solvers[name] = make()
        answers.append(solvers[name].solve(target, None, **options))  # type: ignore[attr-defined]
    return answers


def _same_or_capped(labels, idle, capped) -> int:
    """How many of ``capped`` the cap stopped (each says so); each other one is its ``idle``
    answer (``labels`` name the cases in a failure)."""
    stopped = 0
    for label, first, second in zip(labels, idle, capped, strict=True):
        if second.status == "timeout":  # the cap came first: allowed, and it says so
            assert "--timeout" in second.message and second.rejected, f"{label}: {second.message}"
            stopped += 1
        else:
            assert _answer(second) == _answer(first), f"{label}: {second.message}"
    return stopped


@pytest.mark.default_cap
def test_a_slow_machine_gets_the_answers_of_an_idle_one(monkeypatch):
    """80 targets (Panda poses and positions, humanoid7 near its limits, puma560 positions, some
    not reachable): on a clock that moves 10 ms at each reading, with no cap in the way, every
    call gives the status, stage and joint vectors of the real clock, the longest seeming to take
    five times the default cap; under the default cap on that clock, each call gives the same
    answer or says ``timeout``."""
    cases = _cases()
    labels = [f"{name} {target}" for name, _, target in cases]
    idle = _run(cases, timeout=NO_CAP)
    assert all(result.status != "timeout" for result in idle), [r.message for r in idle]
    statuses = {result.status for result in idle}
    methods = {result.method for result in idle}
    # The targets reach every stage and both verdicts (else the test would prove little).
    assert {"ok", "not_found"} <= statuses, statuses
    assert {"closed_form_free_joint", "seed_table", "mink_qp"} <= methods, methods
    with ticking_clock(monkeypatch, NUMERIC_STEP):
        busy = _run(cases, timeout=NO_CAP)
    assert _same_or_capped(labels, idle, busy) == 0
    # The played machine is slow: the default cap would have stopped its longest calls.
    assert max(result.time for result in busy) > 5 * DEFAULT_TIMEOUT
    with ticking_clock(monkeypatch, NUMERIC_STEP):
        capped = _run(cases)
    stopped = _same_or_capped(labels, idle, capped)
    assert 0 < stopped < len(cases), stopped  # both kinds, the same ones on every run


def test_a_call_that_reaches_the_cap_says_timeout_with_its_best():
    """A 1 us cap: ``timeout``, the hint to raise --timeout, never not_found or out_of_reach."""
    solver = NumericIK(load_robot("humanoid7"), closed_form=False)
    pose = _poses("humanoid7", 1, 5)[0]
    target = _turned(pose, np.random.default_rng(0))
    done = solver.solve(target, None)
    assert done.status == "not_found", done.message
    assert re.search(r"found in (\d+) starts", done.message), done.message
    assert int(re.search(r"found in (\d+) starts", done.message)[1]) >= MAX_ATTEMPTS
    capped = solver.solve(target, None, timeout=1e-6)
    assert (capped.success, capped.status) == (False, "timeout"), capped.message
    assert "--timeout" in capped.message and "1e-3 ms" not in capped.message


@pytest.mark.default_cap
@pytest.mark.parametrize("kind", ["not_found", "out_of_reach"])
def test_a_search_stopped_by_a_slow_clock_says_timeout(monkeypatch, kind):
    """On a clock that moves 0.25 s at each reading, the default cap (2 s) stops after a few
    starts what an idle machine finishes as not_found or out_of_reach (beyond the reach found,
    within the links laid end to end): the answer is ``timeout`` with the best configuration
    found, not the idle machine's verdict."""
    name = "humanoid7" if kind == "not_found" else "panda"  # Panda: bound 1.39 m, reach 1.19 m
    solver = NumericIK(load_robot(name), closed_form=False)
    pose = _poses(name, 1, 5)[0]
    if kind == "not_found":
        target = _turned(pose, np.random.default_rng(0))
    else:  # 5 % beyond the largest distance the tool reaches
        direction = pose.translation / np.linalg.norm(pose.translation)
        target = PositionTarget(direction * solver.arm_reach.maximum * 1.05)
    assert solver.solve(target, None, timeout=NO_CAP).status == kind
    with ticking_clock(monkeypatch, 0.25):
        result = solver.solve(target, None)
    assert (result.success, result.status) == (False, "timeout"), result.message
    assert f"{DEFAULT_TIMEOUT * 1e3:.4g} ms" in result.message and "--timeout" in result.message
    assert result.rejected and "misses by" in result.message


@pytest.mark.default_cap
def test_the_mimic_solver_answers_alike_on_a_slow_machine(tmp_path, monkeypatch):
    """A 6R arm with a mimic joint, 12 reached poses and 4 with turned tools: on a clock that
    moves 0.1 s at each reading, with no cap in the way, the same answers as on the real clock,
    those that run every start seeming to take twice the default cap; under the default cap on
    that clock, these say timeout and the others give the same answer; a 1 us cap on a far
    target says timeout with the hint."""
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(1.0), encoding="utf-8")
    arm = load_mimic_arm(path)
    rng = np.random.default_rng(9)
    targets = []
    for k in range(16):
        tool = arm.fk(rng.uniform(arm.lower, arm.upper))
        rotation = tool[:3, :3] if k < 12 else pin.exp3(rng.normal(size=3))
        targets.append(PoseTarget(tool[:3, 3] * (1.0 if k < 12 else 1.3), rotation))
    labels = [f"target {k}" for k in range(len(targets))]
    idle = [MimicSolver(arm).solve(target, timeout=NO_CAP) for target in targets]
    unfound = [k for k, result in enumerate(idle) if result.status == "not_found"]
    assert {result.status for result in idle} == {"ok", "not_found"}, unfound
    with ticking_clock(monkeypatch, MIMIC_STEP):
        busy = [MimicSolver(arm).solve(target, timeout=NO_CAP) for target in targets]
    assert _same_or_capped(labels, idle, busy) == 0
    # The played machine is slow: the default cap would have stopped every search not found.
    assert min(busy[k].time for k in unfound) > 2 * MIMIC_TIMEOUT
    with ticking_clock(monkeypatch, MIMIC_STEP):
        capped = [MimicSolver(arm).solve(target) for target in targets]
    assert _same_or_capped(labels, idle, capped) < len(targets)
    assert all(capped[k].status == "timeout" for k in unfound), [capped[k].message for k in unfound]
    far = PoseTarget(np.array([5.0, 0.0, 0.0]), np.eye(3))
    capped_far = MimicSolver(arm).solve(far, timeout=1e-6)
    assert (capped_far.success, capped_far.status) == (False, "timeout"), capped_far.message
    assert "--timeout" in capped_far.message and capped_far.rejected
