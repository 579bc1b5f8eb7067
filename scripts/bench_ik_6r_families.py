"""Benchmark one target of every case of the two 6R families (issue 34 item 3).

Random tables of each case (the recipes of ``tests/ik/analytic/six_r/test_ik_pieper.py`` and
``tests/ik/analytic/six_r/test_ik_three_parallel.py``, standard convention, seeds 0..``--tables - 1``, random base
and tool): Pieper ``intersecting`` (axes 1, 2 meet), ``parallel`` (axes 1, 2 parallel),
``general`` (a quartic in q3) and ``parallel23`` (axes 2, 3 parallel: the spherical-wrist case),
three-parallel ``general`` (``a5 != 0``, a quartic in q1) and ``intersecting`` (``a5 = 0``: the
UR case).
Targets: the FK of seeded random q. The documented call ``kin.ik.get_solver(robot).solve(
PoseTarget(p, R))`` (every branch wrapped into the limits and verified) is timed two ways,
alternated target by target, one call each: ``compiled``, the family's one compiled twin
(``_pieper_arms.c``, ``_three_parallel.c``: the branches and the verify in C), and ``numpy``, the
same solver with ``compiled=False`` (the family's NumPy algorithm at N = 1, Pinocchio as the
judge). Columns: medians of single calls [us] and ``numpy x``, the NumPy median over the compiled
one; ``same``: targets where both return the same solutions (count, branch labels, q to 1e-10 rad).

Measured on the 2-core machine under the other engineers' load (2026-11-27): the tests' random
tables (``random_table(family, "standard", 0)``), 50 targets x 15, medians of single calls of
``get_solver(robot).solve``, the commit before the families' merge (d001f74^: scalar Python per
target) and this one alternated process by process, three rounds: Pieper intersecting 104, 128,
134 -> 5, 5, 5 us; Pieper general 151, 152, 256 -> 14, 9, 9 us; three-parallel general 136, 139,
225 -> 13, 8, 8 us. This script (``--targets 100 --tables 2``, two runs): compiled 4.5-19 us, NumPy 43-138 us,
``numpy x`` 5.4-11.5 (the closed-form cases about 10, the quartics about 6), the same answers on
100/100 targets of every table. One twin per family (the UR and spherical-wrist cases folded into
``_three_parallel.c`` and ``_pieper_arms.c``) against its parent c8b071f, 38 runs alternated
ABBA (``--targets 200 --tables 2``): the compiled column after/before 0.94-1.02 (paired
medians; the unchanged ``numpy`` column 0.93-0.99), 200/200 the same on every table.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

import kin
from dh2urdf import DHTable
from kin.cli import ArgumentParser, positive_int
from kin.ik import ClosedFormSolver, PoseTarget, get_solver

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from support.arm_tables import make_table, random_pose  # noqa: E402  (the tests' table builders)

PI = math.pi
CASES = ("pieper intersecting", "pieper parallel", "pieper general", "pieper parallel23",
         "three_parallel general", "three_parallel intersecting")  # fmt: skip


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik_6r_families.py", description=__doc__)
    parser.add_argument(
        "--targets", type=positive_int, default=200, help="targets per table (default 200)"
    )
    parser.add_argument(
        "--tables", type=positive_int, default=3, help="random tables per case (default 3)"
    )
    parser.add_argument("--case", choices=CASES, help="one case only (default: all)")
    return parser


def random_table(case: str, seed: int) -> DHTable:
    """A random standard table of ``case`` (the tests' recipes), limits +-2 pi [m], [rad]."""
    rng = np.random.default_rng(seed)
    if case.startswith("pieper"):
        a, d = rng.uniform(-0.5, 0.5, 6), rng.uniform(-0.5, 0.5, 6)
        theta, alpha = rng.uniform(-PI, PI, 6), rng.uniform(-PI, PI, 6)
        a[3] = a[4] = d[4] = 0.0
        if case.endswith("intersecting"):
            a[0] = 0.0
        elif case.endswith("parallel"):
            alpha[0] = rng.choice([0.0, PI])
        elif case.endswith("parallel23"):
            alpha[1] = 0.0
    else:
        a, d = rng.uniform(-0.5, 0.5, 6), rng.uniform(-0.3, 0.3, 6)
        alpha, theta = rng.uniform(-PI, PI, 6), rng.uniform(-PI, PI, 6)
        alpha[1] = alpha[2] = 0.0
        if not case.endswith("intersecting"):
            a[4] = rng.choice([-1.0, 1.0]) * rng.uniform(0.05, 0.5)
        else:
            a[4] = 0.0
    name = f"{case} {seed}"
    return make_table(a, alpha, d, theta, "standard", random_pose(rng), random_pose(rng), name)


def _same(ours, theirs) -> bool:
    """The same solutions: count, branch labels and q to 1e-10 rad."""
    if [s.branch for s in ours.solutions] != [s.branch for s in theirs.solutions]:
        return False
    return all(np.abs(a.q - b.q).max() <= 1e-10 for a, b in zip(ours.solutions, theirs.solutions))


def _timed(call: Callable[[], object]) -> tuple[float, object]:
    start = time.perf_counter()
    result = call()
    return time.perf_counter() - start, result


def main(argv: list[str] | None = None) -> int:
    """Print one row per case and table: medians of single calls, their ratio, same answers."""
    args = get_argument_parser().parse_args(argv)
    print(f"{'case':<27} {'table':>5} {'compiled':>9} {'numpy':>9} {'numpy x':>8} {'same':>9}")
    for case in [args.case] if args.case else CASES:
        for seed in range(args.tables):
            robot = kin.robot_from_table(random_table(case, seed))
            compiled, numpy = get_solver(robot), ClosedFormSolver(robot, compiled=False)
            if getattr(compiled, "_twin", None) is None:
                print(f"{case:<27} {seed:>5} the compiled twin is not built or does not fit")
                continue
            q = np.random.default_rng(100 + seed).uniform(-PI, PI, (args.targets, 6))
            poses = kin.batch_forward_kinematics(robot.table, q)
            targets = [PoseTarget(T[:3, 3], T[:3, :3]) for T in poses]
            times: dict[str, list[float]] = {"compiled": [], "numpy": []}
            same = 0
            for k, target in enumerate(targets):
                order = ("compiled", "numpy") if k % 2 == 0 else ("numpy", "compiled")
                results = {}
                for name in order:
                    solver = compiled if name == "compiled" else numpy
                    elapsed, results[name] = _timed(lambda: solver.solve(target))  # noqa: B023
                    times[name].append(elapsed)
                same += _same(results["compiled"], results["numpy"])
            ours, theirs = (statistics.median(times[n]) * 1e6 for n in ("compiled", "numpy"))
            print(f"{case:<27} {seed:>5} {ours:>7.1f}us {theirs:>7.1f}us {theirs / ours:>7.1f}x "
                  f"{same:>4}/{len(targets)}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
