"""Certify kin.plan.plan's paths with an independent check: many plans, 0 collisions expected.

Issue 44, item 3: every path kin returns is collision-free between its joint vectors. Here
``--n`` plans (default 1,000) over Panda and UR5 as their makers ship them (example-robot-data's
URDF and SRDF) and UR10's DH table (``kin.load_robot("ur10")``), in cells of four kinds
(``table``, ``shelves``, ``box``, ``cage``: scripts/plan_problems.py), the arms and kinds taken in
turn, a new cell drawn every five plans. Start and goal are drawn free (kin's checker and the
reference agree); three plans in four have a blocked straight joint line, the fourth may be
straight. Every returned path
is resampled so that no joint moves more than 0.005 rad between two checked configurations, and
each configuration judged by the reference (scripts/plan_reference.py: Pinocchio's own URDF
parser and FK of the full URDF, coal's convex hulls and boxes, built apart from kin.collision).

Prints, per arm and scene and in all: plans made, paths returned (``ok``), configurations
checked, collisions found (must be 0) and the smallest distance seen [mm]; each collision is
printed whole (problem, start, goal, sample, pair). Progress on stderr; Ctrl-C prints what is
done.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from plan_problems import ARMS, SCENES, draw_problem, load_arm  # noqa: E402

from kin.cli import ArgumentParser, positive_float, positive_int  # noqa: E402

#: The arms certified (issue 44: Panda with its SRDF, UR5, a DH arm).
CERTIFY_ARMS = ("panda", "ur5", "ur10-dh")
#: Plans made in each cell before the next cell is drawn.
SCENE_PLANS = 5


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="certify_plans.py", description=__doc__)
    add = parser.add_argument
    add("--n", type=positive_int, default=1000, help="plans to make (default 1000)")
    add("--time-limit", type=positive_float, default=10.0, help="cap of a plan [s] (default 10)")
    add("--seed", type=int, default=0, help="seed of the problem generator (default 0)")
    return parser


def certify(n: int, time_limit: float, seed: int, records: list[dict]) -> None:
    """Make ``n`` plans and judge each returned path; append one record per plan."""
    from kin.plan import plan

    robots = {name: load_arm(ARMS[name]) for name in CERTIFY_ARMS}
    combos = [(a, s) for a in CERTIFY_ARMS for s in SCENES]
    cell = None
    with tempfile.TemporaryDirectory() as folder:
        for i in range(n):
            block = i // SCENE_PLANS  # a new cell every SCENE_PLANS plans
            name, kind = combos[block % len(combos)]
            arm, robot = ARMS[name], robots[name]
            rng = np.random.default_rng([seed, i])
            if i % SCENE_PLANS == 0:
                cell = None
            drawn = None
            while drawn is None:
                drawn = draw_problem(
                    arm, robot, kind, rng, Path(folder), f"{name}-{kind}{block}-{i}", i % 4 != 0,
                    cell,
                )  # fmt: skip
                cell = drawn[1] if drawn else None
            problem, cell = drawn
            result = plan(
                robot, problem.start, problem.goal, collisions=cell.checker, seed=i,
                time_limit=time_limit,
            )  # fmt: skip
            record = {"arm": name, "scene": kind, "status": result.status, "samples": 0}
            if result.success:
                verdict = cell.reference.judge(result.path)
                record.update(samples=verdict.samples, closest=verdict.smallest)
                if not verdict.free:
                    record["collision"] = (
                        f"{problem.id}: start {problem.start.tolist()} goal "
                        f"{problem.goal.tolist()} path {result.path.tolist()} first contact "
                        f"(sample, q, pair) {verdict.first}"
                    )
                    print(f"COLLISION {record['collision']}", file=sys.stderr, flush=True)
            records.append(record)
            print(
                f"[{i + 1}/{n}] {problem.id}: {result.status} {result.plan_time:.2f} s, "
                f"{len(result.path)} joint vectors, {record['samples']} samples judged",
                file=sys.stderr,
                flush=True,
            )


def print_table(records: list[dict]) -> None:
    """Per arm and scene, and in all: plans, paths, samples, collisions, smallest distance."""
    print(
        f"{'arm':<8} {'scene':<8} {'plans':>6} {'ok':>6} {'samples':>9} {'collisions':>10} "
        f"{'closest [mm]':>12}"
    )
    groups = [(a, s) for a in CERTIFY_ARMS for s in SCENES] + [("all", "")]
    for arm, scene in groups:
        mine = [r for r in records if arm == "all" or (r["arm"] == arm and r["scene"] == scene)]
        if not mine:
            continue
        ok = [r for r in mine if r["status"] == "ok"]
        closest = min((r["closest"] for r in ok), default=math.nan) * 1e3
        print(
            f"{arm:<8} {scene:<8} {len(mine):>6} {len(ok):>6} "
            f"{sum(r['samples'] for r in ok):>9} {sum('collision' in r for r in ok):>10} "
            f"{closest:>12.4f}"
        )
    for r in records:
        if "collision" in r:
            print(f"collision: {r['collision']}")


def main(argv: list[str] | None = None) -> int:
    """Make the plans, judge them and print the table; exit 1 when a collision was found."""
    args = get_argument_parser().parse_args(argv)
    signal.signal(signal.SIGINT, signal.default_int_handler)  # also when started in the background
    records: list[dict] = []
    try:
        certify(args.n, args.time_limit, args.seed, records)
    except KeyboardInterrupt:
        print("interrupted: the table holds the plans done", file=sys.stderr)
    statuses = sorted({r["status"] for r in records})
    counts = ", ".join(f"{s} {sum(r['status'] == s for r in records)}" for s in statuses)
    print(
        f"{len(records)} plans ({counts}), time cap {args.time_limit:g} s; each path judged "
        "every 0.005 rad of joint motion by Pinocchio + coal built apart from kin"
    )
    print_table(records)
    return 1 if any("collision" in r for r in records) else 0


if __name__ == "__main__":
    raise SystemExit(main())
