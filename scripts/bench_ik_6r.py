"""Benchmark the closed-form IK of the two 6R families: all 8 branches per call, and batched.

UR5 (``ur_wrist``, the shipped table) and PUMA 560 (``spherical_wrist``, the Robotics Toolbox's
standard DH numbers). Per call: ``solve`` of one target, all branches, median over repeated
timings of ``--number`` calls on the same targets (timeit style). Batched: ``solve_batch`` of
``--batch`` targets, per target. Peers when importable: ur-analytic-ik's Python call (UR5, all
branches) and the Robotics Toolbox's ``ikine_a`` (PUMA 560, one configuration per call; x8 for
all branches). Targets are the FK of seeded random q within +-pi.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math
import statistics
import timeit
from collections.abc import Callable

import numpy as np

from dh2urdf import DHRow, DHTable, get_robot, load_table
from kin.batch_fk import batch_forward_kinematics
from kin.cli import ArgumentParser, positive_int
from kin.ik.analytic.spherical_wrist import SphericalWrist6R
from kin.ik.analytic.ur_wrist import URWrist6R

#: PUMA 560, standard DH (Robotics Toolbox ``models.DH.Puma560``): a, alpha, d per joint.
PUMA560 = (
    (0.0, math.pi / 2, 0.6718),
    (0.4318, 0.0, 0.0),
    (0.0203, -math.pi / 2, 0.15005),
    (0.0, math.pi / 2, 0.4318),
    (0.0, -math.pi / 2, 0.0),
    (0.0, 0.0, 0.0),
)


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
    return parser


def puma560_table() -> DHTable:
    """The PUMA 560 table of the Robotics Toolbox (no base or tool)."""
    rows = tuple(
        DHRow(i + 1, f"joint{i + 1}", "revolute", a, alpha, d, 0.0, -math.pi, math.pi, 1.0, 1.0)
        for i, (a, alpha, d) in enumerate(PUMA560)
    )
    return DHTable("puma560", "PUMA 560", "Robotics Toolbox Puma560 (DH)", "standard", rows)


def _median_us(function: Callable[[], object], number: int, repeat: int) -> float:
    return statistics.median(timeit.repeat(function, number=number, repeat=repeat)) / number * 1e6


def _cycle(items: list) -> Callable[[], object]:
    """A function taking the next item of ``items`` at each call (returns the item)."""
    state = {"i": 0}

    def next_item() -> object:
        i = state["i"]
        state["i"] = (i + 1) % len(items)
        return items[i]

    return next_item


def _peers_ur5(targets: np.ndarray, number: int, repeat: int) -> float | None:
    try:
        import ur_analytic_ik
    except ImportError:
        return None
    poses = [np.ascontiguousarray(t) for t in targets]
    take = _cycle(poses)
    return _median_us(lambda: ur_analytic_ik.ur5.inverse_kinematics(take()), number, repeat)


def _peers_puma(targets: np.ndarray, number: int, repeat: int) -> float | None:
    try:
        import roboticstoolbox as rtb
    except ImportError:
        return None
    robot = rtb.models.DH.Puma560()
    take = _cycle(list(targets))
    return _median_us(lambda: robot.ikine_a(take(), config="lun"), max(1, number // 10), repeat)


def main(argv: list[str] | None = None) -> int:
    """Print the benchmark table; exit 0."""
    args = get_argument_parser().parse_args(argv)
    arms = (
        ("UR5", URWrist6R.recognise(load_table(get_robot("ur5").table_path)), _peers_ur5),
        ("PUMA 560", SphericalWrist6R.recognise(puma560_table()), _peers_puma),
    )
    print(
        f"{'arm':<9} {'solver':<16} {'solve [us/call]':>16} {'batch [us/target]':>18}  "
        f"{'peer [us/call]':>15}  peer"
    )
    for label, solver, peer in arms:
        table = load_table(get_robot("ur5").table_path) if label == "UR5" else puma560_table()
        rng = np.random.default_rng(0)
        q = rng.uniform(-math.pi, math.pi, (max(args.batch, 1000), 6))
        poses = batch_forward_kinematics(table, q)
        targets = [(T[:3, 3].copy(), T[:3, :3].copy()) for T in poses[:1000]]
        take = _cycle(targets)

        def one_call(solver=solver, take=take) -> object:
            position, rotation = take()  # type: ignore[misc]
            return solver.solve(position, rotation)

        per_call = _median_us(one_call, args.number, args.repeat)
        positions, rotations = poses[: args.batch, :3, 3], poses[: args.batch, :3, :3]
        batch = _median_us(
            lambda s=solver: s.solve_batch(positions, rotations), 1, max(3, args.repeat // 2)
        )
        peer_us = peer(poses[:1000], args.number, args.repeat)
        if peer_us is None:
            peer_text, peer_name = f"{'-':>15}", "not installed"
        elif label == "UR5":
            peer_text, peer_name = f"{peer_us:15.1f}", "ur-analytic-ik (all branches)"
        else:
            peer_text = f"{peer_us:15.1f}"
            peer_name = f"RTB ikine_a (one branch; x8 = {8 * peer_us:.0f} us)"
        print(
            f"{label:<9} {solver.name:<16} {per_call:16.1f} {batch / args.batch:18.2f}  "
            f"{peer_text}  {peer_name}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
