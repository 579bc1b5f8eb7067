"""Benchmark IK of many poses: the documented call, the batch, the stream, each against Pinocchio's FK.

For each robot (default humanoid7 and Panda), N reachable targets (the tool poses of seeded random
joint vectors inside the limits) and seeds (``zero``: q = 0; ``random``: other seeded random joint
vectors inside the limits), it prints:

- ``per call``: ``kin.ik.get_solver(robot).solve(PoseTarget(p, R), seed)``, the documented call,
  target built inside the timing (from the arrays ``p``, ``R`` the caller holds); ``core``: ``NumericIK.solve(NumericTarget(p, R), seed)``, the
  internal call with a prepared target (what the documented one should cost within 10 %);
- ``batch``: ``kin.ik.solve_batch(robot, positions, rotations, seeds)`` over all N (per pose);
- ``stdin``: ``kin ik --robot R --stdin`` on 100,000 lines ``{"target": ..., "rpy": ...}`` (the
  poses repeated; a subprocess, its start-up, measured on one line, taken off), with ``--stream``;
- ``TRAC-IK``: pytracik's per call (Speed, 20 ms), where installed.

Each time is also given in Pinocchio FK calls: the median time of one
``forwardKinematics`` + ``updateFramePlacement`` of the tool on the same robot, at the targets'
own joint vectors (configurations across the workspace; not at the seeds, which may be q = 0,
where sin and cos are cheapest). For the per-call rows it is timed interleaved with the IK calls
in the same loop (so both see the same CPU state). For the batch, in a loop of its own right
before and right after each pass: each pass is divided by the FK call of its own moment (the
machine's speed drifts from minute to minute), and the row gives the median of those ratios (a
loop of FK calls alone runs with warm caches, as the batch does: faster than FK calls between IK
calls, so this ratio is the stricter one; the row also gives the batch's best time against the
interleaved FK). For the stream, right before and after it. The batch runs the 7R scans in
blocks shared by one thread per processor (its row says how many threads). Per-call figures are the median of single
calls (and the best of ``--passes`` passes per target beside it); batch figures the best and the
median of ``--passes`` runs. Success is judged by Pinocchio (1e-5 m, 1e-4 rad, inside
the limits); a false success is an answer marked successful that misses.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import gc
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from kin import batch_forward_kinematics
from kin.cli import ArgumentParser, positive_int, run_guarded
from kin.ik import NumericIK, NumericTarget, PoseTarget, get_solver, solve_batch
from kin.ik.analytic.seven_r.subproblems import batch_threads
from kin.robot_model import RobotModel, load_robot

#: Lines of the ``--stream`` run (the poses repeated): several seconds, so that the start-up
#: taken off (and its spread from run to run, about 0.1 s here) weighs little.
STREAM_LINES = 100_000


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik_batch.py", description=__doc__)
    parser.add_argument("--robots", nargs="+", default=["humanoid7", "panda"])
    parser.add_argument("--poses", type=positive_int, default=2000, help="targets (default 2000)")
    parser.add_argument("--calls", type=positive_int, default=500, help="targets timed per call")
    parser.add_argument("--passes", type=positive_int, default=5, help="timing passes")
    parser.add_argument("--stream", action="store_true", help="time kin ik --stdin too")
    return parser


def _fk_timer(robot: RobotModel):  # noqa: ANN202
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.tool_frame)

    def fk(q: np.ndarray) -> float:
        begin = time.perf_counter()
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacement(model, data, frame)
        return time.perf_counter() - begin

    return fk


def _judge(robot: RobotModel, q: np.ndarray, pose: np.ndarray) -> bool:
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.tool_frame)
    pin.forwardKinematics(model, data, q)
    reached = pin.updateFramePlacement(model, data, frame)
    inside = bool(np.all(q >= robot.lower) and np.all(q <= robot.upper))
    position = float(np.linalg.norm(reached.translation - pose[:3, 3]))
    rotation = float(np.linalg.norm(pin.log3(reached.rotation.T @ pose[:3, :3])))
    return inside and position < 1e-5 and rotation < 1e-4


def per_call(
    robot: RobotModel, poses: np.ndarray, seeds: np.ndarray, passes: int, joints: np.ndarray
) -> dict:
    """Median single-call times [s] of the documented and the core call, and of the FK call.

    The FK call is timed at ``joints`` (the targets' own joint vectors, one per target: a
    configuration of the workspace, not the seed, which may be q = 0 where sin and cos are
    cheap).
    """
    solver = get_solver(robot)
    core = NumericIK(robot)
    fk = _fk_timer(robot)
    n = len(poses)
    public = np.full((passes, n), math.inf)
    internal = np.full((passes, n), math.inf)
    fks = np.full((passes, n), math.inf)
    ok = false = 0
    prepared = [NumericTarget(p[:3, 3].copy(), p[:3, :3].copy()) for p in poses]
    # The user's arrays (position [m], rotation), held before the call as the core's are.
    given = [(p[:3, 3].copy(), p[:3, :3].copy()) for p in poses]
    gc.disable()
    try:
        for turn in range(passes):
            for i, pose in enumerate(poses):
                seed = seeds[i]
                fks[turn, i] = fk(joints[i])
                # Which call goes first alternates: the second finds the caches the first warmed.
                if (i + turn) % 2:
                    begin = time.perf_counter()
                    core.solve(prepared[i], seed)
                    internal[turn, i] = time.perf_counter() - begin
                position, rotation = given[i]
                begin = time.perf_counter()
                result = solver.solve(PoseTarget(position, rotation), seed)
                public[turn, i] = time.perf_counter() - begin
                if not (i + turn) % 2:
                    begin = time.perf_counter()
                    core.solve(prepared[i], seed)
                    internal[turn, i] = time.perf_counter() - begin
                if turn == 0 and result.success:
                    good = _judge(robot, result.solutions[0].q, pose)
                    ok += good
                    false += not good
    finally:
        gc.enable()
    return {
        "public": float(np.median(public[0])),
        "public_best": float(np.median(public.min(axis=0))),
        "core": float(np.median(internal[0])),
        "core_best": float(np.median(internal.min(axis=0))),
        "fk": float(np.median(fks)),
        "success": ok / n,
        "false": false,
    }


def fk_median(fk, seeds: np.ndarray) -> float:  # noqa: ANN001
    """The median time [s] of the FK call over ``seeds`` (one call each)."""
    return float(np.median([fk(s) for s in seeds]))


def batch(
    robot: RobotModel,
    poses: np.ndarray,
    seeds: np.ndarray,
    passes: int,
    fk,  # noqa: ANN001
    joints: np.ndarray,
) -> dict:
    """Best and median batch time [s] over ``passes``, in FK calls, success, false successes.

    ``fk``: the FK timer, run at 1000 of ``joints`` (the targets' joint vectors) right before and
    right after each pass; ``"calls"`` in the answer is the median over the passes of the pass's
    time over the mean of its two FK medians (the machine's speed drifts: each pass is measured
    against the FK call of its own moment), ``"fk"`` the median of all FK medians.
    """
    times = []
    ratios = []
    fks = []
    result = None
    for _ in range(passes):
        before = fk_median(fk, joints[:1000])
        begin = time.perf_counter()
        result = solve_batch(robot, poses[:, :3, 3], poses[:, :3, :3], seeds)
        elapsed = time.perf_counter() - begin
        after = fk_median(fk, joints[:1000])
        times.append(elapsed)
        fks += [before, after]
        ratios.append(elapsed / len(poses) / (0.5 * (before + after)))
    assert result is not None
    ok = false = 0
    for i in np.flatnonzero(result.success):
        good = _judge(robot, result.q[i], poses[i])
        ok += good
        false += not good
    return {
        "time": min(times),
        "median": float(np.median(times)),
        "calls": float(np.median(ratios)),
        "success": ok / len(poses),
        "false": false,
        "fk": float(np.median(fks)),
    }


def stream(robot: RobotModel, poses: np.ndarray, lines: int = STREAM_LINES) -> dict:
    """``kin ik --stdin`` on ``lines`` lines, the poses repeated (q = 0 seeds): lines/s.

    The start-up (the same command on one line) is taken off.
    """
    rows = []
    for k in range(lines):
        pose = poses[k % len(poses)]
        r = pose[:3, :3]
        rpy = [
            math.atan2(r[2, 1], r[2, 2]),
            math.asin(-max(-1.0, min(1.0, r[2, 0]))),
            math.atan2(r[1, 0], r[0, 0]),
        ]
        rows.append(json.dumps({"target": pose[:3, 3].tolist(), "rpy": rpy}))
    kin = [sys.executable, "-m", "kin", "ik", "--robot", robot.name, "--stdin"]
    with tempfile.TemporaryDirectory() as folder:
        many = Path(folder) / "lines.jsonl"
        many.write_text("\n".join(rows) + "\n")
        one = Path(folder) / "one.jsonl"
        one.write_text(rows[0] + "\n")  # start-up with the solver's first call (caches, twins)

        def wall(path: Path) -> tuple[float, bytes]:
            with path.open("rb") as source:
                begin = time.perf_counter()
                done = subprocess.run(kin, stdin=source, capture_output=True, check=False)
                return time.perf_counter() - begin, done.stdout

        startup = min(wall(one)[0] for _ in range(3))
        total, out = min((wall(many) for _ in range(2)), key=lambda item: item[0])
    answers = out.decode().splitlines()
    solved = sum(json.loads(line).get("success", False) for line in answers)
    return {
        "lines_per_s": (len(rows) - 1) / max(total - startup, 1e-9),
        "lines": len(answers),
        "success": solved / len(rows),
        "startup": startup,
    }


def tracik_call(robot: RobotModel, poses: np.ndarray, seeds: np.ndarray) -> float | None:
    """TRAC-IK's median single call [s] (Speed, 20 ms), or None when pytracik is not installed."""
    try:
        import pytracik  # noqa: F401
    except ImportError:
        return None
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench_ik_humanoid7 import tracik

    solve = tracik(robot)
    if isinstance(solve, str):
        return None
    times = []
    for pose, seed in zip(poses, seeds):
        begin = time.perf_counter()
        solve(pose[:3, 3], pose[:3, :3], seed.copy())
        times.append(time.perf_counter() - begin)
    return float(np.median(times))


def main(argv: list[str] | None = None) -> int:
    """Print the table."""
    args = get_argument_parser().parse_args(argv)
    print(
        "| robot | seeds | call | time per pose | in FK calls | success | false |\n"
        "|---|---|---|---|---|---|---|"
    )
    for name in args.robots:
        robot = load_robot(name)
        rng = np.random.default_rng(0)
        q = rng.uniform(robot.lower, robot.upper, (args.poses, robot.nq))
        poses = batch_forward_kinematics(robot.table, q)
        random_seeds = rng.uniform(robot.lower, robot.upper, (args.poses, robot.nq))
        fk = _fk_timer(robot)
        fk_time = float(np.median([fk(s) for s in q[:2000]]))
        for label, seeds in (("zero", np.zeros_like(q)), ("random", random_seeds)):
            calls = per_call(robot, poses[: args.calls], seeds[: args.calls], args.passes, q)
            fk_time = calls["fk"]
            for key, title in (("public", "per call (documented)"), ("core", "core (internal)")):
                print(
                    f"| {name} | {label} | {title} | {calls[key] * 1e6:.1f} us "
                    f"(best of {args.passes}: {calls[key + '_best'] * 1e6:.1f} us) | "
                    f"{calls[key] / fk_time:.1f} | {calls['success']:.2%} | {calls['false']} |"
                )
            done = batch(robot, poses, seeds, args.passes, fk, q)
            each = done["time"] / args.poses
            middle = done["median"] / args.poses
            print(
                f"| {name} | {label} | batch of {args.poses} ({batch_threads()} threads) | "
                f"{each * 1e6:.2f} us, median {middle * 1e6:.2f} us ({1.0 / each:,.0f} poses/s; "
                f"{each / fk_time:.1f} FK calls timed interleaved with the calls above) | "
                f"{done['calls']:.1f} | {done['success']:.2%} | {done['false']} |"
            )
        if args.stream:
            before = fk_median(fk, q[:1000])
            streamed = stream(robot, poses)
            fk_time = 0.5 * (before + fk_median(fk, q[:1000]))  # timed around it
            per_line = 1.0 / streamed["lines_per_s"]
            print(
                f"| {name} | zero | kin ik --stdin ({streamed['lines']} lines) | "
                f"{per_line * 1e6:.1f} us ({streamed['lines_per_s']:,.0f} lines/s; start-up "
                f"{streamed['startup']:.2f} s off) | {per_line / fk_time:.1f} | "
                f"{streamed['success']:.2%} | - |"
            )
        peer = tracik_call(robot, poses[: args.calls], random_seeds[: args.calls])
        if peer is not None:
            print(
                f"| {name} | random | TRAC-IK per call (Speed, 20 ms) | {peer * 1e6:.1f} us | "
                f"{peer / fk_time:.1f} | - | - |"
            )
        else:
            print(f"| {name} | - | TRAC-IK | not installed (pip install pytracik) | - | - | - |")
    return 0


if __name__ == "__main__":
    sys.exit(run_guarded("bench_ik_batch.py", lambda: main()))
