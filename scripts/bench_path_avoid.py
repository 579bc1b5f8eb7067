"""Benchmark ``kin path --avoid`` (kin.path.follow_path_avoiding) against the plain path and check.

Per row, a 20-step straight line of the tool (pose, tool down) in a cell with one box:

* ``plain``: :func:`kin.path.follow_path` + :func:`kin.path.check_path_collisions` in a cell
  the plain path misses (a ball far away; what ``kin path --scene`` does on a free path);
* ``avoid free``: :func:`kin.path.follow_path_avoiding` in the same cell: the plain path and
  its check, nothing searched;
* ``avoid``: the same in the cell whose box the plain path hits: the search over every sample's
  free answers.

Medians of single calls, the three alternated call by call (the machine is shared: ratios
survive the load better than the absolute times).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402
from bench_ik_urdf import erd  # noqa: E402

from kin import load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402

SHELF = "[[box]]\nname = 'shelf'\nsize = [0.1, 1.0, 0.4]\nxyz = [-0.12, 0.0, 0.55]\n"
ROOF = "[[box]]\nname = 'roof'\nsize = [0.3, 1.0, 0.1]\nxyz = [0.1, 0.0, 0.73]\n"
FAR = "[[sphere]]\nname = 'far'\nradius = 0.05\nxyz = [-1.0, -1.0, 1.5]\n"
#: row -> (robot name or example-robot-data URDF, tip, SRDF or None, box, start, end [m]).
ROWS = {
    "ur5 (DH)": ("ur5", None, None, SHELF, (0.4, 0.1, 0.3), (0.4, -0.3, 0.3)),
    "panda (DH)": ("panda", None, None, ROOF, (0.5, 0.2, 0.3), (0.5, -0.2, 0.3)),
    "panda (URDF+SRDF)": (
        "panda_description/urdf/panda.urdf",
        "panda_link8",
        "panda_description/srdf/panda.srdf",
        ROOF,
        (0.5, 0.2, 0.3),
        (0.5, -0.2, 0.3),
    ),
}


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=positive_int, default=5, help="calls of each (median)")
    parser.add_argument("--steps", type=positive_int, default=20, help="steps of the line")
    return parser


def _row(name: str, folder: Path, repeat: int, steps: int) -> str:
    from kin.collision import CollisionChecker, load_collision_model
    from kin.ik import PoseTarget
    from kin.path import check_path_collisions, follow_path, follow_path_avoiding, polyline

    robot_name, tip, srdf, box, start, end = ROWS[name]
    if tip is None:
        robot = load_robot(robot_name)
    else:
        robot = load_robot(erd(robot_name), None, tip)
    srdf_file = None if srdf is None else erd(srdf)
    checkers = {}
    for key, text in (("hit", box), ("far", FAR)):
        scene = folder / f"{key}.toml"
        scene.write_text(text, encoding="utf-8")
        model = load_collision_model(robot, srdf=srdf_file, scene=scene)
        checkers[key] = CollisionChecker(model)
    down = pin.rpy.rpyToMatrix(np.pi, 0.0, 0.0)
    path = polyline([PoseTarget(np.array(p), down) for p in (start, end)], steps)
    calls = {
        "plain": lambda: check_path_collisions(checkers["far"], follow_path(robot, path).q),
        "avoid free": lambda: follow_path_avoiding(robot, path, checkers["far"]),
        "avoid": lambda: follow_path_avoiding(robot, path, checkers["hit"]),
    }
    times: dict[str, list[float]] = {key: [] for key in calls}
    outcome = calls["avoid"]()
    for round_ in range(repeat):
        keys = list(calls) if round_ % 2 == 0 else list(calls)[::-1]
        for key in keys:
            start_time = time.perf_counter()
            calls[key]()
            times[key].append(time.perf_counter() - start_time)
    median = {key: statistics.median(value) for key, value in times.items()}
    verdict = "free" if outcome.success else f"failed: {outcome.failure.describe()}"
    return (
        f"{name:<18} {median['plain'] * 1e3:>9.1f} {median['avoid free'] * 1e3:>11.1f} "
        f"{median['avoid'] * 1e3:>9.1f} {median['avoid free'] / median['plain']:>11.2f}x "
        f"{median['avoid'] / median['plain']:>7.2f}x  {verdict}"
    )


def main(argv: list[str] | None = None) -> int:
    """Print one line per row."""
    args = get_argument_parser().parse_args(argv)
    print(f"{args.steps}-step line, medians of {args.repeat} alternated calls [ms]")
    print(
        f"{'row':<18} {'plain':>9} {'avoid free':>11} {'avoid':>9} {'free/plain':>12} "
        f"{'avoid/plain':>8}  avoid's verdict"
    )
    with tempfile.TemporaryDirectory() as folder:
        for name in ROWS:
            print(_row(name, Path(folder), args.repeat, args.steps), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
