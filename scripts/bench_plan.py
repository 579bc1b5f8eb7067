"""Benchmark kin.plan.plan beside mplib and a plain OMPL + coal loop; print a table per arm and scene.

Problems (scripts/bench_plan_problems.json, made once by ``--regenerate`` from a seeded
generator, scripts/plan_problems.py): Panda and UR5 as their makers ship them (example-robot-data's
URDF and SRDF, meshes as convex hulls) in four kinds of cell made of boxes (``table``,
``shelves``, ``box``, ``cage``), 15 problems each: start and goal joint vectors [rad], both free
(kin's checker and the reference agree), the straight joint line between them blocked.

Planners, their order turned by one at each problem (the machine is shared):

* ``kin``: :func:`kin.plan.plan` (RRTConnect on kin's certified motion rule, simplified);
* ``kin+turns``: the same with ``any_turn=True``: the goal's whole-turn copies within the limits
  are goals too, as mplib offers them;
* ``mplib``: mplib's RRTConnect (``Planner.planner.plan``, range 0.1, simplified, meshes as convex
  hulls, the same self pairs as kin) in its own venv and process (scripts/plan_peers.py); its
  path is judged as it moves, straight in joint space between its joint vectors (mplib plans on
  R^n for bounded joints and offers the goal's whole-turn twins as goals too: a UR5 path may end
  a turn away from the goal, the same place of the arm);
* ``ompl+coal``: the ``ompl`` wheel's SimpleSetup + RRTConnect + ``simplifySolution`` with a
  Pinocchio + coal validity callback, OMPL's discrete motion check at its default resolution
  (1 % of the space's extent: 0.13 rad on Panda) and at 0.02 rad (``ompl+coal .02``).

Every returned path is judged by the reference (scripts/plan_reference.py: Pinocchio + coal built
apart from kin) at every 0.005 rad of joint motion: ``certified`` is the share of returned paths
with no contact there, ``closest`` the smallest distance seen [mm] (negative: penetration).
Plan times are single calls (one per problem); ``/straight`` is a path's length over the straight
joint line's to the configuration it reaches. ``--optimal-every K``: kin's path against
kin.plan.plan with AORRTC (an asymptotically optimal RRT-Connect) given 10x the configurations
kin's RRTConnect checked, on every K-th problem kin solved. Progress on stderr; Ctrl-C prints
what is done.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import json  # noqa: E402
import signal  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from plan_problems import ARMS, SCENES, Problem, draw_problem, load_arm  # noqa: E402
from plan_reference import Reference  # noqa: E402

from kin.cli import ArgumentParser, positive_float, positive_int  # noqa: E402

PROBLEMS = Path(__file__).with_name("bench_plan_problems.json")
#: The arms of the benchmark (issue 44: Panda and UR5).
BENCH_ARMS = ("panda", "ur5")
PLANNERS = ("kin", "kin+turns", "mplib", "ompl+coal", "ompl+coal .02")


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_plan.py", description=__doc__)
    add = parser.add_argument
    add("--problems", type=Path, default=PROBLEMS, help="problem file (default %(default)s)")
    add("--regenerate", action="store_true", help="draw the problems again and write the file")
    add("--count", type=positive_int, default=15, help="problems per arm and scene (default 15)")
    add("--quick", action="store_true", help="the first problem of each arm and scene, cap 5 s")
    add("--no-mplib", action="store_true", help="leave mplib out")
    add("--arm", choices=BENCH_ARMS, help="only this arm's problems (seeds as in the whole run)")
    add("--time-limit", type=positive_float, default=10.0, help="cap of a plan [s] (default 10)")
    add("--optimal-every", type=int, default=4, help="AORRTC on every K-th solved (0: none)")
    return parser


def make_problems(count: int) -> list[Problem]:
    """``count`` problems per arm and scene from seeded generators (progress on stderr)."""
    problems = []
    with tempfile.TemporaryDirectory() as folder:
        for a, name in enumerate(BENCH_ARMS):
            arm, robot = ARMS[name], load_arm(ARMS[name])
            for s, kind in enumerate(SCENES):
                for i in range(count):
                    rng = np.random.default_rng([a, s, i])
                    drawn = None
                    while drawn is None:
                        drawn = draw_problem(
                            arm, robot, kind, rng, Path(folder), f"{name}-{kind}-{i:02d}", True
                        )
                    problems.append(drawn[0])
                    print(f"  drew {drawn[0].id}", file=sys.stderr, flush=True)
    return problems


def run_problem(problem: Problem, index: int, planners, cells, args, mplib) -> list[dict]:
    """Every planner on one problem, the order turned by ``index``; one record each."""
    from kin.plan import plan, prepare

    arm, robot, cell = cells(problem)
    baseline = Reference(arm, robot, cell.model, problem.boxes)  # the plain loop's own check
    records = []
    k = index % len(planners)
    for planner in planners[k:] + planners[:k]:
        path, extra = None, {}
        if planner.startswith("kin"):
            began = time.perf_counter()  # the cell's spheres and tests, once per scene
            prepare(cell.checker)
            if planner == "kin":
                extra["setup"] = time.perf_counter() - began
            result = plan(
                robot, problem.start, problem.goal, collisions=cell.checker, seed=index,
                time_limit=args.time_limit, any_turn=planner == "kin+turns",
            )  # fmt: skip
            status, elapsed = result.status, result.plan_time
            path = result.path if result.success else None
            extra["checks"] = result.checks
        elif planner == "mplib":
            answer = mplib.solve(arm, robot, cell.model, problem, args.time_limit, index + 1)
            status = answer.get("status", "error: " + str(answer.get("error")))
            elapsed = answer.get("plan_time", float("nan"))
            if answer.get("path"):
                path = np.array(answer["path"])
        else:
            from plan_peers import plain_ompl

            step = 0.02 if planner.endswith(".02") else None
            status, elapsed, path = plain_ompl(
                baseline, *_bounds(robot), problem.start, problem.goal, args.time_limit, step, index
            )
        records.append(_record(problem, planner, status, elapsed, path, cell, extra))
    return records


def _bounds(robot) -> tuple[np.ndarray, np.ndarray]:
    lower = np.where(np.isfinite(robot.lower), robot.lower, -np.pi)
    upper = np.where(np.isfinite(robot.upper), robot.upper, np.pi)
    return lower, upper


def _record(problem, planner, status, elapsed, path, cell, extra) -> dict:
    record = {"id": problem.id, "arm": problem.arm, "scene": problem.scene, "planner": planner}
    record.update(status=status, time=elapsed, **extra)
    if path is not None:
        verdict = cell.reference.judge(path)
        length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
        straight = float(np.linalg.norm(path[-1] - path[0]))
        record.update(
            length=length, ratio=length / straight if straight > 0 else 1.0,
            certified=verdict.free, closest=verdict.smallest, first=verdict.first,
        )  # fmt: skip
        if not verdict.free and planner.startswith("kin"):
            print(
                f"NOT CERTIFIED: kin's path on {problem.id} (start {problem.start.tolist()}, "
                f"goal {problem.goal.tolist()}): sample {verdict.first}", file=sys.stderr,
            )  # fmt: skip
    return record


def _p95(values: list[float]) -> float:
    return float(np.percentile(values, 95)) if values else float("nan")


def _median(values: list[float]) -> float:
    return statistics.median(values) if values else float("nan")


def print_tables(records: list[dict], planners, note: dict) -> None:
    """One table per arm and scene: solved, plan times, length, certified share."""
    header = (
        f"{'planner':<14} {'solved':>7} {'median [ms]':>11} {'p95 [ms]':>9} {'length [rad]':>12} "
        f"{'/straight':>9} {'certified':>9} {'closest [mm]':>12}"
    )
    for arm in BENCH_ARMS:
        for scene in SCENES:
            rows = [r for r in records if r["arm"] == arm and r["scene"] == scene]
            if not rows:
                continue
            count = len({r["id"] for r in rows})
            print(f"\n{arm} / {scene}: {count} problems")
            print(header)
            for planner in planners:
                mine = [r for r in rows if r["planner"] == planner]
                if planner in note:
                    print(f"{planner:<14} {note[planner]}")
                    continue
                if not mine:
                    continue
                paths = [r for r in mine if "length" in r]
                solved = [r for r in mine if r["status"] == "ok"]
                times = [r["time"] for r in solved]
                good = sum(r["certified"] for r in paths)
                share = _share(good, len(paths))
                closest = min((r["closest"] for r in paths), default=float("nan")) * 1e3
                print(
                    f"{planner:<14} {len(solved) / len(mine):>7.0%} {1e3 * _median(times):>11.1f} "
                    f"{1e3 * _p95(times):>9.1f} {_median([r['length'] for r in paths]):>12.3f} "
                    f"{_median([r['ratio'] for r in paths]):>9.2f} {share:>9} {closest:>12.3f}"
                )
            setups = [r["setup"] for r in rows if "setup" in r]
            if setups:
                print(
                    f"kin's setup of the cell (kin.plan.prepare: its spheres' tests and exact rule, "
                    f"once per scene, before the plan): median {_median(setups):.3f} s, max {max(setups):.3f} s"
                )


def _share(good: int, total: int) -> str:
    """A share as a percentage that says 100 % only when every one counts."""
    if total == 0:
        return "-"
    if good == total:
        return "100%"
    return f"{min(100.0 * good / total, 99.9):.1f}%"


def optimal_subset(problems, records, every: int, cells, time_limit: float) -> list[dict]:
    """The kin RRTConnect path against AORRTC given 10x its checks, on every ``every``-th solved."""
    from kin.plan import plan

    solved = [r for r in records if r["planner"] == "kin" and r["status"] == "ok"]
    by_id = {p.id: p for p in problems}
    out = []
    for n, record in enumerate(solved[::every]):
        problem = by_id[record["id"]]
        arm, robot, cell = cells(problem)
        result = plan(
            robot, problem.start, problem.goal, collisions=cell.checker, planner="AORRTC",
            max_checks=10 * max(record["checks"], 1000), time_limit=10 * time_limit,
        )  # fmt: skip
        entry = {"arm": problem.arm, "scene": problem.scene, "kin": record["length"]}
        entry["status"] = result.status
        if result.success:
            entry["optimal"] = result.length
            entry["certified"] = cell.reference.judge(result.path).free
        out.append(entry)
        print(f"  AORRTC {n + 1}: {problem.id} {result.status}", file=sys.stderr, flush=True)
    return out


def print_optimal(entries: list[dict]) -> None:
    """The optimizing planner's table: path lengths [rad], medians per arm and scene."""
    print("\nkin's path against AORRTC with 10x kin's checks (path lengths [rad], medians)")
    print(
        f"{'arm':<6} {'scene':<8} {'n':>3} {'kin':>7} {'AORRTC':>7} {'kin/AORRTC':>10} {'certified':>9}"
    )
    for arm in BENCH_ARMS:
        for scene in SCENES:
            mine = [
                e for e in entries if e["arm"] == arm and e["scene"] == scene and "optimal" in e
            ]
            if not mine:
                continue
            ratio = _median([e["kin"] / e["optimal"] for e in mine])
            good = _share(sum(e["certified"] for e in mine), len(mine))
            print(
                f"{arm:<6} {scene:<8} {len(mine):>3} {_median([e['kin'] for e in mine]):>7.3f} "
                f"{_median([e['optimal'] for e in mine]):>7.3f} {ratio:>10.2f} {good:>9}"
            )


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print its tables; exit 0 (also after Ctrl-C)."""
    args = get_argument_parser().parse_args(argv)
    signal.signal(signal.SIGINT, signal.default_int_handler)  # also when started in the background
    if args.regenerate or not args.problems.exists():
        problems = make_problems(args.count)
        rows = ",\n".join(json.dumps(p.as_json(), separators=(",", ":")) for p in problems)
        args.problems.write_text('{"problems": [\n' + rows + "\n]}\n")  # a problem a line
    problems = [Problem.from_json(p) for p in json.loads(args.problems.read_text())["problems"]]
    if args.quick:
        problems = [p for p in problems if p.id.endswith("-00")]
        args.time_limit = min(args.time_limit, 5.0)
        args.optimal_every = 0
    planners = [p for p in PLANNERS if not (p == "mplib" and args.no_mplib)]
    note: dict[str, str] = {}
    mplib = None
    if "mplib" in planners:
        from plan_peers import MplibWorker

        mplib = MplibWorker()
        if not mplib.available:
            note["mplib"] = f"not run: mplib cannot be installed here ({mplib.reason})"
            planners.remove("mplib")
    cells = _Cells()
    records: list[dict] = []
    entries: list[dict] = []
    try:
        for index, problem in enumerate(problems):
            if args.arm and problem.arm != args.arm:
                continue
            done = run_problem(problem, index, planners, cells, args, mplib)
            records += done
            summary = ", ".join(f"{r['planner']} {r['status']} {r['time']:.2f} s" for r in done)
            print(
                f"[{index + 1}/{len(problems)}] {problem.id}: {summary}",
                file=sys.stderr,
                flush=True,
            )
        if args.optimal_every > 0:
            entries = optimal_subset(problems, records, args.optimal_every, cells, args.time_limit)
    except KeyboardInterrupt:
        print("interrupted: the tables hold the problems done", file=sys.stderr)
    finally:
        if mplib is not None:
            mplib.close()
        cells.close()
    print(
        f"{len({r['id'] for r in records})} problems, time cap {args.time_limit:g} s, "
        f"{os.cpu_count()} cores; paths judged every 0.005 rad by Pinocchio + coal"
    )
    print_tables(records, planners + list(note), note)
    if entries:
        print_optimal(entries)
    return 0


class _Cells:
    """The arms and cells of the problems, built once each (kin reads scenes from files)."""

    def __init__(self):
        self.folder = tempfile.TemporaryDirectory()
        self.robots: dict = {}
        self.cells: dict = {}

    def __call__(self, problem: Problem):
        from plan_problems import Cell

        arm = ARMS[problem.arm]
        if arm.name not in self.robots:
            self.robots[arm.name] = load_arm(arm)
        robot = self.robots[arm.name]
        if problem.id not in self.cells:
            folder = Path(self.folder.name) / problem.id
            folder.mkdir(exist_ok=True)
            self.cells = {problem.id: Cell(arm, robot, problem.boxes, folder)}  # keep one
        return arm, robot, self.cells[problem.id]

    def close(self) -> None:
        self.folder.cleanup()


if __name__ == "__main__":
    raise SystemExit(main())
