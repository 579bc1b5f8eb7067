"""Every arm of the public URDF corpus against TRAC-IK, per call, taking turns target by target.

``python scripts/bench_ik_corpus.py --corpus DIR [--targets N] [--reps R] [--arms TEXT ...]``

DIR is a checkout of github.com/Daniella1/urdf_files_dataset (or a folder holding its
``urdf_files``). Its URDFs are read once each (byte-identical files once): an arm is the chain
``load_robot`` reads from the root to the tip (:func:`arm_tip`: the single deepest leaf, or, when
several leaves are as deep, their lowest common ancestor link: a gripper's fingers end at the
gripper, a ``flange`` and a ``tool0`` at the last link), with 2 to 10 moving joints; a URDF that
gives no such chain (a mobile base, a hand, a mimic joint on the chain) is counted apart. The
small arms and the redundant mobile manipulators (Frankie, Fetch) are read with the base and tip
that ``scripts/bench_ik_small_arms.py`` and ``scripts/bench_redundant.py`` give them (Valkyrie's
forearms to the palm).

Timed is the documented call ``get_solver(robot).solve(PoseTarget(p, R), seed)`` (one verified
answer near the seed, or every branch of a closed form) beside TRAC-IK's ``ik`` (pytracik: 5 ms,
epsilon 1e-6, Speed), on ``N`` reachable targets (Pinocchio FK of the original URDF at seeded
joint vectors inside the limits, clipped to +-pi), seed q = 0 moved into the limits. The two take
turns target by target (the order alternates), ``R`` single calls each, so a machine that speeds
up or slows down weighs on both alike. Success: the first call's answer inside the URDF's limits
and within ``bench_ik_urdf``'s tolerances, judged by Pinocchio on the original URDF.

The table, one row per arm: our solver, our and TRAC-IK's medians of single calls [us], ``ratio``
(ours over TRAC-IK's), success of both, our slowest call [ms]; then the arms above 1.0x, those
whose success is below TRAC-IK's, and the slowest call of the run.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import hashlib  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_ik_small_arms import CORPUS_ARMS  # noqa: E402
from bench_ik_urdf import Judge, tracik  # noqa: E402
from bench_redundant import ARMS as REDUNDANT  # noqa: E402
from bench_redundant import targets as reachable  # noqa: E402
from bench_redundant import urdf_limits  # noqa: E402

from kin import load_arm, load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402
from kin.exceptions import ModelLoadError  # noqa: E402
from kin.ik import PoseTarget, get_solver  # noqa: E402

#: Moving joints an arm of this benchmark has at least and at most.
JOINTS = (2, 10)


@dataclass(frozen=True)
class Arm:
    """One corpus arm: its name (the file inside ``urdf_files``), the file, base and tip links."""

    name: str
    urdf: Path
    base: str | None
    tip: str | None


def arm_tip(urdf: Path) -> str | None:
    """The tip of the URDF's arm: the deepest leaf, or the deepest leaves' common ancestor.

    Depth counts moving joints from the root; ``None`` when the file is no URDF Pinocchio reads.
    """
    import pinocchio as pin

    try:
        model = pin.buildModelFromUrdf(str(urdf))
    except Exception:  # noqa: BLE001 - a file Pinocchio refuses is counted apart
        return None
    bodies = [k for k, f in enumerate(model.frames) if f.type == pin.FrameType.BODY]

    def parent_body(index: int) -> int | None:
        """The body frame above frame ``index`` (through its joint's frame), None at the root."""
        index = model.frames[index].parentFrame
        while index != 0 and model.frames[index].type != pin.FrameType.BODY:
            index = model.frames[index].parentFrame
        return index or None

    def depth(index: int) -> int:
        """Moving joints from the root down to frame ``index``."""
        return len(model.supports[model.frames[index].parentJoint]) - 1

    has_child = {parent_body(k) for k in bodies}
    leaves = [k for k in bodies if k not in has_child]
    if not leaves:
        return None
    deepest = max(depth(k) for k in leaves)
    candidates = sorted(
        (k for k in leaves if depth(k) == deepest), key=lambda k: model.frames[k].name
    )
    if len(candidates) == 1:
        return str(model.frames[candidates[0]].name)
    ancestry = []
    for index in candidates:
        line: list[int] = []
        at: int | None = index
        while at is not None:
            line.append(at)
            at = parent_body(at)
        ancestry.append(line[::-1])
    common = None
    for column in zip(*ancestry, strict=False):
        if len(set(column)) > 1:
            break
        common = column[0]
    chosen = common if common is not None and depth(common) >= JOINTS[0] else candidates[0]
    return str(model.frames[chosen].name)


def corpus_arms(corpus: Path) -> tuple[list[Arm], dict[str, str]]:
    """The corpus' arms, and each file that gives none with the reason."""
    root = corpus / "urdf_files"
    seen: set[str] = set()
    arms: list[Arm] = []
    skipped: dict[str, str] = {}
    chosen = {}  # a file's content -> the base and tip the other benches give it
    for relative, base, tip in (*CORPUS_ARMS.values(), *REDUNDANT.values()):
        if (root / relative).is_file():
            chosen[hashlib.sha1((root / relative).read_bytes()).hexdigest()] = (base, tip)
    for urdf in sorted(root.rglob("*.urdf")):
        relative = str(urdf.relative_to(root))
        digest = hashlib.sha1(urdf.read_bytes()).hexdigest()
        if digest in seen:
            skipped[relative] = "a copy of an earlier file"
            continue
        seen.add(digest)
        base, tip = chosen.get(digest) or (None, arm_tip(urdf))
        if tip is None:
            skipped[relative] = "no URDF Pinocchio reads"
            continue
        arms.append(Arm(relative, urdf, base, tip))
    return arms, skipped


@dataclass(frozen=True)
class Row:
    """One arm's figures: medians [us], success counts, our slowest call [ms]."""

    arm: str
    joints: int
    solver: str
    ours_us: float
    peer_us: float
    ours_ok: int
    peer_ok: int
    targets: int
    ours_max_ms: float

    @property
    def ratio(self) -> float:
        """Our median over TRAC-IK's."""
        return self.ours_us / self.peer_us


def bench_arm(arm: Arm, n: int, reps: int, seed: int) -> Row | str:
    """Time one arm (ours and TRAC-IK taking turns), or why it is not measured."""
    try:
        robot = load_robot(arm.urdf, arm.base, arm.tip)
    except ModelLoadError as err:
        if "(mimic)" in str(err):
            return bench_mimic_arm(arm, n, reps, seed)
        return f"not read: {type(err).__name__}: {' '.join(str(err).split())[:90]}"
    except Exception as err:  # noqa: BLE001 - the reason is a row
        return f"not read: {type(err).__name__}: {' '.join(str(err).split())[:90]}"
    if not JOINTS[0] <= robot.nq <= JOINTS[1]:
        return f"{robot.nq} moving joints"
    file, base, tip = robot.urdf_source or (str(arm.urdf), arm.base, arm.tip)
    judge = Judge(Path(file), base, tip, robot.joint_names)
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    poses = reachable(judge, lower, upper, n, seed)
    limits = urdf_limits(judge)
    peer = tracik(Path(file), base, tip)
    if isinstance(peer, str):
        return f"TRAC-IK {peer}"
    _, prepare, peer_solve = peer
    solver = get_solver(robot)
    start_q = np.minimum(np.maximum(np.zeros(robot.nq), lower), upper)
    targets = [(np.array(p.translation), np.array(p.rotation)) for p in poses]
    peer_targets = [prepare(p) for p in poses]

    def ours(i: int) -> list[np.ndarray]:
        return [s.q for s in solver.solve(PoseTarget(*targets[i]), start_q).solutions]

    def theirs(i: int) -> list[np.ndarray]:
        return peer_solve(peer_targets[i], start_q)

    calls = (ours, theirs)
    times: tuple[list[float], list[float]] = ([], [])
    ok = [0, 0]
    clock = time.perf_counter
    for i in range(n):
        for k in (0, 1) if i % 2 == 0 else (1, 0):
            for rep in range(reps):
                begin = clock()
                answers = calls[k](i)
                times[k].append(clock() - begin)
                if rep == 0:
                    ok[k] += any(judge.on_target(q, poses[i], *limits) for q in answers[:1])
    return Row(
        arm.name,
        robot.nq,
        solver.name,
        statistics.median(times[0]) * 1e6,
        statistics.median(times[1]) * 1e6,
        ok[0],
        ok[1],
        n,
        max(times[0]) * 1e3,
    )


def bench_mimic_arm(arm: Arm, n: int, reps: int, seed: int) -> Row | str:
    """Time one chain with mimic joints: ``get_solver(load_arm(...))``, ours alone.

    TRAC-IK reads a mimic joint as a free one (KDL has no coupling), so it answers another
    question: not timed. Targets and judge: Pinocchio's mimic model of the original URDF
    (``buildModelFromUrdf(..., mimic=True)``) over the independent joints, their URDF limits.
    """
    try:
        chain = load_arm(arm.urdf, arm.base, arm.tip)
    except Exception as err:  # noqa: BLE001 - the reason is a row
        return f"not read: {type(err).__name__}: {' '.join(str(err).split())[:90]}"
    if not JOINTS[0] <= chain.nq <= JOINTS[1]:
        return f"{chain.nq} independent joints (mimic)"
    judge = Judge(
        Path(chain.chain.path), chain.chain.base, chain.chain.tip, chain.joint_names, True
    )
    poses = reachable(judge, chain.lower, chain.upper, n, seed)
    limits = urdf_limits(judge)
    solver = get_solver(chain)
    start_q = np.minimum(np.maximum(np.zeros(chain.nq), chain.lower), chain.upper)
    times, ok = [], 0
    for pose in poses:
        target = PoseTarget(np.array(pose.translation), np.array(pose.rotation))
        for rep in range(reps):
            begin = time.perf_counter()
            answers = [s.q for s in solver.solve(target, start_q).solutions]
            times.append(time.perf_counter() - begin)
            if rep == 0:
                ok += any(judge.on_target(q, pose, *limits) for q in answers[:1])
    median = statistics.median(times) * 1e6
    return Row(arm.name, chain.nq, solver.name, median, math.nan, ok, 0, n, max(times) * 1e3)


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik_corpus.py", description=__doc__)
    parser.add_argument("--corpus", type=Path, required=True, help="the URDF corpus (a checkout)")
    parser.add_argument("--targets", type=positive_int, default=100, help="targets per arm (100)")
    parser.add_argument("--reps", type=positive_int, default=1, help="single calls a target (1)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the joint vectors (0)")
    parser.add_argument(
        "--arms", nargs="+", metavar="TEXT", help="only the arms whose file path holds a TEXT"
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print one row per arm, then the arms behind TRAC-IK and the slowest call."""
    args = get_argument_parser().parse_args(argv)
    if not (args.corpus / "urdf_files").is_dir():
        raise SystemExit(f"--corpus {args.corpus}: no urdf_files folder (a checkout is needed)")
    arms, skipped = corpus_arms(args.corpus)
    if args.arms:
        arms = [a for a in arms if any(text in a.name for text in args.arms)]
    print(f"{len(arms)} arms; {args.targets} targets each, {args.reps} calls a target, in turns")
    print(
        "| arm | joints | solver | ours [us] | TRAC-IK [us] | ratio | ours | TRAC-IK | max [ms] |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    rows: list[Row] = []
    for arm in arms:
        row = bench_arm(arm, args.targets, args.reps, args.seed)
        if isinstance(row, str):
            skipped[arm.name] = row
            continue
        rows.append(row)
        peer = (
            f"{row.peer_us:.1f} | {row.ratio:.2f} | {row.ours_ok}/{row.targets} | "
            f"{row.peer_ok}/{row.targets}"
            if row.peer_us == row.peer_us
            else f"(mimic: not compared) | | {row.ours_ok}/{row.targets} |"
        )
        print(
            f"| {row.arm} | {row.joints} | {row.solver} | {row.ours_us:.1f} | {peer} "
            f"| {row.ours_max_ms:.1f} |",
            flush=True,
        )
    behind = [r for r in rows if r.ratio > 1.0]
    worse = [r for r in rows if r.ours_ok < r.peer_ok]
    mimic = [r for r in rows if r.peer_us != r.peer_us]
    solved = sum(r.ours_ok for r in mimic), sum(r.targets for r in mimic)
    print(f"\nchains with mimic joints: {len(mimic)}, solved {solved[0]}/{solved[1]}")
    print(f"\n{len(rows)} arms measured; {len(skipped)} files without an arm measured")
    print(f"above 1.0x: {len(behind)}: " + ", ".join(f"{r.arm} {r.ratio:.2f}" for r in behind))
    print(f"success below TRAC-IK's: {len(worse)}: " + ", ".join(r.arm for r in worse))
    if rows:
        slowest = max(rows, key=lambda r: r.ours_max_ms)
        print(f"slowest single call: {slowest.ours_max_ms:.1f} ms ({slowest.arm})")
    if args.arms:
        for name, reason in skipped.items():
            if any(text in name for text in args.arms):
                print(f"skipped {name}: {reason}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
