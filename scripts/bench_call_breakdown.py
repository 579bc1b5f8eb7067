"""Where the microseconds of one documented IK call go, in this tree.

``python scripts/bench_call_breakdown.py [--targets N] [--reps R] [--arms ...]`` (also
``scripts/bench_per_call.py --breakdown``).

For an arm whose closed form has a compiled twin that verifies (the UR and spherical wrists), the
call ``get_solver(robot).solve(PoseTarget(p, R), seed)`` is taken apart into nested steps, each
timed on its own, the steps taking turns target by target (medians of single calls [us]):

- ``target``: ``PoseTarget(p, R)`` from NumPy arrays (the pose check);
- ``seed``: :func:`kin.configuration.seed_inside` of the seed;
- ``bare closed form``: the twin's ``solve`` of one target (8 branches, nothing else): the peer's
  work;
- ``+ limits and verification``: the twin's ``verify`` (the same branches, each moved into the
  limits and measured by the table's DH product), minus the bare solve;
- ``+ result objects``: the twin's ``solutions`` (the same, and the ``IKResult``), minus verify;
- ``dispatch``: the whole call minus all of the above.

For every arm, then, cProfile's view of 200 calls: the Python functions that take the most time
of their own (per call [us], inflated by the profiler's own cost of about 0.1 us per call).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import cProfile
import pstats
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from kin import load_robot
from kin.configuration import default_seed, seed_inside
from kin.ik import PoseTarget, get_solver

ROOT = Path(__file__).resolve().parent.parent
ARMS = ("ur5", "puma560", "tests/data/six_r/xarm6.toml", "humanoid7")


def poses(robot: Any, n: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Tool poses ``(p [m], R)`` of ``n`` seeded joint vectors inside the limits (Pinocchio FK)."""
    rng = np.random.default_rng(seed)
    model, data = robot.model, robot.model.createData()
    fid = model.getFrameId(robot.tool_frame)
    lower = np.maximum(model.lowerPositionLimit, -np.pi)
    upper = np.minimum(model.upperPositionLimit, np.pi)
    out = []
    for q in rng.uniform(lower, upper, size=(n, robot.nq)):
        pin.framesForwardKinematics(model, data, q)
        out.append((data.oMf[fid].translation.copy(), data.oMf[fid].rotation.copy()))
    return out


def steps(robot: Any, solver: Any, seed: np.ndarray) -> dict[str, Callable[[Any, Any], Any]]:
    """The nested steps of one call, each a ``(pose, target) -> None`` to time."""
    solve = solver.solve
    timed: dict[str, Callable[[Any, Any], Any]] = {
        "target": lambda pose, target: PoseTarget(*pose),
        "seed": lambda pose, target: seed_inside(robot, seed),
    }
    twin = getattr(solver, "_twin", None)
    if twin is not None:
        structure = solver.structure
        bare, params = structure.compiled_twin.solve, structure.c_params
        verify, check = twin._verify, twin._check
        out, q, info = np.empty((1, 8, 6)), np.empty((8, 6)), np.empty((8, 4))
        solutions = solver._solutions

        def solve_bare(pose: Any, target: Any) -> None:
            bare(params, pose[0].reshape(1, 3), pose[1].reshape(1, 3, 3), 0.0, out)

        def solve_verify(pose: Any, target: Any) -> None:
            verify(params, check, pose[0], pose[1], seed, 0.0, q, info)

        timed["bare closed form"] = solve_bare
        timed["verify"] = solve_verify
        timed["solutions"] = lambda pose, target: solutions(target, seed, 0.0)
    timed["call"] = lambda pose, target: solve(PoseTarget(*pose), seed)
    return timed


def median_times(robot: Any, targets: list[Any], reps: int) -> dict[str, float]:
    """Median single-call time [us] of each step, the steps taking turns target by target."""
    solver = get_solver(robot)
    seed = default_seed(robot)
    timed = steps(robot, solver, seed)
    built = [PoseTarget(*pose) for pose in targets]
    for pose, target in zip(targets, built):  # warm up
        for step in timed.values():
            step(pose, target)
    samples: dict[str, list[float]] = {name: [] for name in timed}
    perf = time.perf_counter
    for pose, target in zip(targets, built):
        for name, step in timed.items():
            for _ in range(reps):
                start = perf()
                step(pose, target)
                samples[name].append(perf() - start)
    return {name: statistics.median(values) * 1e6 for name, values in samples.items()}


def profile(
    robot: Any, targets: list[Any], top: int = 8, rounds: int = 5
) -> list[tuple[float, str]]:
    """The own time per call (cProfile) [us] of the ``top`` costliest functions of the call.

    Each function's least over ``rounds`` profiled passes of the targets (a pass that another
    job on the machine slowed down only adds time).
    """
    solve, seed = get_solver(robot).solve, default_seed(robot)
    for pose in targets:
        solve(PoseTarget(*pose), seed)
    least: dict[str, float] = {}
    for _ in range(rounds):
        profiler = cProfile.Profile()
        profiler.enable()
        for pose in targets:
            solve(PoseTarget(*pose), seed)
        profiler.disable()
        stats = pstats.Stats(profiler).stats  # type: ignore[attr-defined]
        for (path, line, function), (_, calls, own, _, _) in stats.items():
            if function == "<method 'disable' of '_lsprof.Profiler' objects>":
                continue
            where = f"{Path(path).name}:{line}({function})" if line else function
            key = f"{where} x{calls / len(targets):.3g}"
            value = own / len(targets) * 1e6
            least[key] = min(least.get(key, value), value)
    return sorted(((v, k) for k, v in least.items()), reverse=True)[:top]


def breakdown(arms: tuple[str, ...], n: int, reps: int, seed: int) -> None:
    """Print the breakdown of each arm's call."""
    for arm in arms:
        robot = load_robot(ROOT / arm if "/" in arm else arm)
        targets = poses(robot, n, seed)
        medians = median_times(robot, targets, reps)
        name = get_solver(robot).name
        print(f"\n{Path(arm).stem} ({name}), {n} targets x {reps} single calls, medians [us]:")
        parts = [("target: PoseTarget(p, R)", medians["target"])]
        parts.append(("seed: seed_inside", medians["seed"]))
        rest = medians["call"] - medians["target"] - medians["seed"]
        if "bare closed form" in medians:
            bare, verify, whole = (
                medians["bare closed form"],
                medians["verify"],
                medians["solutions"],
            )
            parts += [
                ("bare closed form (twin solve)", bare),
                ("+ limits and verification (twin verify)", verify - bare),
                ("+ result objects (twin solutions)", whole - verify),
            ]
            rest -= whole
            parts.append(("dispatch (the rest)", rest))
            above = medians["call"] - bare
            parts.append(
                (f"whole call ({above:.2f} us above the bare closed form)", medians["call"])
            )
        else:
            parts.append(("the solve (target and seed aside)", rest))
            parts.append(("whole call", medians["call"]))
        for label, value in parts:
            print(f"  {label:55s} {value:8.2f}")
        print("  under cProfile, own time per call [us] (inflated by the profiler):")
        for own, where in profile(robot, targets[:200]):
            print(f"    {own:8.2f}  {where}")


def main(argv: list[str] | None = None) -> int:
    """Run the breakdown."""
    from kin.cli import ArgumentParser, positive_int

    parser = ArgumentParser(prog="bench_call_breakdown.py", description=__doc__)
    parser.add_argument("--targets", type=positive_int, default=200, help="targets per arm (200)")
    parser.add_argument("--reps", type=positive_int, default=5, help="single calls per target (5)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the joint vectors (0)")
    parser.add_argument("--arms", nargs="+", default=ARMS, help=f"arms (default: {' '.join(ARMS)})")
    options = parser.parse_args(sys.argv[1:] if argv is None else argv)
    breakdown(tuple(options.arms), options.targets, options.reps, options.seed)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
