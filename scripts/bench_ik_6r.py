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
branch wrapped into the limits and verified, valid and rejected), ``batch`` (``solve_batch`` of
``min(--batch, 10000)`` targets, per target) and the peer ssik when installed (``pip install
ssik``: ``Manipulator.from_transforms`` of the same chain, ``solve(T, respect_limits=False,
enumerate_windings=False)``: every branch, its own verification; its first call on an arm
prepares it, tens of seconds, not timed), ``ratio`` = verified / ssik, ``same count``: targets
where ssik finds as many solutions as our branches. With ssik, ``verified`` and ``ssik`` are
timed in alternation (``--repeat`` pairs of timings on the same targets).
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import functools
import math
import statistics
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
    parser.add_argument(
        "--no-ssik", action="store_true", help="general 6R: leave the peer ssik out"
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
    if args.robot is None or args.robot in {name for _, name, _ in ARMS}:
        _families(args)
    if args.robot is None or args.robot in {name for _, name in GENERAL_ARMS}:
        _general(args)
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


def _ssik_peer(F: np.ndarray, use: bool) -> Callable[[np.ndarray], list] | None:
    """The peer ssik's every-branch solve of the chain ``F`` (solutions, ``.q``), or None."""
    if not use:
        return None
    try:
        import ssik
    except ImportError:
        return None
    arm = ssik.Manipulator.from_transforms(F)

    def solve(pose: np.ndarray) -> list:
        return arm.solve(pose, respect_limits=False, enumerate_windings=False)

    return solve


def _general(args) -> None:
    """The general-6R table (see the module)."""
    from kin import robot_from_table
    from kin.ik import PoseTarget, get_solver
    from kin.ik.analytic.six_r.general_6r import General6R, chain_transforms

    number = max(1, args.number // 10)
    size = min(args.batch, 10_000)
    print(
        f"\n{'arm':<9} {'solver':<11} {'branches':>8} {'solve':>9} {'verified':>9} "
        f"{'batch':>9}  {'ssik':>9} {'ratio':>6}  {'same count':>10}"
    )
    print(f"{'':<9} {'':<11} {'[mean]':>8} {'[us]':>9} {'[us]':>9} {'[us/tgt]':>9}  {'[us]':>9}")
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
        peer = _ssik_peer(chain_transforms(table)[0], not args.no_ssik)
        if peer is None:
            print(f"{label:<9} {solver.name.split(':')[-1]:<11} {counts.mean():8.2f} "
                  f"{solve_us:9.1f} {verified_us:9.1f} {batch / size:9.2f}  {'-':>9} {'-':>6}  "
                  f"{'-':>10}  ssik not installed")  # fmt: skip
            continue
        peer(poses[0])  # ssik prepares the arm on its first call
        # Ours and ssik's timed in alternation on the same targets (the machine's load drifts):
        # the medians of the interleaved timings.
        peer_poses = list(poses[:1000])
        ours_times, peer_times = [], []
        for r in range(args.repeat):
            start = (r * number) % 1000
            chunk = [documented_targets[(start + k) % 1000] for k in range(number)]
            poses_chunk = [peer_poses[(start + k) % 1000] for k in range(number)]
            ours_times.append(_per_call_us(functools.partial(_each, solver.solve, chunk), number))
            peer_times.append(_per_call_us(functools.partial(_each, peer, poses_chunk), number))
        verified_us = statistics.median(ours_times)
        peer_us = statistics.median(peer_times)
        compare = min(args.compare, 1000)
        same = sum(len(peer(poses[k])) == counts[k] for k in range(compare))
        print(
            f"{label:<9} {solver.name.split(':')[-1]:<11} {counts.mean():8.2f} {solve_us:9.1f} "
            f"{verified_us:9.1f} {batch / size:9.2f}  {peer_us:9.1f} "
            f"{verified_us / peer_us:6.2f}  {f'{same}/{compare}':>10}"
        )


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
