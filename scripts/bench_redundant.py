"""The cost of one IK call on the redundant numeric arms (9-10 joints), beside an earlier commit.

``python scripts/bench_redundant.py --corpus DIR [--against COMMIT] [--targets N] [--reps R]``

The arms are the URDF corpus' mobile manipulators (github.com/Daniella1/urdf_files_dataset, a
checkout or its bare git directory): the Robotics Toolbox's Frankie (a revolute and a prismatic
base joint + Panda, 9 joints, to ``frankie_hand``) and Fetch (the same base, the torso lift and
its 7-joint arm, 10 joints, to ``gripper_link``), each read as the corpus run reads it (the
longest chain to the gripper). The call is the documented one,
``get_solver(load_robot(urdf, base, tip)).solve(PoseTarget(p, R), seed)``, the seed q = 0 moved
into the limits, no warm-up: the first call's one-time costs count.

Targets: Pinocchio's FK of the original URDF (every joint off the chain at 0) at seeded random
joint vectors inside the limits (clipped to +-pi). Each tree (this one and, with ``--against``, a
``git worktree`` of COMMIT, as in ``scripts/bench_per_call.py``) runs in a worker subprocess; the
trees, and TRAC-IK when ``trac_ik`` (pytracik) imports, take turns target by target, each timing
``R`` single calls. Success is judged by the same Pinocchio FK: inside the limits, within
``bench_ik_urdf``'s tolerances. The table: median, p95 and max of the single calls [ms], success.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import contextlib
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

# The helpers of the other benches (imported after a worker has put its tree first on the path).
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_per_call import Tree, _is_commit, worktree  # noqa: E402  (no kin import in it)

ROOT = Path(__file__).resolve().parent.parent

#: arm -> (file inside the corpus' ``urdf_files``, base link, tip link).
ARMS = {
    "fetch": ("robotics-toolbox/fetch_description/robots/fetch.urdf", "base0", "gripper_link"),
    "frankie": (
        "robotics-toolbox/xacro_generated/franka_description/robots/frankie.urdf",
        "panda_base0",
        "frankie_hand",
    ),
}


def worker(root: str) -> None:
    """Serve requests on stdin, one JSON line each, with ``kin`` imported from ``root``.

    ``{"arm": [urdf, base, tip], "targets": [[p, R], ...]}`` builds the solver (no call);
    ``{"time": i, "reps": R}`` answers R single-call times [s] of target i and the last call's
    first solution (or None); ``{"peer": i, ...}`` the same for TRAC-IK.
    """
    import json
    import time

    sys.path.insert(0, root)  # before anything imports kin
    from bench_ik_urdf import tracik

    import kin
    from kin import load_robot
    from kin.ik import PoseTarget, get_solver

    state: dict[str, Any] = {}
    for line in sys.stdin:
        request = json.loads(line)
        if "arm" in request:
            urdf, base, tip = request["arm"]
            robot = load_robot(urdf, base, tip)
            lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
            seed = np.minimum(np.maximum(np.zeros(robot.nq), lower), upper)
            targets = [(np.array(p), np.array(r)) for p, r in request["targets"]]
            peer = tracik(Path(urdf), base, tip) if request["peer"] else "not asked"
            state.update(solver=get_solver(robot), seed=seed, targets=targets, peer=peer)
            reply: dict[str, Any] = {"kin": kin.__file__, "peer": not isinstance(peer, str)}
        else:
            p, r = state["targets"][request.get("time", request.get("peer"))]
            if "time" in request:
                solve, seed = state["solver"].solve, state["seed"]

                def call() -> list[Any]:
                    return [s.q for s in solve(PoseTarget(p, r), seed).solutions]
            else:
                _, _, peer_solve = state["peer"]

                def call() -> list[Any]:
                    return peer_solve((p, r), state["seed"])

            times, answers = [], []
            for _ in range(request["reps"]):
                start = time.perf_counter()
                answers = call()
                times.append(time.perf_counter() - start)
            reply = {"times": times, "q": answers[0].tolist() if answers else None}
        print(json.dumps(reply), flush=True)


class RedundantTree(Tree):
    """A worker subprocess of one source tree serving this script's requests."""

    def __init__(self, root: Path, label: str):
        self.label, self.root = label, root
        command = [sys.executable, str(Path(__file__).resolve()), "--worker", str(root)]
        self.process = subprocess.Popen(
            command, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, cwd=ROOT
        )


def targets(judge: Any, lower: np.ndarray, upper: np.ndarray, n: int, seed: int) -> list[Any]:
    """``n`` reachable targets: the judge's FK at seeded joint vectors inside the limits."""
    rng = np.random.default_rng(seed)
    low, high = np.maximum(lower, -np.pi), np.minimum(upper, np.pi)
    return [judge.pose(rng.uniform(low, high)) for _ in range(n)]


def urdf_limits(judge: Any) -> tuple[np.ndarray, np.ndarray]:
    """The chain's joint limits as the original URDF declares them (a continuous joint: none)."""
    model = judge.model
    lower = [model.lowerPositionLimit[j.idx_q] if j.nq == 1 else -np.inf for j in judge.joints]
    upper = [model.upperPositionLimit[j.idx_q] if j.nq == 1 else np.inf for j in judge.joints]
    return np.array(lower), np.array(upper)


def run(trees: list[RedundantTree], corpus: Path, n: int, reps: int, seed: int) -> None:
    """Print the table: per arm and solver, median, p95 and max of single calls [ms], success."""
    from bench_ik_small_arms import corpus_file
    from bench_ik_urdf import Judge

    from kin import load_robot

    print(f"{n} targets per arm, {reps} single calls each, solvers taking turns; seed q = 0")
    print("| arm | joints | solver | median [ms] | p95 [ms] | max [ms] | success |")
    print("|---|---|---|---|---|---|---|")
    for arm, (relative, base, tip) in ARMS.items():
        urdf = corpus_file(corpus, relative)
        robot = load_robot(urdf, base, tip)
        lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
        judge = Judge(urdf, base, tip, robot.joint_names)
        poses = targets(judge, lower, upper, n, seed)
        # Answers judged inside the URDF's own limits (a tree may read a joint's otherwise).
        lower, upper = urdf_limits(judge)
        listed = [[p.translation.tolist(), p.rotation.tolist()] for p in poses]
        built = [
            tree.ask({"arm": [str(urdf), base, tip], "targets": listed, "peer": k == 0})
            for k, tree in enumerate(trees)
        ]
        for tree, reply in zip(trees, built):
            if not Path(reply["kin"]).resolve().is_relative_to(tree.root.resolve()):
                raise SystemExit(f"{tree.label} imported kin from {reply['kin']}, not its tree")
        runners = [(tree, "time", tree.label) for tree in trees]
        if built[0]["peer"]:
            runners.append((trees[0], "peer", "TRAC-IK (5 ms, Speed)"))
        times: list[list[float]] = [[] for _ in runners]
        solved = [0] * len(runners)
        for i in range(n):
            order = range(len(runners)) if i % 2 == 0 else reversed(range(len(runners)))
            for k in order:
                tree, kind, _ = runners[k]
                reply = tree.ask({kind: i, "reps": reps})
                times[k] += reply["times"]
                q = reply["q"]
                solved[k] += q is not None and judge.on_target(np.array(q), poses[i], lower, upper)
        for (_, _, label), spent, ok in zip(runners, times, solved):
            ms = np.array(spent) * 1e3
            row = [arm, str(robot.nq), label, f"{np.median(ms):.3f}"]
            row += [f"{np.percentile(ms, 95):.3f}", f"{ms.max():.1f}", f"{ok}/{n}"]
            print("| " + " | ".join(row) + " |", flush=True)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark (``--worker ROOT`` runs :func:`worker` instead, see the end)."""
    from kin.cli import ArgumentParser, positive_int

    parser = ArgumentParser(prog="bench_redundant.py", description=__doc__)
    parser.add_argument("--corpus", type=Path, required=True, help="the URDF corpus (or bare git)")
    parser.add_argument("--against", metavar="COMMIT", help="an earlier commit to time beside")
    parser.add_argument("--targets", type=positive_int, default=200, help="targets per arm (200)")
    parser.add_argument("--reps", type=positive_int, default=1, help="single calls per target (1)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the joint vectors (0)")
    options = parser.parse_args(argv)
    if not options.corpus.is_dir():
        parser.error(f"--corpus {options.corpus}: not a folder (a checkout or its bare git dir)")
    if options.against and not _is_commit(options.against):
        parser.error(f"--against {options.against}: not a commit of this repository")
    with contextlib.ExitStack() as stack:
        temporary = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="bench_red_")))
        trees = [RedundantTree(ROOT, "this tree")]
        stack.callback(trees[0].close)
        if options.against:
            old = worktree(options.against, temporary)  # removed after its worker has ended
            remove = ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(old)]
            stack.callback(subprocess.run, remove, check=False)
            trees.append(RedundantTree(old, options.against))
            stack.callback(trees[1].close)
        run(trees, options.corpus, options.targets, options.reps, options.seed)
    return 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["--worker"]:  # a tree's worker (RedundantTree starts it)
        worker(sys.argv[2])
        raise SystemExit(0)
    raise SystemExit(main())
