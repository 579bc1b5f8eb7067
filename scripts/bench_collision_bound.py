"""Benchmark the distance bound inside the numeric solve (kin.ik.collision.collision_bound).

Panda (the maker's URDF and SRDF, example-robot-data), targets near a free seed: a 5 cm box is
put where the plain answer's forearm (panda_link4 or panda_link5) is, so the plain answer
collides and the seed stays free. Each case is solved by :class:`kin.ik.collision.collision_aware.
CollisionAwareSolver` with the distance-bounded search (``bound``) and without it (``no bound``:
the closed-form sweeps and the random restarts alone), the two alternated case by case, for:

* ``pose, closed-form grid``: a full pose, the default solver (the free-joint grid first);
* ``pose, numeric only``: a full pose, ``NumericIK(closed_form=False)`` (no grid);
* ``axis``: an :class:`~kin.ik.AxisTarget` (the roll sweep first).

Prints the collision-free answers found (every one checked free by the checker) and the medians
of single calls; the machine is shared, so the ratio is the figure to read.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import contextlib  # noqa: E402
import statistics  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from unittest import mock  # noqa: E402

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402
from bench_ik_urdf import erd  # noqa: E402

from kin import Configuration, load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402
from kin.collision import CollisionChecker, load_collision_model  # noqa: E402
from kin.ik import AxisTarget, PoseTarget, get_solver  # noqa: E402
from kin.ik.collision.collision_aware import CollisionAwareSolver  # noqa: E402
from kin.ik.numeric.solver import NumericIK  # noqa: E402
from kin.ik.result import IKResult  # noqa: E402

URDF, TIP, SRDF = (
    "panda_description/urdf/panda.urdf",
    "panda_link8",
    "panda_description/srdf/panda.srdf",
)
ROUTES = ("pose, closed-form grid", "pose, numeric only", "axis")


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(description=__doc__)
    parser.add_argument("--targets", type=positive_int, default=40, help="random targets")
    return parser


def _link_center(robot, model, link: str, q: np.ndarray) -> np.ndarray:
    """The world position [m] of ``link``'s first shape at ``q`` (the checker's own placement)."""
    data, geometry_data = robot.model.createData(), pin.GeometryData(model.geometry_model)
    pin.forwardKinematics(robot.model, data, q)
    pin.updateGeometryPlacements(robot.model, data, model.geometry_model, geometry_data)
    return np.array(geometry_data.oMg[model.owners.index(link)].translation)


def _cases(robot, count: int, folder: Path):
    """(pose target, seed, checker): the plain answer's forearm in a box, the seed free."""
    plain, config = get_solver(robot), Configuration(robot)
    bare = load_collision_model(robot, srdf=erd(SRDF))
    rng = np.random.default_rng(4)
    for k in range(count):
        seed = rng.uniform(robot.lower, robot.upper)
        q = np.clip(seed + rng.normal(0.0, 0.4, robot.nq), robot.lower, robot.upper)
        T = config.fk(q)
        target = PoseTarget(T.translation, T.rotation)
        result = plain.solve(target, seed)
        if not result.solutions:
            continue
        for link in ("panda_link5", "panda_link4"):
            center = _link_center(robot, bare, link, result.solutions[0].q)
            xyz = ", ".join(repr(float(v)) for v in center)
            scene = folder / f"box{k}_{link}.toml"
            scene.write_text(f'[[box]]\nname = "box"\nsize = [0.05, 0.05, 0.05]\nxyz = [{xyz}]\n')
            checker = CollisionChecker(load_collision_model(robot, srdf=erd(SRDF), scene=scene))
            if not checker.in_collision(seed) and checker.in_collision(result.solutions[0].q):
                yield target, seed, checker


def _solve(solver, target, seed, checker, bound: bool) -> tuple[bool, float]:
    """(a free answer found, seconds) of one collision-aware call, with or without the bound."""
    off = IKResult(False, "numeric", "not_found", "bound off")
    switch = (
        contextlib.nullcontext()
        if bound
        else mock.patch(
            "kin.ik.collision.collision_bound.solve_clear", lambda *args, **options: off
        )
    )
    with switch:
        start = time.perf_counter()
        result = CollisionAwareSolver(solver, checker).solve(target, seed, timeout=5.0)
        elapsed = time.perf_counter() - start
    assert not any(checker.in_collision(s.q) for s in result.solutions)
    return result.success, elapsed


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print one line per route."""
    args = get_argument_parser().parse_args(argv)
    robot = load_robot(erd(URDF), None, TIP)
    solvers = {
        ROUTES[0]: get_solver(robot),
        ROUTES[1]: NumericIK(robot, closed_form=False),
        ROUTES[2]: get_solver(robot),
    }
    with tempfile.TemporaryDirectory() as folder:
        cases = list(_cases(robot, args.targets, Path(folder)))
        print(f"Panda (URDF+SRDF), {len(cases)} cases: the plain answer in a 5 cm box, seed free")
        print(
            f"{'route':<24} {'free: no bound':>15} {'bound':>6} {'median: no bound':>17} {'bound':>8}"
        )
        for route in ROUTES:
            found = {False: 0, True: 0}
            times: dict[bool, list[float]] = {False: [], True: []}
            for target, seed, checker in cases:
                if route == "axis":
                    target = AxisTarget(target.position, target.rotation[:, 2])
                for bound in (False, True):
                    ok, elapsed = _solve(solvers[route], target, seed, checker, bound)
                    found[bound] += ok
                    times[bound].append(elapsed)
            off, on = statistics.median(times[False]), statistics.median(times[True])
            print(
                f"{route:<24} {found[False]:>15} {found[True]:>6} {off * 1e3:>14.1f} ms "
                f"{on * 1e3:>5.1f} ms (x{on / off:.2f})"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
