"""Sweep the IK peers' settings on the humanoid7 benchmark targets and print the best per case.

The issue asks for the peers to run with the settings that give them their best success rate.
This runs each setting of a grid on the targets and starts of bench_ik_humanoid7.py (same --n and
--seed give the same targets and start arrays), judged alike (Pinocchio error < 1e-5 m and
1e-4 rad, inside the limits), and prints one row per (peer, setting, task, start): success,
median and p90 time. Then, per peer, task and start, the setting with the best success (ties: the
lower median), as bench_ik_humanoid7.py options; and per peer the best single setting over all its
tasks and starts (the benchmark takes one setting per peer).

Grid: Robotics Toolbox ik_LM method x k (chan 1.0, 0.1, 0.01; wampler 0.01, 0.001, 0.0001;
sugihara 0.1, 0.01, 0.0001, around its docstring's ranges) x ilimit (30, 100) x slimit (100,
1000), full pose and position only; TRAC-IK solver_type (Speed, Distance, Manip1, Manip2) x
timeout (5, 20, 50 ms), full pose only (its binding has no position-only mode).

The tolerances stay fixed, as in the benchmark: ik_LM tol 1e-12 on its error 0.5 e'e (so
|e| < 1.5e-6) and TRAC-IK epsilon 1e-6 per twist component. They set how precise an answer must
be, not how hard the peer tries, and they only have to beat the judge's 1e-5 m and 1e-4 rad so
that every answer a peer reports as solved is one the judge accepts.

Progress goes to stderr, one line per setting; Ctrl-C prints the finished runs and exits 130.
A full sweep takes about an hour on a 2-core machine, mostly ik_LM's wampler and sugihara settings
at slimit 1000 (a target they miss costs all ilimit x slimit iterations, up to ~1 s) and TRAC-IK's
Distance and Manip modes (they use their whole budget); --peers and --quick narrow it.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import functools
import importlib.util
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

from kin.cli import ArgumentParser, positive_int, run_guarded
from kin.robot_model import RobotModel, load_robot

PROG = "sweep_ik_peers.py"
RTB = "RTB ik_LM"
TRACIK = "TRAC-IK"

#: ik_LM: k per method, iterations per search, searches.
RTB_K = {
    "chan": (1.0, 0.1, 0.01),
    "wampler": (0.01, 0.001, 0.0001),
    "sugihara": (0.1, 0.01, 0.0001),
}
RTB_ILIMITS = (30, 100)
RTB_SLIMITS = (100, 1000)
#: TRAC-IK: solver types and budgets [ms].
TRACIK_TYPES = ("Speed", "Distance", "Manip1", "Manip2")
TRACIK_TIMEOUTS = (5.0, 20.0, 50.0)
#: --quick: one k per method, and two TRAC-IK modes at the smallest budget.
QUICK_RTB_K = {"chan": (0.1,), "wampler": (0.001,), "sugihara": (0.01,)}
QUICK_TRACIK_TYPES = ("Speed", "Distance")


def _benchmark() -> ModuleType:
    """The module of ``scripts/bench_ik_humanoid7.py`` (a sibling script, not a package)."""
    if "bench_ik_humanoid7" in sys.modules:
        return sys.modules["bench_ik_humanoid7"]
    path = Path(__file__).resolve().with_name("bench_ik_humanoid7.py")
    spec = importlib.util.spec_from_file_location("bench_ik_humanoid7", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@dataclass(frozen=True)
class Setting:
    """One point of a peer's grid."""

    peer: str
    label: str
    #: The bench_ik_humanoid7.py options that select this setting.
    options: str
    #: robot -> solve function, or why the peer is skipped.
    build: Callable[[RobotModel], object]
    #: Whether the peer also runs position-only targets.
    position_only: bool


@dataclass(frozen=True)
class Result:
    """One row of the table: a setting on one task from one start."""

    setting: Setting
    task: str
    start: str
    success: float
    median_ms: float
    p90_ms: float


def rtb_grid(quick: bool) -> list[Setting]:
    """ik_LM settings: method x k x ilimit x slimit (``quick``: one k per method, 30 x 100)."""
    bench = _benchmark()
    ks = QUICK_RTB_K if quick else RTB_K
    ilimits = RTB_ILIMITS[:1] if quick else RTB_ILIMITS
    slimits = RTB_SLIMITS[:1] if quick else RTB_SLIMITS
    return [
        Setting(
            RTB,
            f"{method} k={k:g} ilimit={ilimit} slimit={slimit}",
            f"--rtb-method {method} --rtb-k {k:g} --rtb-ilimit {ilimit} --rtb-searches {slimit}",
            functools.partial(bench.rtb_lm, searches=slimit, method=method, k=k, ilimit=ilimit),
            True,
        )
        for method, values in ks.items()
        for k in values
        for ilimit in ilimits
        for slimit in slimits
    ]


def tracik_grid(quick: bool) -> list[Setting]:
    """TRAC-IK settings: solver_type x timeout (``quick``: Speed and Distance at 5 ms)."""
    bench = _benchmark()
    types = QUICK_TRACIK_TYPES if quick else TRACIK_TYPES
    timeouts = TRACIK_TIMEOUTS[:1] if quick else TRACIK_TIMEOUTS
    return [
        Setting(
            TRACIK,
            f"{solver_type} timeout={timeout:g} ms",
            f"--tracik-solver {solver_type} --tracik-timeout {timeout:g}",
            functools.partial(bench.tracik, timeout_ms=timeout, solver_type=solver_type),
            False,
        )
        for solver_type in types
        for timeout in timeouts
    ]


def best(results: list[Result]) -> Result:
    """The result with the highest success; ties go to the lower median."""
    return max(results, key=lambda r: (r.success, -r.median_ms))


def print_report(results: list[Result], n_starts: int) -> None:
    """The table, the best setting per (peer, task, start), and the best per peer overall.

    A setting enters the per-peer summary only when all its runs are done: ``n_starts`` per task.
    """
    width = max([len(r.setting.label) for r in results] + [len("settings")])
    print(
        f"{'peer':<10} {'settings':<{width}} {'task':<10} {'start':<9} {'success':>8} "
        f"{'median ms':>10} {'p90 ms':>8}"
    )
    for r in results:
        print(
            f"{r.setting.peer:<10} {r.setting.label:<{width}} {r.task:<10} {r.start:<9} "
            f"{100 * r.success:7.1f}% {r.median_ms:10.3f} {r.p90_ms:8.3f}"
        )
    if not results:
        return
    print()
    print("best setting per peer, task and start (highest success, then lowest median):")
    groups: dict[tuple[str, str, str], list[Result]] = {}
    for r in results:
        groups.setdefault((r.setting.peer, r.task, r.start), []).append(r)
    for (peer, task, start), group in groups.items():
        top = best(group)
        print(
            f"{peer:<10} {task:<10} {start:<9} {100 * top.success:6.1f}% "
            f"{top.median_ms:8.3f} ms  {top.setting.options}"
        )
    print()
    print(
        "best single setting per peer over its tasks and starts "
        "(highest mean success, then lowest mean median):"
    )
    by_setting: dict[Setting, list[Result]] = {}
    for r in results:
        by_setting.setdefault(r.setting, []).append(r)
    peers: dict[str, list[tuple[float, float, Setting]]] = {}
    for setting, rows in by_setting.items():
        if len(rows) != n_starts * (2 if setting.position_only else 1):
            continue  # interrupted before all its runs
        success = sum(r.success for r in rows) / len(rows)
        median = sum(r.median_ms for r in rows) / len(rows)
        peers.setdefault(setting.peer, []).append((success, median, setting))
    for peer, scores in peers.items():
        success, median, setting = max(scores, key=lambda s: (s[0], -s[1]))
        print(f"{peer:<10} {100 * success:6.1f}% {median:8.3f} ms  {setting.options}")


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog=PROG, description=__doc__)
    parser.add_argument(
        "--n", type=positive_int, default=1000, help="number of targets (default 1000)"
    )
    parser.add_argument("--seed", type=int, default=0, help="random seed of the targets")
    parser.add_argument("--peers", choices=("all", "rtb", "tracik"), default="all")
    parser.add_argument(
        "--quick", action="store_true", help="a small grid (3 ik_LM and 2 TRAC-IK settings)"
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print the table and the best settings; exit 0 (130 on Ctrl-C, after the finished runs)."""
    args = get_argument_parser().parse_args(argv)

    def body() -> int:
        bench = _benchmark()
        robot = load_robot("humanoid7")
        _, poses = bench.make_targets(robot, args.n, args.seed)
        starts = bench.make_starts(robot, args.n, args.seed)
        grid: list[Setting] = []
        if args.peers in ("all", "rtb"):
            grid += rtb_grid(args.quick)
        if args.peers in ("all", "tracik"):
            grid += tracik_grid(args.quick)
        print(
            f"{robot.name}: {args.n} reachable targets (seed {args.seed}); success = Pinocchio "
            "error < 1e-5 m and 1e-4 rad, inside the limits; ik_LM tol 1e-12, TRAC-IK epsilon 1e-6"
        )
        results: list[Result] = []
        skipped: set[str] = set()
        interrupted = False
        begin = time.perf_counter()
        try:
            for index, setting in enumerate(grid, 1):
                if setting.peer in skipped:
                    continue
                solve = setting.build(robot)
                if isinstance(solve, str):
                    print(solve)
                    skipped.add(setting.peer)
                    continue
                tasks = (False, True) if setting.position_only else (False,)
                started = time.perf_counter()
                done = []
                for position_only in tasks:
                    for label, seeds in starts.items():
                        (row,) = bench.run(
                            robot, {setting.peer: solve}, poses, position_only, seeds, label
                        )
                        result = Result(
                            setting, row.task, row.start, row.success, row.median_ms, row.p90_ms
                        )
                        results.append(result)
                        done.append(f"{100 * row.success:.1f}%")
                print(
                    f"{PROG}: [{index}/{len(grid)}] {setting.peer} {setting.label}: "
                    f"{' '.join(done)} ({time.perf_counter() - started:.1f} s; "
                    f"{time.perf_counter() - begin:.0f} s in all)",
                    file=sys.stderr,
                    flush=True,
                )
        except KeyboardInterrupt:
            interrupted = True
        print_report(results, len(starts))
        if interrupted:
            started = len({r.setting for r in results})
            print(
                f"interrupted: results of {started} of {len(grid)} settings (last may be partial)"
            )
            sys.stdout.flush()
            raise KeyboardInterrupt  # run_guarded: "interrupted" on stderr, exit 130
        return 0

    return run_guarded(PROG, body)


if __name__ == "__main__":
    raise SystemExit(main())
