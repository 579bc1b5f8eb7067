"""The cost of one documented IK call, this tree beside an earlier commit, alternated per target.

``python scripts/bench_per_call.py [--against COMMIT] [--targets N] [--reps R] [--arms ...]``

The call is the documented one, ``get_solver(robot).solve(PoseTarget(p, R), seed)``: the target
built inside the timed call from NumPy arrays made outside it, the seed q = 0 (moved into the
limits when zero is outside them). For each arm the same joint vectors (seeded, inside the
limits) give the targets, each tree making its own poses with Pinocchio's FK of its own model.

Each tree runs in a subprocess of its own that imports ``kin`` from that tree's sources: this
tree, and with ``--against`` a ``git worktree`` of COMMIT in a temporary directory (its compiled
twins built there first; removed at the end). The two take turns target by target (the order
flips every target), each timing ``R`` single calls of the target; the table gives the median of
all single calls [us], their ratio, and how many targets got the same answers (status and every
solution's joint vector to 1e-12 rad) from both trees. With ur-analytic-ik installed (the
``bench`` extra), the UR5 row also times its ``ur5.inverse_kinematics`` (all branches, C++) on
its own FK of the same joint vectors, in this tree's process, taking turns with ours.

``--breakdown`` prints where the microseconds of one call go in this tree
(``scripts/bench_call_breakdown.py``).
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import json
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent

#: The arms: a UR wrist, a spherical wrist, a general 6R (no closed-form family), a 7R.
ARMS = ("ur5", "puma560", "tests/data/six_r/xarm6.toml", "humanoid7")


def worker(root: str) -> None:
    """Serve timing requests on stdin, one JSON line each, with ``kin`` imported from ``root``.

    Requests: ``{"arm": NAME, "qs": [[...], ...]}`` builds the arm's solver and targets and
    answers ``{"solver": ..., "answers": [...], "kin": file}``; ``{"time": i, "reps": R}`` answers
    R single-call times [s] of target i (``{"peer": i, ...}``: ur-analytic-ik's).
    """
    sys.path.insert(0, root)
    import numpy as np
    import pinocchio as pin

    import kin
    from kin import load_robot
    from kin.ik import PoseTarget, get_solver

    try:
        from kin.configuration import default_seed
    except ImportError:  # a tree before it: zero

        def default_seed(robot: Any) -> Any:
            return np.zeros(robot.nq)

    perf = __import__("time").perf_counter
    state: dict[str, Any] = {}
    for line in sys.stdin:
        request = json.loads(line)
        if "arm" in request:
            name = request["arm"]
            robot = load_robot(ROOT / name if "/" in name else name)
            solver = get_solver(robot)
            model, data = robot.model, robot.model.createData()
            fid = model.getFrameId(robot.tool_frame)
            poses = []
            for q in request["qs"]:
                pin.framesForwardKinematics(model, data, np.array(q))
                pose = data.oMf[fid]
                poses.append((pose.translation.copy(), pose.rotation.copy()))
            seed = default_seed(robot)
            answers = []
            for p, r in poses:
                result = solver.solve(PoseTarget(p, r), seed)
                answers.append([result.status, [s.q.tolist() for s in result.solutions]])
            state.update(solver=solver, poses=poses, seed=seed, peer=None)
            if name == "ur5":
                state["peer"] = _ur_peer(request["qs"])
            reply: dict[str, Any] = {"solver": solver.name, "answers": answers}
            reply.update(kin=kin.__file__, peer=state["peer"] is not None)
        elif "time" in request:
            solve, seed = state["solver"].solve, state["seed"]
            p, r = state["poses"][request["time"]]
            times = []
            for _ in range(request["reps"]):
                start = perf()
                solve(PoseTarget(p, r), seed)
                times.append(perf() - start)
            reply = {"times": times}
        else:
            call, pose = state["peer"]
            matrix = pose[request["peer"]]
            times = []
            for _ in range(request["reps"]):
                start = perf()
                call(matrix)
                times.append(perf() - start)
            reply = {"times": times}
        print(json.dumps(reply), flush=True)


def _ur_peer(qs: list[list[float]]) -> tuple[Any, list[Any]] | None:
    """ur-analytic-ik's UR5 IK and its own FK poses (4x4) of ``qs``, or None (not installed)."""
    try:
        import ur_analytic_ik
    except ImportError:
        return None
    import numpy as np

    arm = ur_analytic_ik.ur5
    poses = [np.ascontiguousarray(arm.forward_kinematics(*q)) for q in qs]
    return arm.inverse_kinematics, poses


class Tree:
    """A worker subprocess of one source tree (its ``kin`` imported from ``root``)."""

    def __init__(self, root: Path, label: str):
        self.label = label
        command = [sys.executable, str(Path(__file__).resolve()), "--worker", str(root)]
        self.process = subprocess.Popen(
            command,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            cwd=tempfile.gettempdir(),
        )
        self.root = root

    def ask(self, request: dict[str, Any]) -> dict[str, Any]:
        """One request and its reply."""
        assert self.process.stdin is not None and self.process.stdout is not None
        self.process.stdin.write(json.dumps(request) + "\n")
        self.process.stdin.flush()
        line = self.process.stdout.readline()
        if not line:
            raise SystemExit(f"the worker of {self.label} stopped (see its error above)")
        return json.loads(line)  # type: ignore[no-any-return]

    def close(self) -> None:
        """End the worker (its stdin closed: it returns)."""
        assert self.process.stdin is not None
        self.process.stdin.close()
        self.process.wait(timeout=60)


def same_answers(ours: list[Any], theirs: list[Any], tol: float = 1e-12) -> int:
    """How many targets got the same status and solutions (to ``tol`` [rad]) from both trees."""
    same = 0
    for (status_a, qs_a), (status_b, qs_b) in zip(ours, theirs):
        if status_a != status_b or len(qs_a) != len(qs_b):
            continue
        if all(abs(x - y) <= tol for qa, qb in zip(qs_a, qs_b) for x, y in zip(qa, qb)):
            same += 1
    return same


#: Builds the compiled twins of a tree into that tree (argv: the tree, a scratch folder), without
#: its project metadata (which this venv's setuptools may not read): from its setup.py's one
#: declaration (since 7752f8b), else from its pyproject.toml's ext-modules table (before).
BUILD_TWINS = """
import runpy, sys, tomllib
from pathlib import Path
from setuptools import Extension, setup
tree = Path(sys.argv[1])
if (tree / "setup.py").is_file():
    listed = runpy.run_path(str(tree / "setup.py"))["twin_extensions"](tree)
else:
    listed = tomllib.loads((tree / "pyproject.toml").read_text())["tool"]["setuptools"]["ext-modules"]
modules = [
    Extension(
        e["name"],
        [str(tree / s) for s in e["sources"]],
        include_dirs=[str(tree), *(str(tree / d) for d in e.get("include_dirs", ()))],
    )
    for e in listed
]
setup(name="twins", ext_modules=modules, script_args=[
    "-q", "build_ext", "--build-lib", str(tree), "--build-temp", sys.argv[2]])
"""


def worktree(commit: str, where: Path) -> Path:
    """A ``git worktree`` of ``commit`` under ``where``, its compiled twins built in it."""
    path = where / "tree"
    subprocess.run(
        ["git", "-C", str(ROOT), "worktree", "add", "--detach", "--quiet", str(path), commit],
        check=True,
    )
    print(f"building the compiled twins of {commit} ...", file=sys.stderr, flush=True)
    subprocess.run(
        [sys.executable, "-c", BUILD_TWINS, str(path), str(where / "build")],
        cwd=where,
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return path


def _is_commit(name: str) -> bool:
    """Whether ``name`` names a commit of this repository."""
    found = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--verify", "--quiet", f"{name}^{{commit}}"],
        capture_output=True,
    )
    return found.returncode == 0


def joint_vectors(arm: str, n: int, seed: int) -> list[list[float]]:
    """``n`` seeded random joint vectors inside the arm's limits (this tree's model) [rad]."""
    import numpy as np

    from kin import load_robot

    robot = load_robot(arm if "/" not in arm else ROOT / arm)
    rng = np.random.default_rng(seed)
    lower = np.maximum(robot.model.lowerPositionLimit, -np.pi)
    upper = np.minimum(robot.model.upperPositionLimit, np.pi)
    return rng.uniform(lower, upper, size=(n, robot.nq)).tolist()  # type: ignore[no-any-return]


def run(trees: list[Tree], arms: tuple[str, ...], n: int, reps: int, seed: int) -> None:
    """Print the table: per arm, each tree's median single call [us], ratio, same answers."""
    labels = [tree.label for tree in trees]
    head = ["arm", "solver", *(f"{label} [us]" for label in labels)]
    if len(trees) == 2:
        head += [f"{labels[0]} / {labels[1]}", "same answers"]
    print("| " + " | ".join([*head, "ur-analytic-ik [us]", "ours / it"]) + " |")
    print("|" + "---|" * (len(head) + 2))
    for arm in arms:
        qs = joint_vectors(arm, n, seed)
        built = [tree.ask({"arm": arm, "qs": qs}) for tree in trees]
        for tree, reply in zip(trees, built):
            if not Path(reply["kin"]).resolve().is_relative_to(tree.root.resolve()):
                raise SystemExit(f"{tree.label} imported kin from {reply['kin']}, not its tree")
        times: list[list[float]] = [[] for _ in trees]
        peer: list[float] = []
        for i in range(n):
            order = range(len(trees)) if i % 2 == 0 else reversed(range(len(trees)))
            for k in order:
                times[k] += trees[k].ask({"time": i, "reps": reps})["times"]
            if built[0]["peer"]:
                peer += trees[0].ask({"peer": i, "reps": reps})["times"]
        medians = [statistics.median(t) * 1e6 for t in times]
        row = [Path(arm).stem, built[0]["solver"], *(f"{m:.2f}" for m in medians)]
        if len(trees) == 2:
            same = same_answers(built[0]["answers"], built[1]["answers"])
            row += [f"{medians[0] / medians[1]:.2f}", f"{same}/{n}"]
        if peer:
            row += [
                f"{statistics.median(peer) * 1e6:.2f}",
                f"{medians[0] * 1e-6 / statistics.median(peer):.2f}",
            ]
        else:
            row += ["", ""]
        print("| " + " | ".join(row) + " |", flush=True)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark (or, with ``--worker``, serve one tree's timings)."""
    args = sys.argv[1:] if argv is None else argv
    if args[:1] == ["--worker"]:
        worker(args[1])
        return 0
    from kin.cli import ArgumentParser, positive_int

    parser = ArgumentParser(prog="bench_per_call.py", description=__doc__)
    parser.add_argument("--against", metavar="COMMIT", help="an earlier commit to time beside")
    parser.add_argument("--targets", type=positive_int, default=200, help="targets per arm (200)")
    parser.add_argument("--reps", type=positive_int, default=5, help="single calls per target (5)")
    parser.add_argument("--seed", type=int, default=0, help="random seed of the joint vectors (0)")
    parser.add_argument("--arms", nargs="+", default=ARMS, help=f"arms (default: {' '.join(ARMS)})")
    parser.add_argument("--breakdown", action="store_true", help="where one call's time goes")
    options = parser.parse_args(args)
    if options.against and not _is_commit(options.against):
        parser.error(f"--against {options.against}: not a commit of this repository")
    if options.breakdown:
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from bench_call_breakdown import breakdown

        breakdown(tuple(options.arms), options.targets, options.reps, options.seed)
        return 0
    temporary = Path(tempfile.mkdtemp(prefix="bench_per_call_"))
    trees: list[Tree] = []
    try:
        trees.append(Tree(ROOT, "this tree"))
        if options.against:
            old = worktree(options.against, temporary)
            trees.append(Tree(old, options.against))
        print(
            f"{options.targets} targets per arm, {options.reps} single calls each, trees taking "
            f"turns; medians of single calls; seed q = 0 (moved into the limits)"
        )
        run(trees, tuple(options.arms), options.targets, options.reps, options.seed)
    finally:
        for tree in trees:
            tree.close()
        if options.against:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(temporary / "tree")],
                check=False,
            )
        shutil.rmtree(temporary, ignore_errors=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
