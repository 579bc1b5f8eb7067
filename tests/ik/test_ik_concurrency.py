"""Threads, processes and time budgets: one solver shared by threads, one cache file written by two
processes at once, and a timeout that bounds the whole call, cold caches included."""

from __future__ import annotations

import math
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
from support.solver_caps import NO_CAP

from kin import Configuration, load_robot
from kin.ik import PoseTarget, PositionTarget, get_solver
from kin.ik.numeric import seed_cache
from kin.ik.numeric.solver import NumericIK

#: Nothing here overflows or divides by zero: NumPy's warnings fail the test (issue 42).
pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")


def _targets(name: str, count: int, full: bool, seed: int) -> list:
    robot = load_robot(name)
    configuration = Configuration(robot)
    rng = np.random.default_rng(seed)
    q_all = rng.uniform(robot.lower, robot.upper, size=(count, robot.nq))
    targets = []
    for q in q_all:
        pose = configuration.fk(q)
        targets.append(
            PoseTarget(pose.translation, pose.rotation)
            if full
            else PositionTarget(pose.translation)
        )
    return targets


def _answer(result) -> tuple:
    return (result.success, result.status, tuple(tuple(s.q.tolist()) for s in result.solutions))


@pytest.mark.parametrize(("name", "full"), [("humanoid7", True), ("ur5", True), ("panda", False)])
def test_one_solver_shared_by_four_threads_answers_as_one_thread(name, full):
    """4,000 poses split over 4 threads sharing one get_solver(): the answers of one thread.

    A time cap no load reaches (NO_CAP) and an attempt cap make each answer independent of the
    machine's speed (the numeric stages stop on the attempt cap, not the clock).
    """
    count = 4000 if name == "humanoid7" else 1000
    robot = load_robot(name)
    solver = get_solver(robot)
    targets = _targets(name, count, full, seed=17)

    cap = {"max_attempts": 60} if isinstance(solver, NumericIK) else {}

    def solve(target):  # a cap no load reaches: the threads' verdicts are compared
        return _answer(solver.solve(target, timeout=NO_CAP, **cap))

    alone = [solve(target) for target in targets]
    with ThreadPoolExecutor(max_workers=4) as pool:
        shared = list(pool.map(solve, targets, chunksize=50))
    assert shared == alone
    assert sum(success for success, _, _ in alone) >= 0.99 * count


_BUILD = """
import sys
from kin import load_robot
from kin.ik.numeric.seed_table import build_seed_table
from kin.robot_model import robot_from_table
from dh2urdf import get_robot, load_table
robot = robot_from_table(load_table(get_robot("panda").table_path))
table = build_seed_table(robot, size=int(sys.argv[1]))
print(len(table))
"""


def test_two_processes_building_one_cache_leave_one_valid_file(tmp_path, monkeypatch):
    """Two processes build the same seed table at once: one file, which a third one loads."""
    env = {"XDG_CACHE_HOME": str(tmp_path), "PATH": "/usr/bin:/bin"}
    size = "30000"
    processes = [
        subprocess.Popen(
            [sys.executable, "-c", _BUILD, size], env=env, stdout=subprocess.PIPE, text=True
        )
        for _ in range(2)
    ]
    outputs = [process.communicate(timeout=300)[0].strip() for process in processes]
    assert [process.returncode for process in processes] == [0, 0] and outputs == [size] * 2
    files = sorted((tmp_path / "dh-kinematics").iterdir())
    assert len(files) == 1 and files[0].name.startswith("seed_table_"), files
    key = files[0].name[len("seed_table_") : -len(".npz")]
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    arrays = seed_cache.load(key)
    assert arrays is not None and len(arrays["q"]) == int(size)


@pytest.mark.parametrize("name", ["humanoid7", "panda", "ur5", "puma560", "lab5", "scorbot"])
def test_a_tiny_timeout_with_cold_caches_says_what_stopped_it(name, monkeypatch, tmp_path):
    """timeout=5 ms on a fresh solver (no seed table on disk, no MuJoCo model loaded), every
    target kind, reachable, hard or far: each answer is verified, or a proved "out of reach" (the
    far ones only), or a ``timeout`` that names the cap; never a ``not_found`` or an unproved
    "out of reach" because the cap cut the search. How long such a call takes is a figure of
    ``scripts/bench_ik_timeout.py``, not an assertion."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    robot = load_robot(name)
    solver = NumericIK(robot, prepare=False)  # nothing loaded: the first solve meets it all
    configuration = Configuration(robot)
    reachable = configuration.fk(np.zeros(robot.nq) + 0.1).translation
    reach = float(np.linalg.norm(reachable)) + sum(
        abs(row.a) + abs(row.d) for row in robot.table.rows
    )
    positions = [reachable, reachable * 1.05 + 0.02, [0.0, 0.0, 0.0], [1e308, 0, 0], [3.0, 0, 0]]
    for position in positions:
        result = solver.solve(PositionTarget(position), timeout=0.005)
        far = math.hypot(*position) > reach  # no overflow at 1e308 m (np.linalg.norm squares)
        if result.success:
            error = np.linalg.norm(
                configuration.fk(result.best.q).translation - np.asarray(position)
            )
            assert error < 1e-6, f"{name=} {position=} {error=}"
        elif far:
            assert result.status == "out_of_reach", f"{name=} {position=} {result.message}"
        else:
            assert result.status in ("timeout", "out_of_reach"), f"{name=} {result.message}"
            if result.status == "timeout":
                assert "time cap (5 ms)" in result.message, result.message
            else:  # proved: beyond the reach, said with the distance
                assert "beyond the arm's reach" in result.message, result.message
