"""Benchmark the planner's checks with and without the spheres; print tables (issue 44, item 4).

Three parts, on this machine (shared: the ratios are the figures to read):

* ``shapes``: per link, the spheres that enclose its shapes (kin.collision.sphere_fit) and the
  largest gap between them and the shapes [mm] (the farthest point of the spheres' union from
  the shapes, coal's distance from points of the union's boundary), for Panda and UR5 as their
  makers ship them (example-robot-data's URDF and SRDF, meshes as their convex hulls) and the
  shipped UR5 and humanoid7 DH tables;
* ``one check``: median single-call time [us] at random configurations in examples/cell.toml,
  alternated per configuration: the checker's verdict (``in_collision``), the distances of every
  pair (what the motion rule needs at the ends of a motion), the spheres' bounds of every pair,
  and the fast verdict (bounds first, coal only for the pairs they leave undecided); with the
  share of configurations the bounds alone call free;
* ``plans``: plan time [s] and checks of the same problems in four modes, alternated per
  problem: ``before`` (every pair measured at every midpoint of the motion rule, the full
  verdict there: the rule as it was), ``exact`` (only the pairs the rule has not shown apart),
  ``spheres`` (and the spheres' bounds from the first check) and ``default`` (the spheres after
  ``FAST_AFTER`` checks). Problems: the README's UR5 pose, UR5 around the cell's wall, Panda
  around a box, and ``--per`` problems of each arm and scene of scripts/bench_plan_problems.json
  (scripts/plan_problems.py). The column ``same`` says every mode found the same path with the
  same checks. The spheres are fitted before the timing (``fit`` says how long it took, once a
  model).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import json  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from contextlib import ExitStack  # noqa: E402
from pathlib import Path  # noqa: E402
from unittest import mock  # noqa: E402

import numpy as np  # noqa: E402
from bench_collision import _alternate  # noqa: E402
from bench_ik_urdf import erd  # noqa: E402

from kin import load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402
from kin.collision import CollisionChecker, load_collision_model  # noqa: E402
from kin.collision.sphere_bound import sphere_bound  # noqa: E402
from kin.ik import PoseTarget  # noqa: E402
from kin.path.pair_distances import PairDistances  # noqa: E402
from kin.plan import ompl_problem, plan  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CELL = ROOT / "examples" / "cell.toml"
PROBLEMS = ROOT / "scripts" / "bench_plan_problems.json"
BOX = "[[box]]\nname = 'box'\nsize = [0.2, 0.2, 0.2]\nxyz = [0.5, 0.0, 0.3]\n"
#: name -> (URDF in example-robot-data or a shipped table, tip, SRDF or None).
ARMS = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_hand", "panda_description/srdf/panda.srdf"),
    "ur5 (URDF)": ("ur_description/urdf/ur5_robot.urdf", "tool0", "ur_description/srdf/ur5.srdf"),
    "ur5": ("ur5", None, None),
    "humanoid7": ("humanoid7", None, None),
}  # fmt: skip
MODES = ("before", "exact", "spheres", "default")
#: Runs of each mode per problem (the fastest kept: the machine is shared).
REPEAT = 2


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_plan_checks.py", description=__doc__)
    parser.add_argument(
        "--configurations",
        type=positive_int,
        default=2000,
        help="random configurations of the single-check timings (default 2000)",
    )
    parser.add_argument(
        "--per",
        type=int,
        default=3,
        help="problems of each arm and scene of scripts/bench_plan_problems.json (default 3; 0: none)",
    )
    parser.add_argument(
        "--samples", type=positive_int, default=200, help="points per sphere of the gaps (200)"
    )
    return parser


def _arm(name: str, scene: Path | None):
    robot_name, tip, srdf = ARMS[name]
    robot = load_robot(robot_name) if tip is None else load_robot(erd(robot_name), None, tip)
    model = load_collision_model(robot, srdf=erd(srdf) if srdf else None, scene=scene)
    return robot, CollisionChecker(model)


def shapes(samples: int) -> None:
    """The spheres per link and their largest gap."""
    print("shapes: spheres per link and the largest gap between them and the link's shapes")
    print(f"{'arm':12} {'link':28} {'spheres':>7} {'gap [mm]':>9}")
    for name in ARMS:
        _, checker = _arm(name, None)
        bound = sphere_bound(checker.model)
        counts: dict[str, int] = {}
        for index in bound.objects:
            owner = checker.model.owners[index]
            counts[owner] = counts.get(owner, 0) + 1
        for link, gap in bound.gaps(samples).items():
            print(f"{name:12} {link:28} {counts[link]:7d} {gap * 1e3:9.1f}")
    print()


def one_check(count: int) -> None:
    """Median single-call times of the checks."""
    print("one check [us], median of single calls at random configurations in examples/cell.toml")
    print("(an end of a motion needs the verdict and every pair's distance: exact, or by bounds)")
    print(
        f"{'arm':12} {'pairs':>5} {'verdict':>8} {'distances':>9} {'bounds':>7} "
        f"{'end exact':>9} {'end fast':>9} {'free by bounds':>15}"
    )
    for name in ("panda", "ur5 (URDF)", "ur5"):
        robot, checker = _arm(name, CELL)
        bound = sphere_bound(checker.model)
        exact, fast = PairDistances(checker), PairDistances(checker, fast=True)
        ends = PairDistances(checker)  # its own remembered distances (no hit from ``exact``'s)

        def end_exact(q: np.ndarray) -> None:
            checker.in_collision(q)
            ends.at(q)

        def end_fast(q: np.ndarray) -> None:
            fast.at(q)
            fast.in_collision(q)

        rng = np.random.default_rng(0)  # every call at a configuration of its own (no cache hit)
        qs = rng.uniform(robot.lower, robot.upper, (count, robot.nq))
        functions = [checker.in_collision, exact.at, bound.lower_bounds, end_exact, end_fast]
        times = _alternate(functions, qs, len(functions))
        decided = float(np.mean((bound.lower_bounds(qs) > 2e-5).all(axis=1)))
        print(
            f"{name:12} {fast.count:5d} {times[0]:8.1f} {times[1]:9.1f} {times[2]:7.1f} "
            f"{times[3]:9.1f} {times[4]:9.1f} {decided:14.1%}"
        )
    print()


def _problems(per: int, folder: Path) -> list[tuple[str, object, CollisionChecker, object, object]]:
    """(name, robot, checker, start, goal) of the benchmark's problems."""
    robot, ur5_cell = _arm("ur5", CELL)
    readme = PoseTarget(np.array([0.3, -0.3, 0.3]), np.diag([1.0, -1.0, -1.0]))
    box = folder / "box.toml"
    box.write_text(BOX, encoding="utf-8")
    panda, panda_box = _arm("panda", box)
    found = [
        ("README ur5", robot, ur5_cell, np.radians([-69, -74, 80, -92, -86, 0]), readme),
        ("ur5 wall", robot, ur5_cell, np.array([-1.2, -1.3, 1.4, -1.6, -1.5, 0.0]),
         np.array([2.0, -1.2, 1.2, -1.6, -1.5, 0.3])),
        ("panda box", panda, panda_box, np.array([-1.0, 0.3, 0.0, -1.8, 0.0, 2.0, 0.8]),
         np.array([1.0, 0.3, 0.0, -1.8, 0.0, 2.0, 0.8])),
    ]  # fmt: skip
    if per <= 0 or not PROBLEMS.exists():
        return found
    from plan_problems import ARMS as SHARED
    from plan_problems import Problem, collision_model, load_arm, scene_toml

    taken: dict[tuple[str, str], int] = {}
    robots: dict[str, object] = {}
    for item in json.loads(PROBLEMS.read_text(encoding="utf-8"))["problems"]:
        key = (item["arm"], item["scene"])
        if taken.get(key, 0) >= per or item["arm"] not in SHARED:
            continue
        taken[key] = taken.get(key, 0) + 1
        problem = Problem.from_json(item)
        arm = SHARED[problem.arm]
        robot = robots.setdefault(problem.arm, load_arm(arm))
        scene = folder / f"{problem.id}.toml"
        scene.write_text(scene_toml(problem.boxes), encoding="utf-8")
        checker = CollisionChecker(collision_model(arm, robot, scene))
        found.append((problem.id, robot, checker, problem.start, problem.goal))
    return found


def _plan(mode: str, robot, checker, start, goal):  # noqa: ANN001
    """One plan in ``mode`` (the module): (result, seconds)."""
    with ExitStack() as stack:
        after = {"spheres": 0, "default": ompl_problem.FAST_AFTER}.get(mode, 10**12)
        stack.enter_context(mock.patch.object(ompl_problem, "FAST_AFTER", after))
        if mode == "before":  # every pair at every midpoint, and the checker's verdict there
            stack.enter_context(
                mock.patch.object(PairDistances, "of", lambda self, q, *_: self.at(q))
            )
        began = time.perf_counter()
        result = plan(robot, start, goal, collisions=checker, seed=0)
        return result, time.perf_counter() - began


def plans(per: int) -> None:
    """Plan times and checks per mode."""
    with tempfile.TemporaryDirectory() as folder:
        problems = _problems(per, Path(folder))
        print(
            "plans: time [s] per mode (the faster of two runs), seed 0; same: every mode the "
            "same path and checks (cap: the time cap ended a search)"
        )
        print(f"{'problem':18} {'status':10} {'fit [s]':>7} " + " ".join(f"{m:>9}" for m in MODES)
              + f" {'checks':>7} {'same':>5}")  # fmt: skip
        times: dict[str, list[float]] = {m: [] for m in MODES}  # the problems solved in all
        rates: dict[str, list[float]] = {m: [] for m in MODES}  # capped: checks per second
        for name, robot, checker, start, goal in problems:
            began = time.perf_counter()
            sphere_bound(checker.model)
            fit = time.perf_counter() - began
            results, seconds = {}, {m: [] for m in MODES}
            for _ in range(REPEAT):  # modes alternated, the faster of each mode's runs kept
                for mode in MODES:
                    results[mode], taken = _plan(mode, robot, checker, start, goal)
                    seconds[mode].append(taken)
            first = results["before"]
            same = all(
                np.array_equal(r.path, first.path) and r.checks == first.checks
                for r in results.values()
            )
            capped = any(r.status == "timeout" for r in results.values())
            for mode in MODES:
                if capped:
                    rates[mode].append(results[mode].checks / seconds[mode][-1])  # its last run
                else:
                    times[mode].append(min(seconds[mode]))
            print(
                f"{name:18} {first.status:10} {fit:7.3f} "
                + " ".join(f"{min(seconds[m]):9.3f}" for m in MODES)
                + f" {first.checks:7d} {'cap' if capped else 'yes' if same else 'NO':>5}"
            )
        if times["before"]:
            print(f"solved by every mode ({len(times['before'])}):")
            for label, figure in (("median [s]", statistics.median), ("total [s]", sum)):
                print(f"{label:37} " + " ".join(f"{figure(times[m]):9.3f}" for m in MODES))
            ratios = [
                statistics.median(np.array(times["before"]) / np.array(times[m])) for m in MODES
            ]
            print(f"{'median speed-up over before':37} " + " ".join(f"{r:9.2f}" for r in ratios))
        if rates["before"]:
            print(f"capped by the time limit ({len(rates['before'])}): median checks per second")
            print(f"{'':37} " + " ".join(f"{statistics.median(rates[m]):9.0f}" for m in MODES))


def main(argv: list[str] | None = None) -> int:
    """Print the three tables."""
    args = get_argument_parser().parse_args(argv)
    shapes(args.samples)
    one_check(args.configurations)
    plans(args.per)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
