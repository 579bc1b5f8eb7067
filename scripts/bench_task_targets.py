r"""Success of task-shaped targets (a free tool axis, masks) on reachable poses, per arm.

Issue #32 item 1: on every shipped robot and on example-robot-data's Panda, Kinova Jaco 2, UR5,
Z1, xArm7, TIAGo arm and Baxter arm, ``N`` targets per kind made from the tool poses of random
joint vectors inside the limits (reachable by construction), solved by
``get_solver(robot).solve(target)`` with the default seed, and judged by an independent forward
kinematics (a plain NumPy DH product of the table, or Pinocchio on the maker's URDF:
``tests/support/task_targets_reference.py``)::

    python scripts/bench_task_targets.py --n 1000

prints per arm and kind: solved / N, false successes (a success the reference rejects), the
statuses of the failures, the median time of a call [ms] and the methods that answered. Rows
print as each arm ends; Ctrl-C stops and keeps the rows printed.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))


def main(argv: list[str] | None = None) -> int:
    """Print the table; exit 0 (130 on Ctrl-C after the rows done)."""
    from support.task_targets_reference import KINDS, POSITION_TOL, ROBOTS, ROTATION_TOL, arm_of

    parser = argparse.ArgumentParser(prog="bench_task_targets.py", description=__doc__)
    parser.add_argument("--n", type=int, default=1000, help="targets per arm and kind")
    parser.add_argument("--robots", nargs="*", default=list(ROBOTS), help="names (erd:<arm>)")
    args = parser.parse_args(argv)
    print(
        f"{'robot':18} {'kind':8} {'solved':>11} {'false':>5} {'median ms':>9}  failures; methods"
    )
    try:
        for name in args.robots:
            arm = arm_of(name)
            for kind in KINDS:
                solved = false = 0
                times: list[float] = []
                failures: Counter[str] = Counter()
                methods: Counter[str] = Counter()
                for target, _ in arm.targets(kind, args.n, seed=2026):
                    start = time.perf_counter()
                    result = arm.solver.solve(target)
                    times.append(time.perf_counter() - start)
                    if not result.success:
                        failures[result.status] += 1
                        continue
                    methods[result.method] += 1
                    position, angle, inside = arm.errors(target, result.best.q)
                    if position < POSITION_TOL and angle < ROTATION_TOL and inside:
                        solved += 1
                    else:
                        false += 1
                print(
                    f"{name:18} {kind:8} {solved:>5}/{args.n:<5} {false:>5} "
                    f"{1e3 * statistics.median(times):>9.2f}  {dict(failures)}; {dict(methods)}",
                    flush=True,
                )
    except KeyboardInterrupt:
        print("interrupted: the rows above are complete", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
