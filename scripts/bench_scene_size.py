"""Benchmark scenes of many shapes: the refusal over the cap and a scene at the cap; print a table.

UR5 (the shipped DH table) in scenes of N boxes of 5 cm at random places above the arm:

* ``refuse``: ``load_collision_model`` of a scene over :data:`kin.collision.bounds.MAX_SHAPES`
  (20,000 and 100,000 boxes), the time to the error (the TOML read included);
* ``load``: the same call on a scene of exactly ``MAX_SHAPES`` boxes;
* ``check``: ``CollisionChecker.in_collision`` on that scene at random configurations within the
  limits, median of single calls (the broad phase decides which boxes are tested).

Issue 42 found 10,000 boxes with no answer after 200 s (Pinocchio's geometry model copies a square
matrix of its objects at each one added); the tests assert the work (no shape built before the
refusal), this script the time. Usage: ``python scripts/bench_scene_size.py [--samples N]``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from kin import load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402
from kin.collision import CollisionChecker, CollisionModelError, load_collision_model  # noqa: E402
from kin.collision.bounds import MAX_SHAPES  # noqa: E402


def write_boxes(path: Path, count: int) -> None:
    """``count`` boxes of 5 cm [m] centred uniformly in a 40 m cube whose centre is 30 m up."""
    centres = np.random.default_rng(0).uniform(-20.0, 20.0, (count, 3)) + [0.0, 0.0, 30.0]
    path.write_text(
        "".join(
            f"[[box]]\nsize = [0.05, 0.05, 0.05]\nxyz = [{x}, {y}, {z}]\n" for x, y, z in centres
        ),
        encoding="utf-8",
    )


def main() -> None:
    """Print the table."""
    parser = ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=positive_int, default=200, help="configurations")
    args = parser.parse_args()
    robot = load_robot("ur5")
    warnings.simplefilter("ignore")  # the boxes are meant to be tens of meters away
    print(f"{'case':<28} {'boxes':>8} {'time':>12}")
    with tempfile.TemporaryDirectory() as folder:
        scene = Path(folder) / "boxes.toml"
        for count in (20_000, 100_000):
            write_boxes(scene, count)
            start = time.perf_counter()
            try:
                load_collision_model(robot, scene=scene)
            except CollisionModelError:
                pass
            else:
                raise SystemExit(f"{count} boxes were not refused")
            print(f"{'refuse':<28} {count:>8} {time.perf_counter() - start:>10.2f} s")
        write_boxes(scene, MAX_SHAPES)
        start = time.perf_counter()
        checker = CollisionChecker(load_collision_model(robot, scene=scene))
        print(f"{'load':<28} {MAX_SHAPES:>8} {time.perf_counter() - start:>10.2f} s")
    qs = np.random.default_rng(1).uniform(robot.lower, robot.upper, (args.samples, robot.nq))
    times = []
    for q in qs:
        start = time.perf_counter()
        checker.in_collision(q)
        times.append(time.perf_counter() - start)
    median = statistics.median(times) * 1e6
    print(f"{'check (median of single)':<28} {MAX_SHAPES:>8} {median:>9.1f} us")


if __name__ == "__main__":
    main()
