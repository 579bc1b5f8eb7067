"""Benchmark peak memory and time of chains up to the joint cap (64): tables and URDFs.

For each size (8, 16, 32, 64 joints by default) and each kind (a DH table, a URDF chain of
revolute joints with alternately tilted axes), a fresh process loads the robot
(``kin.load_robot``), computes FK once (``Configuration``) and solves one IK (a position target
from FK, ``get_solver(robot).solve``). The table prints the child's peak resident memory
(``ru_maxrss`` from ``os.wait4``) and the three times; the ``imports`` row is a child that only
imports ``kin`` and Pinocchio, the floor under every other row. Pinocchio's ``Data`` holds
tensors of ``nv^3`` entries (:mod:`dh2urdf.joint_cap`), so memory grows with the cube of the
joint count beyond the cap; at the cap it is a few MB over the floor.

    python scripts/bench_joint_cap.py                  # 8, 16, 32, 64 joints
    python scripts/bench_joint_cap.py --joints 64 --timeout 2
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from dh2urdf.joint_cap import MAX_JOINTS
from kin.cli import ArgumentParser, positive_float, positive_int

_PROBE = r"""
import json, sys, time
t0 = time.perf_counter()
import numpy as np
import pinocchio
from kin import Configuration, load_robot
out = {"import_s": time.perf_counter() - t0}
if sys.argv[1] != "-":
    from kin.ik import PositionTarget, get_solver
    t1 = time.perf_counter()
    robot = load_robot(sys.argv[1])
    t2 = time.perf_counter()
    pose = Configuration(robot, np.full(robot.nq, 0.3)).transform_frame_to_world("tool")
    t3 = time.perf_counter()
    result = get_solver(robot).solve(PositionTarget(pose.translation), timeout=float(sys.argv[2]))
    t4 = time.perf_counter()
    out.update(load_s=t2 - t1, fk_s=t3 - t2, ik_s=t4 - t3, status=result.status)
print(json.dumps(out))
"""


def chain_urdf(n: int) -> str:
    """A URDF chain of ``n`` revolute joints, 0.1 m apart, axes alternately tilted by 0.3 rad."""
    parts = ['<robot name="chain">', '<link name="l0"/>']
    for i in range(1, n + 1):
        parts.append(
            f'<link name="l{i}"/><joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
            f'<child link="l{i}"/><origin xyz="0 0 0.1" rpy="0 {0.3 * (i % 2)} 0"/>'
            '<axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
        )
    return "\n".join([*parts, "</robot>"])


def chain_table(n: int) -> str:
    """A DH table of ``n`` revolute rows (a 0.1 m, d 0.05 m, alpha +-0.5 rad), m and rad."""
    rows = ['convention = "standard"', 'length_unit = "m"', 'angle_unit = "rad"']
    for i in range(n):
        rows.append(
            f'[[joints]]\ntype = "revolute"\na = 0.1\nalpha = {0.5 if i % 2 else -0.5}\n'
            "d = 0.05\ntheta = 0.0\nlimits = [-3.0, 3.0]"
        )
    return "\n".join(rows) + "\n"


def measure(path: str, timeout: float) -> tuple[dict, int]:
    """The probe's JSON for ``path`` ('-' for imports only) and its peak memory [KiB]."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONWARNINGS="ignore")
    process = subprocess.Popen(
        [sys.executable, "-c", _PROBE, path, str(timeout)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
    )
    assert process.stdout is not None
    lines = process.stdout.read().strip().splitlines() or ["no output"]
    _, status, usage = os.wait4(process.pid, 0)  # this child's own rusage
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        return {"error": "refused: " + lines[-1].split(": ", 1)[-1]}, usage.ru_maxrss
    return json.loads(lines[-1]), usage.ru_maxrss


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_joint_cap.py", description=__doc__)
    parser.add_argument(
        "--joints",
        type=positive_int,
        nargs="+",
        default=[8, 16, 32, MAX_JOINTS],
        help=f"chain sizes (default 8 16 32 {MAX_JOINTS}; more than {MAX_JOINTS} is refused)",
    )
    parser.add_argument(
        "--timeout", type=positive_float, default=1.0, help="time budget of the IK [s] (default 1)"
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print one row per kind and size: peak memory [MiB], load, FK and IK times [ms]."""
    args = get_argument_parser().parse_args(argv)
    print(f"{'kind':<6} {'joints':>6} {'peak MiB':>9} {'load ms':>9} {'FK ms':>7} {'IK ms':>8}  IK")
    floor, peak = measure("-", args.timeout)
    print(f"{'import':<6} {'-':>6} {peak / 1024:>9.1f} {floor['import_s'] * 1e3:>9.0f} (import)")
    with tempfile.TemporaryDirectory() as folder:
        for n in args.joints:
            for kind, text, suffix in (
                ("table", chain_table(n), ".toml"),
                ("URDF", chain_urdf(n), ".urdf"),
            ):
                path = Path(folder) / f"chain{n}{suffix}"
                path.write_text(text, encoding="utf-8")
                row, peak = measure(str(path), args.timeout)
                if "error" in row:
                    print(f"{kind:<6} {n:>6} {peak / 1024:>9.1f}  {row['error'][:90]}")
                    continue
                print(
                    f"{kind:<6} {n:>6} {peak / 1024:>9.1f} {row['load_s'] * 1e3:>9.0f} "
                    f"{row['fk_s'] * 1e3:>7.1f} {row['ik_s'] * 1e3:>8.0f}  {row['status']}"
                )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
