"""Benchmark the kin FK call against the raw Pinocchio call, fk.py's wall time, and batched FK.

Targets (foundation issue): kin FK at most 1.5x the raw
``pin.forwardKinematics + updateFramePlacement + oMf`` call; ``fk.py`` under 0.6 s wall.
Batched NumPy FK (``kin.batch_forward_kinematics``, issue 9): at least 1,000,000 humanoid7
configurations/s, printed beside a loop of raw Pinocchio calls over the same configurations.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import statistics
import subprocess
import sys
import time
import timeit
from pathlib import Path

import numpy as np
import pinocchio as pin

from dh2urdf import robot_names
from kin.batch_fk import batch_forward_kinematics
from kin.cli import ArgumentParser, positive_int
from kin.configuration import Configuration
from kin.robot_model import load_robot

SCRIPTS = Path(__file__).resolve().parent


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_fk.py", description=__doc__)
    parser.add_argument(
        "--number", type=positive_int, default=20000, help="calls per timing (default 20000)"
    )
    parser.add_argument(
        "--repeat", type=positive_int, default=7, help="timings per figure, best kept (default 7)"
    )
    parser.add_argument("--cli-runs", type=positive_int, default=5, help="fk.py runs (default 5)")
    parser.add_argument(
        "--batch",
        type=positive_int,
        default=1_000_000,
        help="configurations of the batched FK timing (default 1000000)",
    )
    return parser


def _per_call_us(function, number: int, repeat: int) -> float:
    return min(timeit.repeat(function, number=number, repeat=repeat)) / number * 1e6


def main(argv: list[str] | None = None) -> int:
    """Print the benchmark table; exit 0."""
    args = get_argument_parser().parse_args(argv)
    rng = np.random.default_rng(0)
    print(f"{'robot':<11} {'raw pin [us]':>13} {'kin fk [us]':>12} {'ratio':>7}  target <= 1.50")
    worst = 0.0
    for name in robot_names():
        robot = load_robot(name)
        q = rng.uniform(robot.lower, robot.upper)
        model, data = robot.model, robot.model.createData()
        fid = model.getFrameId(robot.tool_frame)

        def raw(model=model, data=data, fid=fid, q=q):
            pin.forwardKinematics(model, data, q)
            pin.updateFramePlacement(model, data, fid)
            return data.oMf[fid]

        configuration = Configuration(robot)

        def ours(configuration=configuration, q=q):
            return configuration.fk(q, "tool")

        assert np.allclose(raw().homogeneous, ours().homogeneous)
        t_raw = _per_call_us(raw, args.number, args.repeat)
        t_ours = _per_call_us(ours, args.number, args.repeat)
        worst = max(worst, t_ours / t_raw)
        print(f"{name:<11} {t_raw:13.2f} {t_ours:12.2f} {t_ours / t_raw:7.2f}", flush=True)
    print(f"worst ratio: {worst:.2f}")
    walls = []
    command = [sys.executable, str(SCRIPTS / "fk.py"), "--robot", "humanoid7", "--q", *["0"] * 7]
    for _ in range(args.cli_runs):
        start = time.perf_counter()
        subprocess.run(command, check=True, capture_output=True)
        walls.append(time.perf_counter() - start)
    print(
        f"fk.py wall time over {args.cli_runs} runs [s]: median {statistics.median(walls):.3f}, "
        f"max {max(walls):.3f}  target < 0.6"
    )
    _bench_batch(args.batch, args.repeat)
    return 0


def _bench_batch(n: int, repeat: int) -> None:
    """Print batched NumPy FK and a raw Pinocchio loop in humanoid7 configurations/s."""
    robot = load_robot("humanoid7")
    q = np.random.default_rng(1).uniform(robot.lower, robot.upper, size=(n, robot.nq))
    best = min(
        timeit.repeat(lambda: batch_forward_kinematics(robot.table, q), number=1, repeat=repeat)
    )
    model, data = robot.model, robot.model.createData()
    fid = model.getFrameId(robot.tool_frame)
    loop_n = min(n, 20_000)

    def loop() -> None:
        for qi in q[:loop_n]:
            pin.forwardKinematics(model, data, qi)
            pin.updateFramePlacement(model, data, fid)

    loop_best = min(timeit.repeat(loop, number=1, repeat=3))
    batch_rate, loop_rate = n / best, loop_n / loop_best
    print(
        f"humanoid7 batched FK (tool pose, N = {n:,}): numpy {batch_rate:,.0f} configurations/s, "
        f"Pinocchio loop {loop_rate:,.0f} configurations/s ({batch_rate / loop_rate:.1f}x)  "
        f"target >= 1,000,000"
    )


if __name__ == "__main__":
    raise SystemExit(main())
