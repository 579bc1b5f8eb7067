"""Benchmark the closed-form IK of the 6R families: all branches per call, and batched.

UR5 and UR10 (``ur_wrist``) and PUMA 560 (``spherical_wrist``, the Robotics Toolbox's DH model),
their shipped tables. Columns, medians over repeated timings of ``--number`` calls on
the same targets (timeit style): ``solve``, the structure's 8 branches of one target (not
verified); ``verified``, the same through ``ClosedFormSolver.solve`` (branches wrapped into the
limits, each verified by FK, ordered by distance to the seed: what ``kin.ik.solve_ik`` returns),
in the compiled twin when it is built (the table's DH product in C as the judge); ``py verified``,
the Python path of the same solver (Pinocchio as the judge); ``batch``, ``solve_batch`` of
``--batch`` targets, per target. The ``compiled`` line says whether the twins are built (without
them ``solve`` and ``batch`` run in Python and NumPy). Peers when importable (``[bench]`` extra):
ur-analytic-ik's Python call (all branches) and the Robotics Toolbox's ``ikine_a`` (its 8
configurations, 8 calls); ``same solutions``: targets where the peer's solutions are exactly
ours (same count, each within 1e-9 rad modulo 2 pi). Targets are the FK of seeded random q
within +-pi.

General 6R (``general_6r``, Raghavan-Roth elimination, up to 16 branches): the non-Pieper arms of
``tests/data/six_r`` (xArm6, Jaco 2 6-DOF, CRX-10iA, the makers' parameters). Columns, medians
of ``--number // 10`` calls: ``solve`` (the structure's branches, polished, not verified),
``verified`` (the documented call ``kin.ik.get_solver(robot).solve(PoseTarget(p, R))``: every
branch wrapped into the limits and verified, valid and rejected) and ``batch`` (``solve_batch`` of
``min(--batch, 10000)`` targets, per target).

ssik's general 6R arms (when ssik is installed, ``[bench]`` extra): each of the 18 arms of
:data:`ssik_chains.GENERAL_6R`, ssik's own chain written as a URDF and loaded as a user's
``--robot FILE.urdf``; ``--targets`` tool poses of random joint vectors inside the limits. Timed
in turns target by target (the order rotated each target), one call each, medians of single
calls: ours (``get_solver(robot).solve(PoseTarget(p, R))``), ssik's prebuilt module
(``ssik.prebuilt.<maker>.<arm>_ik.solve(T)``: the elimination baked per arm, native backend:
its fastest documented path), TRAC-IK (pytracik: 5 ms, Speed) and EAIK where they accept the
arm. ``ssik x`` and ``trac x``: our median over theirs. ``batch``: ``kin.ik.solve_batch`` of
the same targets (every branch verified, the nearest to the seed returned; the arm's closed
form kept from a first call made before the timing), per target: the median of
:data:`BATCH_TIMINGS` whole batches timed between the rounds of single calls (both under the
same load); ``ours/batch``: the per-call time over it. Branches:
the medians of our valid solutions and of ssik's distinct ones modulo 2 pi (ssik returns each
``2 pi`` copy inside the limits); ``same``: the targets where the two counts are equal;
``trac ok``: TRAC-IK's solved targets.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import functools
import math
import statistics
import sys
import tempfile
import time
import timeit
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from dh2urdf import DHTable, get_robot, load_table
from kin.batch_fk import batch_forward_kinematics
from kin.cli import ArgumentParser, positive_int
from kin.ik.analytic.six_r.spherical_wrist import SphericalWrist6R
from kin.ik.analytic.six_r.ur_wrist import URWrist6R

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ssik_chains import GENERAL_6R, distinct_mod_2pi, write_ssik_arm  # noqa: E402

#: Timings of the whole batch of an ssik arm's targets, spread among its single calls.
BATCH_TIMINGS = 7
#: The arms benchmarked, in order: (label, shipped robot, structure).
ARMS = (("UR5", "ur5", URWrist6R), ("UR10", "ur10", URWrist6R),
        ("PUMA 560", "puma560", SphericalWrist6R))  # fmt: skip
#: The general-6R arms benchmarked: (label, table file in tests/data/six_r).
GENERAL_ARMS = (("xArm6", "xarm6"), ("Jaco 2", "jaco2_6dof"), ("CRX-10iA", "crx10ia"))
SIX_R = Path(__file__).resolve().parents[1] / "tests" / "data" / "six_r"
ROBOTS = tuple(name for _, name, _ in ARMS) + tuple(name for _, name in GENERAL_ARMS)


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik_6r.py", description=__doc__)
    parser.add_argument(
        "--number", type=positive_int, default=2000, help="calls per timing (default 2000)"
    )
    parser.add_argument(
        "--repeat", type=positive_int, default=7, help="timings per figure, median (default 7)"
    )
    parser.add_argument(
        "--batch", type=positive_int, default=100_000, help="targets of the batch (default 100000)"
    )
    parser.add_argument("--robot", choices=ROBOTS, help="one arm only (default: all)")
    parser.add_argument("--no-ssik", action="store_true", help="leave the table of ssik's arms out")
    parser.add_argument(
        "--ssik-arms",
        nargs="+",
        choices=GENERAL_6R,
        metavar="MAKER.ARM_ik",
        help="time these of ssik's general 6R arms only (default: all 18, after the other tables)",
    )
    parser.add_argument(
        "--targets", type=positive_int, default=200, help="targets per ssik arm (default 200)"
    )
    parser.add_argument(
        "--compare",
        type=positive_int,
        default=10_000,
        help="targets compared with the peer's solutions (default 10000; PUMA at most 1000)",
    )
    return parser


def _median_us(function: Callable[[], object], number: int, repeat: int) -> float:
    return statistics.median(timeit.repeat(function, number=number, repeat=repeat)) / number * 1e6


def _each(function: Callable[[Any], object], items: list) -> None:
    """``function`` of every item."""
    for item in items:
        function(item)


def _per_call_us(function: Callable[[], object], calls: int) -> float:
    """One timing of ``function`` (which makes ``calls`` calls), per call [us]."""
    return timeit.timeit(function, number=1) / calls * 1e6


def _cycle(items: list) -> Callable[[], object]:
    """A function taking the next item of ``items`` at each call (returns the item)."""
    state = {"i": 0}

    def next_item() -> object:
        i = state["i"]
        state["i"] = (i + 1) % len(items)
        return items[i]

    return next_item


def _ur_peer(model: str) -> Callable[[np.ndarray], np.ndarray] | None:
    """ur-analytic-ik's IK of one UR model (all branches, (k, 6)), or None when not installed."""
    try:
        import ur_analytic_ik
    except ImportError:
        return None
    arm = getattr(ur_analytic_ik, model)
    return lambda pose: np.asarray(arm.inverse_kinematics(np.ascontiguousarray(pose)))


def _puma_peer() -> Callable[[np.ndarray], np.ndarray] | None:
    """The Robotics Toolbox's ``ikine_a`` of its Puma560, its 8 configurations ((k, 6)), or None."""
    try:
        import roboticstoolbox as rtb
    except ImportError:
        return None
    robot = rtb.models.DH.Puma560()

    def all_configurations(pose: np.ndarray) -> np.ndarray:
        found = [robot.ikine_a(pose, config=c) for c in CONFIGURATIONS]
        return np.array([r.q for r in found if r.success]).reshape(-1, 6)

    return all_configurations


#: ``ikine_a`` configurations: shoulder left/right, elbow up/down, wrist no flip/flip.
CONFIGURATIONS = ("lun", "luf", "ldn", "ldf", "run", "ruf", "rdn", "rdf")


def _same_solutions(ours: np.ndarray, theirs: np.ndarray, tol: float = 1e-9) -> bool:
    """Whether the peer's solutions are exactly ours, each to ``tol`` [rad] modulo 2 pi."""
    ours = ours[~np.isnan(ours[:, 0])]
    if len(theirs) != len(ours):
        return False
    for branch in theirs:
        gap = np.abs(np.angle(np.exp(1j * (ours - branch)))).max(axis=1)
        if gap.min() >= tol:
            return False
    return True


def main(argv: list[str] | None = None) -> int:
    """Print the benchmark table; exit 0."""
    args = get_argument_parser().parse_args(argv)
    if args.ssik_arms:  # that table only
        _ssik_arms(args)
        return 0
    if args.robot is None or args.robot in {name for _, name, _ in ARMS}:
        _families(args)
    if args.robot is None or args.robot in {name for _, name in GENERAL_ARMS}:
        _general(args)
    if args.robot is None and not args.no_ssik:
        _ssik_arms(args)
    return 0


def _families(args) -> None:
    """The UR and spherical-wrist table (see the module)."""
    arms = []
    for label, name, structure in ARMS:
        if args.robot not in (None, name):
            continue
        table = load_table(get_robot(name).table_path)  # puma560: the toolbox's numbers
        peer = _puma_peer() if structure is SphericalWrist6R else _ur_peer(name)
        arms.append((label, table, structure.recognise(table), peer))
    built = all(structure.compiled_twin is not None for _, _, structure, _ in arms)
    print(f"compiled twins: {'built' if built else 'not built (Python and NumPy)'}")
    print(
        f"{'arm':<9} {'solver':<16} {'solve':>9} {'verified':>9} {'py verified':>11} "
        f"{'batch':>9}  {'peer':>9}  {'same solutions':>16}  peer"
    )
    print(f"{'':<9} {'':<16} {'[us]':>9} {'[us]':>9} {'[us]':>11} {'[us/tgt]':>9}  {'[us]':>9}")
    for label, table, solver, peer in arms:
        rng = np.random.default_rng(0)
        q = rng.uniform(-math.pi, math.pi, (max(args.batch, args.compare, 1000), 6))
        poses = batch_forward_kinematics(table, q)
        targets = [(T[:3, 3].copy(), T[:3, :3].copy()) for T in poses[:1000]]
        take = _cycle(targets)

        def one_call(solver=solver, take=take) -> object:
            position, rotation = take()  # type: ignore[misc]
            return solver.solve(position, rotation)

        per_call = _median_us(one_call, args.number, args.repeat)
        verified = _verified_us(table, targets, args.number, args.repeat, compiled=True)
        python = _verified_us(table, targets, max(1, args.number // 4), args.repeat, compiled=False)
        positions, rotations = poses[: args.batch, :3, 3], poses[: args.batch, :3, :3]
        batch = _median_us(
            lambda s=solver: s.solve_batch(positions, rotations), 1, max(3, args.repeat // 2)
        )
        if peer is None:
            print(f"{label:<9} {solver.name:<16} {per_call:9.1f} {verified:9.1f} {python:11.1f} "
                  f"{batch / args.batch:9.2f}  {'-':>9}  {'-':>16}  not installed")  # fmt: skip
            continue
        slow = label == "PUMA 560"  # ikine_a: one configuration per call, milliseconds
        count = min(args.compare, 1000) if slow else args.compare
        peer_take = _cycle(list(poses[:1000]))
        peer_us = _median_us(lambda: peer(peer_take()), max(1, args.number // (80 if slow else 1)),
                             args.repeat)  # fmt: skip
        batch_ours = solver.solve_batch(poses[:count, :3, 3], poses[:count, :3, :3])
        same = sum(_same_solutions(batch_ours[k], peer(poses[k])) for k in range(count))
        name = "RTB ikine_a, 8 configurations" if slow else "ur-analytic-ik, all branches"
        print(
            f"{label:<9} {solver.name:<16} {per_call:9.1f} {verified:9.1f} {python:11.1f} "
            f"{batch / args.batch:9.2f}  {peer_us:9.1f}  {f'{same}/{count}':>16}  {name}"
        )


def _general(args) -> None:
    """The general-6R table (see the module)."""
    from kin import robot_from_table
    from kin.ik import PoseTarget, get_solver
    from kin.ik.analytic.six_r.general_6r import General6R

    number = max(1, args.number // 10)
    size = min(args.batch, 10_000)
    print(f"\n{'arm':<9} {'solver':<11} {'branches':>8} {'solve':>9} {'verified':>9} {'batch':>9}")
    print(f"{'':<9} {'':<11} {'[mean]':>8} {'[us]':>9} {'[us]':>9} {'[us/tgt]':>9}")
    for label, name in GENERAL_ARMS:
        if args.robot not in (None, name):
            continue
        table = load_table(SIX_R / f"{name}.toml")
        structure = General6R.recognise(table)
        solver = get_solver(robot_from_table(table))
        rng = np.random.default_rng(0)
        q = rng.uniform(-math.pi, math.pi, (max(size, 1000), 6))
        poses = batch_forward_kinematics(table, q)
        targets = [(T[:3, 3].copy(), T[:3, :3].copy()) for T in poses[:1000]]
        take = _cycle(targets)
        solve_us = _median_us(lambda: structure.solve(*take()), number, args.repeat)  # type: ignore[misc]
        documented_targets = [PoseTarget(p, r) for p, r in targets]
        documented = _cycle(documented_targets)
        verified_us = _median_us(lambda: solver.solve(documented()), number, args.repeat)
        positions, rotations = poses[:size, :3, 3], poses[:size, :3, :3]
        batch = _median_us(
            lambda: structure.solve_batch(positions, rotations), 1, max(3, args.repeat // 2)
        )
        ours = structure.solve_batch(poses[:1000, :3, 3], poses[:1000, :3, :3])
        counts = (~np.isnan(ours[..., 0])).sum(axis=1)
        print(f"{label:<9} {solver.name.split(':')[-1]:<11} {counts.mean():8.2f} "
              f"{solve_us:9.1f} {verified_us:9.1f} {batch / size:9.2f}")  # fmt: skip


def _peers(path: Path, module) -> dict[str, tuple[Callable, Callable]]:  # noqa: ANN001
    """TRAC-IK and EAIK on the URDF where they accept it: name -> (prepare, solve)."""
    from bench_ik_urdf import eaik_solver, tracik

    found = {}
    for key, make in (("trac", tracik), ("eaik", eaik_solver)):
        made = make(path, module.BASE_LINK, module.EE_LINK)
        if isinstance(made, str):
            print(f"  {path.stem}: {key} {made}")
        else:
            found[key] = made[1:]
    return found


def _ssik_arms(args) -> None:
    """Ssik's general 6R arms against its prebuilt modules, TRAC-IK and EAIK (see the module)."""
    try:
        import pinocchio as pin
        import ssik  # noqa: F401
    except ImportError as err:
        print(f"\nssik's arms: not measured ({err}; pip install ssik)")
        return
    from kin import load_robot
    from kin.ik import PoseTarget, get_solver, solve_batch

    print(
        f"\n{'ssik arm':<19} {'ours':>7} {'ssik':>7} {'ssik x':>6} {'trac':>7} {'trac x':>6} "
        f"{'eaik':>7} {'batch':>7} {'ours/batch':>10}  {'branches':>8} {'same':>8} {'trac ok':>8}"
    )
    print(f"{'':<19} {'[us]':>7} {'[us]':>7} {'':>6} {'[us]':>7} {'':>6} {'[us]':>7} {'[us]':>7}")
    folder = Path(tempfile.mkdtemp())
    for name in args.ssik_arms or GENERAL_6R:
        path, module = write_ssik_arm(name, folder)
        robot = load_robot(path)
        solver = get_solver(robot)
        rng = np.random.default_rng(0)
        q = rng.uniform(robot.lower, robot.upper, (args.targets, 6))
        poses = batch_forward_kinematics(robot.table, q)
        peers = _peers(path, module)
        targets = {
            "ours": [PoseTarget(T[:3, 3], T[:3, :3]) for T in poses],
            "ssik": list(poses),
            **{k: [prepare(pin.SE3(T[:3, :3], T[:3, 3])) for T in poses] for k, (prepare, _) in peers.items()},
        }  # fmt: skip
        calls = {"ours": solver.solve, "ssik": module.solve,
                 **{k: functools.partial(solve, seed=np.zeros(6)) for k, (_, solve) in peers.items()}}  # fmt: skip
        times: dict[str, list[float]] = {key: [] for key in calls}
        answers: dict[str, list] = {key: [] for key in calls}
        keys = list(calls)
        points, frames = poses[:, :3, 3], poses[:, :3, :3]
        solve_batch(robot, points, frames)  # the first call recognises the arm (kept after)
        batches = []  # whole batches, timed between the rounds of single calls (the same load)
        every = max(1, args.targets // BATCH_TIMINGS)
        for i in range(args.targets):
            if i % every == 0:
                start = time.perf_counter()
                solve_batch(robot, points, frames)
                batches.append((time.perf_counter() - start) / args.targets)
            for key in keys[i % len(keys) :] + keys[: i % len(keys)]:  # the order rotated
                target, call = targets[key][i], calls[key]
                start = time.perf_counter()
                answer = call(target)
                times[key].append(time.perf_counter() - start)
                answers[key].append(answer)
        us = {key: statistics.median(values) * 1e6 for key, values in times.items()}
        batch_us = statistics.median(batches) * 1e6
        ours_count = [len(a.solutions) for a in answers["ours"]]
        ssik_count = [distinct_mod_2pi([s.q for s in a]) for a in answers["ssik"]]
        same = sum(a == b for a, b in zip(ours_count, ssik_count))
        trac = f"{sum(bool(a) for a in answers['trac'])}/{args.targets}" if "trac" in us else "-"
        print(
            f"{name:<19} {us['ours']:7.0f} {us['ssik']:7.0f} {us['ours'] / us['ssik']:6.2f} "
            + (f"{us['trac']:7.0f} {us['ours'] / us['trac']:6.2f} " if "trac" in us else f"{'-':>7} {'-':>6} ")
            + (f"{us['eaik']:7.0f} " if "eaik" in us else f"{'-':>7} ")
            + f"{batch_us:7.0f} {us['ours'] / batch_us:10.1f}  "
            f"{statistics.median(ours_count):3.0f}/{statistics.median(ssik_count):<4.0f} "
            f"{f'{same}/{args.targets}':>8} {trac:>8}"
        )  # fmt: skip


def _verified_us(
    table: DHTable, targets: list, number: int, repeat: int, *, compiled: bool
) -> float:
    """Per call of the closed-form solver [us], every branch verified.

    Branches wrapped into the limits, each verified by FK, ordered by distance to the seed (what
    :func:`kin.ik.solve_ik` returns); ``compiled``: in the twin (C judge) when it is built, else
    the Python path (Pinocchio judge).
    """
    from kin import robot_from_table
    from kin.ik import ClosedFormSolver, PoseTarget

    solver = ClosedFormSolver(robot_from_table(table), compiled=compiled)
    poses = [PoseTarget(p, r) for p, r in targets]
    take = _cycle(poses)
    return _median_us(lambda: solver.solve(take()), number, repeat)  # type: ignore[arg-type]


if __name__ == "__main__":
    raise SystemExit(main())
