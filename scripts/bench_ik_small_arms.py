"""Benchmark IK of the small arms (SCARA, yaw_planar 4R, Kinova 4-DOF, QArm) against TRAC-IK.

Targets: Pinocchio's FK of the arm's URDF at random joint vectors inside the limits (so
reachable); the toolbox tables' URDF is the one ``kin`` generates, Kinova's the maker's
(``tests/data/kinova4``). With ``--corpus DIR`` (a checkout of the public URDF corpus
github.com/Daniella1/urdf_files_dataset, or its bare git directory) the corpus' small arms are
added (:data:`CORPUS_ARMS`: every Kinova 4-DOF URDF, the QArm, the ``yaw_planar`` 4R arms, the
Valkyrie forearm). TRAC-IK returns one answer; we return every branch, each verified. Timed is the call a user makes,
``get_solver(robot).solve(target, seed)``, on the position (``ours: position``, every branch
with the free joint stated) and on the full pose (``ours: pose``); TRAC-IK solves the full pose
(it takes no position-only target). Seed: ``q = 0`` moved into the limits. The solvers take
turns target by target, in an order rotated each target; the medians are of single calls,
success is judged by Pinocchio on that URDF (1e-5 m, 1e-4 rad for poses, inside the limits), and
so is each rejected answer (on target, outside the limits: a rounded arm's are listed unpolished).
``ratio`` is our median over TRAC-IK's.

    python scripts/bench_ik_small_arms.py
    python scripts/bench_ik_small_arms.py --arms al5d mico4 --targets 500
    python scripts/bench_ik_small_arms.py --corpus /path/to/urdf_files_dataset
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402

from kin import RobotModel, load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402
from kin.ik import PoseTarget, PositionTarget, get_solver  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_ik_urdf import POSITION_TOL, ROTATION_TOL, Judge, tracik  # noqa: E402

DATA = Path(__file__).resolve().parent.parent / "tests" / "data"

#: arm -> (table or URDF file, base link, tip link; None: the table's generated URDF).
ARMS: dict[str, tuple[Path, str | None, str | None]] = {
    "cobra600": (DATA / "toolbox" / "cobra600.toml", None, None),
    "al5d": (DATA / "toolbox" / "al5d.toml", None, None),
    "orion5": (DATA / "toolbox" / "orion5.toml", None, None),
    "mico4": (DATA / "kinova4" / "m1n4s200_standalone.urdf", "root", "m1n4s200_end_effector"),
    "jaco4": (DATA / "kinova4" / "j2n4s300_standalone.urdf", "root", "j2n4s300_end_effector"),
}

#: Small arms of the URDF corpus: arm -> (file inside the corpus' ``urdf_files``, base link
#: (None: the root), tip link).
CORPUS_ARMS: dict[str, tuple[str, str | None, str]] = {
    "c_mico4": (
        "oems/xacro_generated/kinova_robotics/kinova_description/urdf/m1n4s200_standalone.urdf",
        None,
        "m1n4s200_end_effector",
    ),
    "c_jaco4": (
        "oems/xacro_generated/kinova_robotics/kinova_description/urdf/j2n4s300_standalone.urdf",
        None,
        "j2n4s300_end_effector",
    ),
    "c_jaco4_rtb": (
        "robotics-toolbox/xacro_generated/kinova_description/urdf/j2n4s300.urdf",
        None,
        "j2n4s300_end_effector",
    ),
    "c_mico4_mw": (
        "matlab/kinova_description/urdf/kinovaMicoM1N4S200.urdf",
        None,
        "m1n4s200_end_effector",
    ),
    "c_qarm": ("oems/qarm_quanser/qarm_description/urdf/QARM.urdf", None, "END-EFFECTOR"),
    "c_qarm_mw": ("matlab/qarm_description/urdf/quanserQArm.urdf", None, "END-EFFECTOR"),
    "c_al5d": ("robotics-toolbox/al5d_description/urdf/al5d_robot.urdf", None, "link4"),
    "c_openmanip": (
        "oems/xacro_generated/open-manipulator_robotis/open_manipulator_description/urdf/"
        "open_manipulator_robot.urdf",
        None,
        "end_effector_link",
    ),
    "c_openmanip_mw": (
        "matlab/open_manipulator_description/urdf/robotisOpenManipulator.urdf",
        None,
        "end_effector_link",
    ),
    "c_pincher": (
        "robotics-toolbox/pxpincher/urdf/pincher_arm.urdf",
        None,
        "gripper_finger_base_link",
    ),
    "c_turtlearm": (
        "robotics-toolbox/pxpincher/urdf/turtlebot_arm.urdf",
        None,
        "gripper_static_finger_link",
    ),
    "c_px100": (
        "robotics-toolbox/xacro_generated/interbotix_descriptions/urdf/px100.urdf",
        None,
        "/ee_gripper_link",
    ),
    "c_val_fl": (
        "robotics-toolbox/val_description/model/robots/forearm_left.urdf",
        None,
        "rightPalm",
    ),
    "c_val_fr": (
        "robotics-toolbox/val_description/model/robots/forearm_right.urdf",
        None,
        "rightPalm",
    ),
}


def corpus_file(corpus: Path, relative: str) -> Path:
    """A corpus URDF: from a checkout, or written out of a bare git directory (``git show``)."""
    checkout = corpus / "urdf_files" / relative
    if checkout.is_file():
        return checkout
    text = subprocess.run(
        ["git", "--git-dir", str(corpus), "show", f"HEAD:urdf_files/{relative}"],
        check=True,
        capture_output=True,
    ).stdout
    handle, name = tempfile.mkstemp(suffix=".urdf", prefix=f"{Path(relative).stem}_")
    with os.fdopen(handle, "wb") as stream:
        stream.write(text)
    return Path(name)


#: One timed call: (target pose, seed) -> the joint vectors it returns as answers, and those it
#: returns as rejected (outside the limits; TRAC-IK: none).
Call = Callable[[pin.SE3, np.ndarray], tuple[list[np.ndarray], list[np.ndarray]]]


def urdf_of(robot: RobotModel, source: Path) -> tuple[Path, str, str]:
    """The URDF file, base and tip the arm was read from (a table's generated URDF written out)."""
    if robot.urdf_source is not None:
        file, base, tip = robot.urdf_source
        return Path(file), base, tip
    handle, name = tempfile.mkstemp(suffix=".urdf", prefix=f"{source.stem}_")
    with os.fdopen(handle, "w") as stream:
        stream.write(robot.urdf)
    return Path(name), "base_link", robot.tool_frame


def ours(robot: RobotModel, position_only: bool) -> Call:
    """Our documented call on a position or a full pose (the target built in the call)."""
    solver = get_solver(robot)

    def call(target: pin.SE3, seed: np.ndarray) -> tuple[list[np.ndarray], list[np.ndarray]]:
        goal = (
            PositionTarget(target.translation)
            if position_only
            else PoseTarget(target.translation, target.rotation)
        )
        result = solver.solve(goal, seed)
        return [s.q for s in result.solutions], [s.q for s in result.rejected]

    return call


def on_target(
    judge: Judge,
    q: np.ndarray,
    target: pin.SE3,
    position_only: bool,
    lower,  # noqa: ANN001
    upper,  # noqa: ANN001
    inside: bool = True,
) -> bool:
    """Whether ``q`` reaches the position (or the pose) and is inside the limits (or outside)."""
    q = np.asarray(q, dtype=float)
    if bool(np.all(q >= lower - 1e-9) and np.all(q <= upper + 1e-9)) != inside:
        return False
    reached = judge.pose(q)
    if np.linalg.norm(reached.translation - target.translation) >= POSITION_TOL:
        return False
    return position_only or bool(
        np.linalg.norm(pin.log3(reached.rotation.T @ target.rotation)) < ROTATION_TOL
    )


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik_small_arms.py", description=__doc__)
    parser.add_argument(
        "--arms", nargs="+", choices=(*ARMS, *CORPUS_ARMS), help="arms (default: every one)"
    )
    parser.add_argument(
        "--corpus",
        type=Path,
        help="the URDF corpus (checkout or bare git directory): adds its small arms",
    )
    parser.add_argument("--targets", type=positive_int, default=200, help="targets per arm (200)")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print one row per arm and solver: success, median single call, answers, rejected, ratio."""
    args = get_argument_parser().parse_args(argv)
    print(
        f"{'arm':<14} {'solver':<46} {'success':>8} {'median':>10} {'answers':>8} {'false':>6} "
        f"{'rejected':>8} {'ratio':>6}   (answers: valid per target; false: answers off target or "
        "outside the limits, or rejected ones off target or inside; rejected: per target, on "
        "target outside the limits; ratio: median over TRAC-IK's)"
    )
    print(
        "TRAC-IK returns one answer per call; ours returns every branch of the closed form, "
        "each verified (a free joint stated in its label)"
    )
    arms = args.arms or [*ARMS, *(CORPUS_ARMS if args.corpus else ())]
    for arm in arms:
        if arm in ARMS:
            source, base, tip = ARMS[arm]
        elif args.corpus is None:
            print(f"{arm:<14} needs --corpus")
            continue
        else:
            relative, base, tip = CORPUS_ARMS[arm]
            source = corpus_file(args.corpus, relative)
        robot = load_robot(source, base, tip)
        urdf, base_link, tip_link = urdf_of(robot, source)
        judge = Judge(urdf, base_link, tip_link, robot.joint_names)
        lower, upper = robot.lower, robot.upper
        name = get_solver(robot).name
        calls: dict[str, tuple[Call, bool]] = {
            f"ours: {name}, position": (ours(robot, True), True),
            f"ours: {name}, pose": (ours(robot, False), False),
        }
        peer = tracik(urdf, base_link, tip_link)
        if isinstance(peer, str):
            print(f"{arm:<14} TRAC-IK: {peer}")
        else:
            label, prepare, solve = peer
            calls[label] = ((lambda t, s, p=prepare, f=solve: (f(p(t), s), [])), False)
        rng = np.random.default_rng(11)
        qs = rng.uniform(
            np.maximum(lower, -np.pi), np.minimum(upper, np.pi), (args.targets, robot.nq)
        )
        targets = [judge.pose(q) for q in qs]
        seed = np.clip(np.zeros(robot.nq), lower, upper)
        times: dict[str, list[float]] = {key: [] for key in calls}
        hits = dict.fromkeys(calls, 0)
        answers = dict.fromkeys(calls, 0)
        false = dict.fromkeys(calls, 0)
        rejected = dict.fromkeys(calls, 0)
        keys = list(calls)
        clock = time.perf_counter
        for i, target in enumerate(targets):
            turn = i % len(keys)
            for key in keys[turn:] + keys[:turn]:
                call, position_only = calls[key]
                start = clock()
                found, outside = call(target, seed)
                times[key].append(clock() - start)
                valid = [
                    q for q in found if on_target(judge, q, target, position_only, lower, upper)
                ]
                hits[key] += bool(valid)
                answers[key] += len(valid)
                false[key] += len(found) - len(valid)
                shown = [
                    q
                    for q in outside
                    if on_target(judge, q, target, position_only, lower, upper, inside=False)
                ]
                rejected[key] += len(shown)
                false[key] += len(outside) - len(shown)
        peer_median = next(
            (statistics.median(times[k]) for k in keys if not k.startswith("ours")), None
        )
        for key in keys:
            median = statistics.median(times[key])
            ratio = f"{median / peer_median:>6.2f}" if peer_median else f"{'-':>6}"
            print(
                f"{arm:<14} {key:<46} {100.0 * hits[key] / len(targets):>7.1f}% "
                f"{median * 1e6:>8.1f}us {answers[key] / len(targets):>8.2f} {false[key]:>6} "
                f"{rejected[key] / len(targets):>8.2f} {ratio}"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
