"""Benchmark every branch of a 7R arm: ours (``all_branches=True``) against ssik's prebuilt module.

Arms: those ssik ships that we have. Panda and xArm7 are ours (shipped tables); FR3, Gen3 and
iiwa14 are ssik's own chains (``ssik.prebuilt.<maker>.<arm>_ik``: joint origins, axes, limits and
tool, the maker's URDF as ssik baked it) written as URDFs and read by ``kin`` as any user's
``--robot FILE.urdf``. Targets: the tool pose of random joint vectors inside the limits (ssik's
base and tool frames are ours). Timed: ``get_solver(robot).solve(target, all_branches=True)``
(the default seed) and ssik's ``solve(T)`` (native, full enumeration: its fastest documented
path), taking turns target by target (the first alternating), one call each; medians of single
calls, ``ratio`` = ours / ssik. Branches: the medians of the counts each returns (ours over a
grid of 32 free-joint values, the seed's and the answer's; ssik's over its own sampling);
``>= ssik at its values``: the targets where ours at the free-joint values of ssik's answers
verifies at least as many branches as ssik returns.

    python scripts/bench_ik_7r_branches.py
    python scripts/bench_ik_7r_branches.py --arms panda gen3 --targets 500
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import importlib  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from types import ModuleType  # noqa: E402

import numpy as np  # noqa: E402

from kin import RobotModel, load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402
from kin.ik import PoseTarget, get_solver  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ssik_chains import ssik_urdf  # noqa: E402

#: arm -> (our shipped robot, or None: ssik's chain as a URDF; ssik's prebuilt module).
ARMS: dict[str, tuple[str | None, str]] = {
    "fr3": (None, "franka.fr3_ik"),
    "gen3": (None, "kinova.gen3_ik"),
    "iiwa14": (None, "kuka.iiwa14_ik"),
    "panda": ("panda", "franka.panda_ik"),
    "xarm7": ("xarm7", "ufactory.xarm7_ik"),
}


def load_arm(arm: str, folder: Path) -> tuple[RobotModel, ModuleType]:
    """Our robot of ``arm`` (its ssik chain written into ``folder`` when we do not ship it), ssik's module."""
    shipped, module_name = ARMS[arm]
    module = importlib.import_module(f"ssik.prebuilt.{module_name}")
    if shipped is not None:
        return load_robot(shipped), module
    path = folder / f"{arm}.urdf"
    path.write_text(ssik_urdf(module, arm), encoding="utf-8")
    return load_robot(path), module


def bench_arm(arm: str, robot: RobotModel, module: ModuleType, targets: int, seed: int) -> str:
    """One row of the table: times, branch counts, the comparison at ssik's values."""
    from kin.batch_fk import batch_forward_kinematics
    from kin.ik.numeric.all_branches import solve_all_branches

    solver = get_solver(robot)
    free = solver.closed_form.free  # type: ignore[attr-defined]
    rng = np.random.default_rng(seed)
    q_all = rng.uniform(robot.lower, robot.upper, (targets, robot.nq))
    poses = batch_forward_kinematics(robot.table, q_all)
    times: dict[str, list[float]] = {"ours": [], "ssik": []}
    counts: dict[str, list[int]] = {"ours": [], "ssik": []}
    at_least = answered = 0
    for k, pose in enumerate(poses):
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        calls = {
            "ours": lambda: solver.solve(target, all_branches=True).solutions,  # noqa: B023
            "ssik": lambda: module.solve(pose),  # noqa: B023
        }
        found = {}
        for name in ("ours", "ssik") if k % 2 == 0 else ("ssik", "ours"):
            start = time.perf_counter()
            found[name] = calls[name]()
            times[name].append(time.perf_counter() - start)
            counts[name].append(len(found[name]))
        values = [s.q[free] for s in found["ssik"]]
        if values:
            answered += 1
            ours = solve_all_branches(solver, target, free_values=values)
            at_least += len(ours.solutions) >= len(values)
    ours_ms = statistics.median(times["ours"]) * 1e3
    ssik_ms = statistics.median(times["ssik"]) * 1e3
    return (
        f"| {arm} | {targets} | {ours_ms:.3f} | {ssik_ms:.3f} | {ours_ms / ssik_ms:.2f} | "
        f"{statistics.median(counts['ours']):g} | {statistics.median(counts['ssik']):g} | "
        f"{at_least}/{answered} |"
    )


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments of the benchmark."""
    parser = ArgumentParser(prog="bench_ik_7r_branches.py", description=__doc__)
    parser.add_argument("--arms", nargs="+", choices=tuple(ARMS), default=list(ARMS))
    parser.add_argument("--targets", type=positive_int, default=100, help="targets per arm (100)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random targets (0)")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print the table; exit 2 when ssik is not installed."""
    args = get_argument_parser().parse_args(argv)
    try:
        import ssik
    except ImportError:
        print("bench_ik_7r_branches.py: ssik is not installed: pip install ssik")
        return 2
    print(f"ssik {ssik.__version__}; medians of single calls [ms], alternating per target")
    print(
        "| arm | targets | ours all_branches [ms] | ssik solve [ms] | ratio | ours branches | "
        "ssik solutions | >= ssik at its values |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for arm in args.arms:
            robot, module = load_arm(arm, Path(folder))
            print(bench_arm(arm, robot, module, args.targets, args.seed), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
