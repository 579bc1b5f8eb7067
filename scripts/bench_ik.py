"""Benchmark the closed-form IK: per-call median (all branches, Pinocchio verification) and batch rate.

With ``--robot humanoid7`` (or ``panda``, ``xarm7``) it runs the numeric-IK benchmark instead (``bench_ik_humanoid7.py``:
success and time from q = 0 and from random q, full pose and position only, beside TRAC-IK and the
Robotics Toolbox's ik_LM when installed); the remaining options are passed on to it. With
``--robot ur5`` (or ``ur10``, ``puma560``) it runs the 6R closed-form benchmark
(``bench_ik_6r.py``: all 8 branches per call, verified, batched, beside ur-analytic-ik and the
Robotics Toolbox's ``ikine_a``), likewise.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import gc
import importlib.util
import statistics
import sys
import time
from pathlib import Path

import numpy as np

from kin.batch_fk import batch_forward_kinematics
from kin.cli import ArgumentParser, positive_int
from kin.configuration import Configuration
from kin.ik import BatchSolver, ClosedFormSolver, PoseTarget, PositionTarget
from kin.robot_model import load_robot

ROBOTS = ("lab5", "ned5", "pickplace3", "planar2", "scorbot")
#: 7R arms with a free-joint closed form: forwarded to ``bench_ik_humanoid7.py``.
SEVEN_JOINT = ("humanoid7", "panda", "xarm7")
#: 6R arms with a closed form of 8 branches: forwarded to ``bench_ik_6r.py``.
SIX_JOINT = ("ur5", "ur10", "puma560")


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik.py", description=__doc__)
    parser.add_argument(
        "--calls", type=positive_int, default=2000, help="per-call samples per robot (default 2000)"
    )
    parser.add_argument(
        "--batch",
        type=positive_int,
        default=100_000,
        help="targets per batched call (default 100000)",
    )
    parser.add_argument(
        "--repeat", type=positive_int, default=5, help="passes per target, fastest kept (default 5)"
    )
    parser.add_argument(
        "--robot",
        choices=(*ROBOTS, *SIX_JOINT, *SEVEN_JOINT),
        help="one robot only; humanoid7, panda and xarm7 run the numeric-IK benchmark "
        "(see bench_ik_humanoid7.py -h), ur5, ur10 and puma560 the 6R one against "
        "ur-analytic-ik and the Robotics Toolbox (see bench_ik_6r.py -h)",
    )
    return parser


def per_call_times(solver: ClosedFormSolver, targets: list, repeat: int) -> list[float]:
    """Sorted wall time [s] of one solve per target, the best of ``repeat`` passes.

    As in ``timeit``: the garbage collector is paused while timing, and each target keeps its
    fastest pass (interference from the machine only ever adds time).
    """
    best = [float("inf")] * len(targets)
    enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(repeat):
            for i, target in enumerate(targets):
                start = time.perf_counter()
                solver.solve(target)
                best[i] = min(best[i], time.perf_counter() - start)
    finally:
        if enabled:
            gc.enable()
    return sorted(best)


def _sibling(name: str):
    """The module of ``scripts/<name>.py`` (a sibling script, not a package)."""
    path = Path(__file__).resolve().with_name(f"{name}.py")
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def main(argv: list[str] | None = None) -> int:
    """Print one row per robot: median and p90 per call [us] (target <= 50), batched targets/s (>= 200,000)."""
    args, rest = get_argument_parser().parse_known_args(argv)
    if args.robot in SEVEN_JOINT:
        return _sibling("bench_ik_humanoid7").main(["--robot", args.robot, *rest])
    if args.robot in SIX_JOINT:
        return _sibling("bench_ik_6r").main(["--robot", args.robot, *rest])
    if rest:
        get_argument_parser().error(f"unrecognized arguments: {' '.join(rest)}")
    print(f"{'robot':<11} {'median [us]':>11} {'p90 [us]':>9} {'batch [targets/s]':>18}")
    for name in (args.robot,) if args.robot else ROBOTS:
        robot = load_robot(name)
        solver, batch = ClosedFormSolver(robot), BatchSolver(robot)
        configuration = Configuration(robot)
        rng = np.random.default_rng(0)
        q = rng.uniform(robot.lower, robot.upper, size=(max(args.calls, args.batch), robot.nq))
        targets = []
        for row in q[: args.calls]:
            pose = configuration.fk(row)
            targets.append(
                PositionTarget(pose.translation) if robot.nq < 5 else PoseTarget.from_matrix(pose)
            )
        times = per_call_times(solver, targets, args.repeat)
        poses = batch_forward_kinematics(robot.table, q[: args.batch])
        best = float("inf")
        for _ in range(3):
            start = time.perf_counter()
            batch.solve_positions(poses[:, :3, 3]) if robot.nq < 5 else batch.solve_poses(poses)
            best = min(best, time.perf_counter() - start)
        print(
            f"{name:<11} {statistics.median(times) * 1e6:>11.1f} {times[int(0.9 * len(times))] * 1e6:>9.1f} "
            f"{args.batch / best:>18,.0f}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
