"""Benchmark the time bound of an IK call: does ``timeout`` bound the whole call, cold caches included?

For each shipped robot and each timeout, in a fresh process (nothing imported beyond ``kin.ik``,
no seed table on disk: a private cache folder) the documented call
``get_solver(robot).solve(target, timeout=...)`` is timed for four targets: a reachable pose from
FK, a hard point just outside the sampled workspace's edge, a point beyond the reach but within the
links laid end to end, and a point 1e308 m away. The first call meets every cold cache (seed
table, MuJoCo model, SciPy's linear algebra); the table prints the first call's time and the
median and largest of 20 further calls, each against the bound ``max(2 timeout, 20 ms)``.
Construction of the solver (``get_solver``) is outside the timed call; it is printed beside.

    python scripts/bench_ik_timeout.py                 # every shipped robot, timeouts 5 and 50 ms
    python scripts/bench_ik_timeout.py --robot panda --timeout 5
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

from dh2urdf import ROBOTS
from kin.cli import ArgumentParser, positive_float

_PROBE = r"""
import json, statistics, sys, time
import numpy as np
t0 = time.perf_counter()
from kin import Configuration, load_robot
from kin.ik import PoseTarget, PositionTarget, get_solver
robot = load_robot(sys.argv[1])
timeout = float(sys.argv[2])
t1 = time.perf_counter()
solver = get_solver(robot)
t2 = time.perf_counter()
pose = Configuration(robot).fk(robot.lower * 0.3 + robot.upper * 0.2)
kinds = getattr(solver, "target_kinds", ())
full = PoseTarget in kinds and robot.nq >= 6
from kin.ik.reach import reach_bound
bound = reach_bound(robot)
direction = pose.translation / max(np.linalg.norm(pose.translation), 1e-9)
targets = {
    "reachable": PoseTarget(pose.translation, pose.rotation) if full else PositionTarget(pose.translation),
    "edge": PositionTarget(direction * 0.999 * bound),
    "beyond": PositionTarget(direction * 0.9999 * bound + [0, 0, 1e-3]),
    "1e308": PositionTarget([1e308, 0, 0]),
}
out = {"import_s": t1 - t0, "solver_s": t2 - t1}
for name, target in targets.items():
    times = []
    for i in range(21):
        start = time.perf_counter()
        result = solver.solve(target, timeout=timeout)
        times.append(time.perf_counter() - start)
    out[name] = {"first_s": times[0], "median_s": statistics.median(times[1:]),
                 "max_s": max(times[1:]), "status": result.status}
print(json.dumps(out))
"""


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik_timeout.py", description=__doc__)
    parser.add_argument("--robot", choices=tuple(ROBOTS), help="one robot only")
    parser.add_argument(
        "--timeout",
        type=positive_float,
        nargs="+",
        default=[5.0, 50.0],
        help="time budgets [ms] (default 5 50)",
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print one row per robot, timeout and target."""
    args = get_argument_parser().parse_args(argv)
    names = [args.robot] if args.robot else list(ROBOTS)
    print(
        f"{'robot':<11} {'timeout':>8} {'bound':>7}  {'target':<9} {'first':>8} {'median':>8} "
        f"{'max':>8}  status            (times in ms; solver built in)"
    )
    for name in names:
        for timeout_ms in args.timeout:
            with tempfile.TemporaryDirectory() as cache:
                env = dict(os.environ, XDG_CACHE_HOME=cache, OPENBLAS_NUM_THREADS="1")
                done = subprocess.run(
                    [sys.executable, "-c", _PROBE, name, str(timeout_ms / 1e3)],
                    env=env,
                    capture_output=True,
                    text=True,
                    check=False,
                )
            if done.returncode != 0:
                print(f"{name:<11} {timeout_ms:>6.0f}ms  failed: {done.stderr.strip()[-200:]}")
                continue
            row = json.loads(done.stdout)
            bound = max(2 * timeout_ms, 20.0)
            for target in ("reachable", "edge", "beyond", "1e308"):
                cell = row[target]
                print(
                    f"{name:<11} {timeout_ms:>6.0f}ms {bound:>5.0f}ms  {target:<9} "
                    f"{cell['first_s'] * 1e3:>8.2f} {cell['median_s'] * 1e3:>8.2f} "
                    f"{cell['max_s'] * 1e3:>8.2f}  {cell['status']:<17} "
                    f"({row['solver_s'] * 1e3:.0f} ms)"
                )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
