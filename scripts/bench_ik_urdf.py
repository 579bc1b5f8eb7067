"""Benchmark IK of arms given as URDFs (example-robot-data) against TRAC-IK, ssik and EAIK.

For each arm, poses from Pinocchio's FK of the original URDF at random joint vectors inside the
limits; every solver gets the same URDF, base and tip, and every answer is judged by Pinocchio
on the original URDF (1e-5 m, 1e-4 rad, inside the URDF's limits). Timed is the call a user makes:
ours is ``kin.ik.get_solver(kin.load_robot(urdf, base, tip)).solve(PoseTarget(p, R), seed)``
(the solver built once, outside the loop, like each peer's). Every-branch arms (a closed form):
our time for all branches beside ssik's and EAIK's all-branch call, and beside ssik's prebuilt
module of the arm when ssik ships one (:data:`SSIK_PREBUILT`; its FK compared with the URDF's
first, skipped with the reason when it is another arm); redundant arms: one verified answer near
the seed (q = 0 moved into the limits) beside TRAC-IK's. The table prints the median of single
calls, the success rate and our median over each row's (``ours x``); the solvers take turns
target by target (:func:`measure`); peers not installed (``pip install ".[bench]"``) or
refusing an arm are named.

    python scripts/bench_ik_urdf.py                  # every arm, 200 poses each
    python scripts/bench_ik_urdf.py --arms ur5 panda --poses 1000
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import importlib.metadata  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402

from dh2urdf.urdf_chain import read_chain  # noqa: E402
from kin import load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402
from kin.ik import PoseTarget, get_solver  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ssik_chains import distinct_mod_2pi  # noqa: E402

#: arm -> (URDF inside example-robot-data's robots folder, base link or None, tip link or None:
#: the chain's end).
ARMS = {
    "ur3": ("ur_description/urdf/ur3_robot.urdf", None, "tool0"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", None, "tool0"),
    "kinova": ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    "z1": ("z1_description/urdf/z1.urdf", None, "link06"),
    "panda": ("panda_description/urdf/panda.urdf", None, "panda_link8"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, "link_eef"),
    "tiago": ("tiago_description/robots/tiago.urdf", "torso_lift_link", "arm_tool_link"),
    "baxter_left": ("baxter_description/urdf/baxter.urdf", "torso", "left_gripper"),
    "baxter_right": ("baxter_description/urdf/baxter.urdf", "torso", "right_gripper"),
    "ur5_limited": ("ur_description/urdf/ur5_joint_limited_robot.urdf", None, "tool0"),
    "so100": ("so_arm_description/urdf/so100.urdf", None, "gripper"),
    "so101": ("so_arm_description/urdf/so101.urdf", None, "gripper_link"),
    "double_pendulum": (
        "double_pendulum_description/urdf/double_pendulum_continuous.urdf",
        None,
        None,
    ),
    "asr_twodof": ("asr_twodof_description/urdf/TwoDofs.urdf", None, None),
}

#: arm -> ssik's prebuilt modules (``ssik.prebuilt.<maker>.<arm>_ik``) that may be the same arm,
#: in order: the first whose FK matches the URDF chain's (up to a fixed base and tool frame) is
#: timed; none matching is a named reason (a UR10e is not a UR10).
SSIK_PREBUILT = {
    "ur3": ("universal_robots.ur3e_ik",),
    "ur5": ("universal_robots.ur5_ik",),
    "ur5_limited": ("universal_robots.ur5_ik",),
    "ur10": ("universal_robots.ur10e_ik",),
    "kinova": ("kinova.j2s6s300_ik", "kinova.jaco2_ik"),
    "z1": ("unitree.z1_ik",),
    "panda": ("franka.panda_ik",),
    "xarm7": ("ufactory.xarm7_ik",),
}

#: A solver whose first timing pass over the poses took longer than this [s] runs no other.
SLOW_PASS = 5.0

#: Judge's tolerances [m], [rad].
POSITION_TOL, ROTATION_TOL = 1e-5, 1e-4


def erd(relative: str) -> Path:
    """Absolute path of an example-robot-data file (``robots/<relative>``)."""
    suffix = f"example-robot-data/robots/{relative}"
    for file in importlib.metadata.files("example-robot-data") or ():
        if str(file).endswith(suffix):
            return Path(str(file.locate()))
    raise FileNotFoundError(suffix)


class Judge:
    """Pinocchio's FK of the original URDF between base and tip, and its limits."""

    def __init__(
        self, urdf: Path, base: str, tip: str, joints: tuple[str, ...], mimic: bool = False
    ):
        # mimic: Pinocchio's own mimic joints (``joints`` then the independent ones)
        self.model = pin.buildModelFromUrdf(str(urdf), mimic=mimic)
        self.data = self.model.createData()
        self.base = self.model.getFrameId(base, pin.FrameType.BODY)
        self.tip = self.model.getFrameId(tip, pin.FrameType.BODY)
        self.joints = [self.model.joints[self.model.getJointId(name)] for name in joints]

    def pose(self, q: np.ndarray) -> pin.SE3:
        """``T_base_tip`` at the chain's joint vector ``q`` (every other joint at 0)."""
        full = pin.neutral(self.model)
        for joint, value in zip(self.joints, q, strict=True):
            if joint.nq == 2:
                full[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
            else:
                full[joint.idx_q] = value
        pin.forwardKinematics(self.model, self.data, full)
        pin.updateFramePlacements(self.model, self.data)
        return self.data.oMf[self.base].inverse() * self.data.oMf[self.tip]

    def on_target(self, q: np.ndarray, target: pin.SE3, lower, upper) -> bool:  # noqa: ANN001
        """Whether ``q`` is inside the limits and reaches ``target`` within the tolerances."""
        q = np.asarray(q, dtype=float)
        if not (np.all(q >= lower - 1e-9) and np.all(q <= upper + 1e-9)):
            return False
        reached = self.pose(q)
        position = np.linalg.norm(reached.translation - target.translation)
        angle = np.linalg.norm(pin.log3(reached.rotation.T @ target.rotation))
        return bool(position < POSITION_TOL and angle < ROTATION_TOL)


#: A solver's timed call: its own form of the target (:data:`Prepare`), the seed -> answers.
Solve = Callable[[Any, np.ndarray], list[np.ndarray]]
#: A target pose in the form the solver's API takes (NumPy arrays in its frames): made outside
#: the timing, as a user holds targets in the form their solver takes.
Prepare = Callable[[pin.SE3], Any]


def _arrays(target: pin.SE3) -> tuple[np.ndarray, np.ndarray]:
    """Position [m] and rotation of a pose as NumPy arrays."""
    return np.array(target.translation), np.array(target.rotation)


def ours(urdf: Path, base: str | None, tip: str | None) -> tuple[str, Prepare, Solve]:
    """Our documented call on the robot loaded from the URDF (the PoseTarget built in the call)."""
    robot = load_robot(urdf, base, tip)
    solver = get_solver(robot)

    def solve(target: tuple[np.ndarray, np.ndarray], seed: np.ndarray) -> list[np.ndarray]:
        result = solver.solve(PoseTarget(*target), seed)
        return [s.q for s in result.solutions]

    return solver.name, _arrays, solve


def _kdl_friendly(urdf: Path) -> Path:
    """The URDF with a dummy root link above its root (KDL rejects a root link with inertia)."""
    import tempfile
    import xml.etree.ElementTree as ElementTree

    root = ElementTree.parse(urdf).getroot()
    children = {c.get("link") for c in root.iter("child")}
    first = next(link.get("name") for link in root.iter("link") if link.get("name") not in children)
    ElementTree.SubElement(root, "link", name="bench_root")
    joint = ElementTree.SubElement(root, "joint", name="bench_root_joint", type="fixed")
    ElementTree.SubElement(joint, "parent", link="bench_root")
    ElementTree.SubElement(joint, "child", link=str(first))
    handle, name = tempfile.mkstemp(suffix=".urdf")
    os.close(handle)
    ElementTree.ElementTree(root).write(name)
    return Path(name)


def tracik(urdf: Path, base: str, tip: str) -> tuple[str, Prepare, Solve] | str:
    """TRAC-IK (pytracik): 5 ms, epsilon 1e-6, Speed; or why it is not measured."""
    try:
        from trac_ik import TracIK
    except ImportError as err:
        return f"not installed ({err})"
    try:
        friendly = str(_kdl_friendly(urdf))
        solver = TracIK(base, tip, friendly, timeout=0.005, epsilon=1e-6, solver_type="Speed")
        # pytracik misreads some URDFs' limits (panda's as [0, 0]): hand it the chain's.
        chain = read_chain(urdf, base, tip)
        lower = np.array([max(j.lower, -2 * math.pi) for j in chain.joints])
        upper = np.array([min(j.upper, 2 * math.pi) for j in chain.joints])
        import pytracik

        pytracik.set_joint_limits(solver._ik_solver, lower, upper)
    except Exception as err:  # noqa: BLE001 - a peer's refusal is a row of the table
        return f"refuses: {' '.join(str(err).split())[:60]}"

    def solve(target: tuple[np.ndarray, np.ndarray], seed: np.ndarray) -> list[np.ndarray]:
        q = solver.ik(*target, seed_jnt_values=seed)
        return [] if q is None else [np.asarray(q)]

    return "TRAC-IK (5 ms, Speed)", _arrays, solve


def ssik_solver(urdf: Path, base: str, tip: str) -> tuple[str, Prepare, Solve] | str:
    """The every-branch solve of ssik from the URDF; or why it is not measured."""
    try:
        import ssik
    except ImportError as err:
        return f"not installed ({err})"
    try:
        arm = ssik.Manipulator.from_urdf(str(urdf), base=base, ee=tip)
        name = f"ssik {arm.solver_name}"
    except Exception as err:  # noqa: BLE001
        return f"refuses: {' '.join(str(err).split())[:60]}"

    def solve(target: np.ndarray, seed: np.ndarray) -> list[np.ndarray]:
        return [np.asarray(s.q) for s in arm.solve(target)]

    return name, lambda target: np.array(target.homogeneous), solve


def _same_arm(
    urdf: Path, base: str, tip: str, fk: Callable[[np.ndarray], np.ndarray]
) -> tuple[np.ndarray, np.ndarray] | str:
    """``(A^-1, B^-1)`` with ``T_urdf(q) = A fk(q) B`` over sampled joint vectors, or why not.

    A peer that reads the arm with frames of its own is handed targets in its frames (converted
    outside the timing); a chain that no fixed base and tool frame relate (other lengths, other
    joint zeros) is not the same arm.
    """
    from kin.audit.se3_fit import fit_base_tool_many

    chain = read_chain(urdf, base, tip)
    judge = Judge(urdf, chain.base, chain.tip, tuple(j.name for j in chain.joints))
    rng = np.random.default_rng(1)
    lower = np.array([max(j.lower, -3.0) for j in chain.joints])
    upper = np.array([min(j.upper, 3.0) for j in chain.joints])
    q = rng.uniform(lower, upper, size=(32, len(chain.joints)))
    ours_poses = np.array([judge.pose(v).homogeneous for v in q])
    try:
        theirs = np.array([fk(v) for v in q])
    except Exception as err:  # noqa: BLE001 - its own FK refuses the chain
        return f"refuses: {' '.join(str(err).split())[:60]}"
    fit = next(iter(fit_base_tool_many(theirs[None], ours_poses)))
    if not fit.position_residual_m <= 1e-6:
        return (
            f"its chain is not {chain.base} -> {chain.tip} "
            f"(FK differs by {fit.position_residual_m:.1e} m)"
        )
    return np.linalg.inv(fit.T_ref_base), np.linalg.inv(fit.T_tool_ref)


def eaik_solver(urdf: Path, base: str, tip: str) -> tuple[str, Prepare, Solve] | str:
    """EAIK's every-branch solve from the URDF (targets in its frames); or why not."""
    try:
        from eaik.IK_URDF import UrdfRobot
    except ImportError as err:
        return f"not installed ({err})"
    try:
        robot = UrdfRobot(str(urdf))
        family = robot.getKinematicFamily()
    except Exception as err:  # noqa: BLE001
        return f"refuses: {' '.join(str(err).split())[:60]}"
    if not robot.hasKnownDecomposition():
        return f"refuses: {family}"
    # EAIK reads the whole URDF with frames of its own: relate them to base -> tip once.
    frames = _same_arm(urdf, base, tip, robot.fwdKin)
    if isinstance(frames, str):
        return frames if frames.startswith("refuses") else f"refuses: {frames}"
    a_inv, b_inv = frames

    def prepare(target: pin.SE3) -> np.ndarray:
        return a_inv @ target.homogeneous @ b_inv

    def solve(target: np.ndarray, seed: np.ndarray) -> list[np.ndarray]:
        answer = robot.IK(target)
        return [q for q, least in zip(answer.Q, answer.is_LS) if not least]

    return f"EAIK {family}", prepare, solve


def ssik_prebuilt(arm: str, urdf: Path, base: str, tip: str) -> tuple[str, Prepare, Solve] | str:
    """The prebuilt ssik module of the arm, when its chain is the URDF's; or why not measured.

    ``ssik.prebuilt.<maker>.<arm>_ik.solve(T)``: the peer's fastest documented path (its
    elimination baked per arm, native backend); its FK is compared with the URDF's first
    (:func:`_same_arm`).
    """
    names = SSIK_PREBUILT.get(arm)
    if not names:
        return "ssik ships no prebuilt module of this arm"
    reasons = []
    for name in names:
        try:
            module = importlib.import_module(f"ssik.prebuilt.{name}")
        except ImportError as err:
            reasons.append(f"{name}: not installed ({err})")
            continue
        frames = _same_arm(urdf, base, tip, module.fk)
        if isinstance(frames, str):
            reasons.append(f"{name}: {frames}")
            continue
        a_inv, b_inv = frames

        def prepare(target: pin.SE3, a_inv=a_inv, b_inv=b_inv) -> np.ndarray:  # noqa: ANN001
            return a_inv @ target.homogeneous @ b_inv

        def solve(target: np.ndarray, seed: np.ndarray, module=module) -> list[np.ndarray]:  # noqa: ANN001
            return [np.asarray(s.q) for s in module.solve(target)]

        return f"ssik prebuilt {name}", prepare, solve
    return "skipped: " + "; ".join(reasons)


def measure(
    solvers: dict[str, tuple[Prepare, Solve]],
    targets,  # noqa: ANN001
    seeds,  # noqa: ANN001
    judge: Judge,
    lower,  # noqa: ANN001
    upper,  # noqa: ANN001
    passes: int,
) -> dict[str, tuple[float, float, float, int] | str]:
    """Per solver: (success [%], median single-call time [us], valid answers per pose, passes).

    The solvers take turns target by target, ``passes`` times over the targets: each target is
    solved by every solver, one call each, in an order rotated from target to target, so that
    a machine that speeds up or slows down during the run weighs on every solver alike. The
    median is over all single calls; success and answers (valid joint vectors distinct modulo
    2 pi: ssik returns every ``2 pi`` copy inside the limits) are judged on the first pass. A solver
    whose first pass took over :data:`SLOW_PASS` seconds runs no further pass; one that raises
    is reported by its error (a string instead of the figures). Each solver's targets are
    made in its own form first (its ``Prepare``), outside the timing.
    """
    times: dict[str, list[float]] = {key: [] for key in solvers}
    hits = dict.fromkeys(solvers, 0)
    counts: dict[str, list[int]] = {key: [] for key in solvers}
    done = dict.fromkeys(solvers, 0)
    first_pass = dict.fromkeys(solvers, 0.0)  # [s]
    failed: dict[str, str] = {}
    clock = time.perf_counter
    keys = list(solvers)
    inputs: dict[str, list[Any]] = {}
    for key in keys:
        try:
            inputs[key] = [solvers[key][0](target) for target in targets]
        except Exception as err:  # noqa: BLE001 - a peer failing on a pose is a row
            failed[key] = f"failed: {' '.join(str(err).split())[:50]}"
    for rep in range(passes):
        for i, (target, seed) in enumerate(zip(targets, seeds, strict=True)):
            turn = (i + rep) % len(keys)
            for key in keys[turn:] + keys[:turn]:
                if key in failed or (rep > 0 and first_pass[key] > SLOW_PASS):
                    continue
                try:
                    start = clock()
                    answers = solvers[key][1](inputs[key][i], seed)
                    spent = clock() - start
                except Exception as err:  # noqa: BLE001 - a peer failing on a pose is a row
                    failed[key] = f"failed: {' '.join(str(err).split())[:50]}"
                    continue
                times[key].append(spent)
                if rep == 0:
                    first_pass[key] += spent
                    valid = [q for q in answers if judge.on_target(q, target, lower, upper)]
                    hits[key] += bool(valid)
                    counts[key].append(distinct_mod_2pi(np.array(valid)) if valid else 0)
        for key in keys:
            done[key] += key not in failed and (rep == 0 or first_pass[key] <= SLOW_PASS)
    return {
        key: failed[key]
        if key in failed
        else (
            100.0 * hits[key] / len(targets),
            statistics.median(times[key]) * 1e6,
            float(np.mean(counts[key])),
            done[key],
        )
        for key in solvers
    }


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_ik_urdf.py", description=__doc__)
    parser.add_argument("--arms", nargs="+", choices=tuple(ARMS), default=list(ARMS))
    parser.add_argument("--poses", type=positive_int, default=200, help="poses per arm (200)")
    parser.add_argument(
        "--passes",
        type=positive_int,
        default=4,
        help="timing passes over the poses, the solvers in turn (4)",
    )
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print one row per arm and solver."""
    args = get_argument_parser().parse_args(argv)
    print(
        f"{'arm':<12} {'solver':<40} {'success':>8} {'median':>10} {'answers':>8} {'ours x':>7}"
        "   (answers: valid branches per pose, judged on the original URDF; ours x: our median"
        " over the row's)"
    )
    for arm in args.arms:
        relative, base, tip = ARMS[arm]
        urdf = erd(relative)
        chain = read_chain(urdf, base, tip)
        joints = tuple(joint.name for joint in chain.joints)
        judge = Judge(urdf, chain.base, chain.tip, joints)
        lower = np.array([j.lower for j in chain.joints])
        upper = np.array([j.upper for j in chain.joints])
        rng = np.random.default_rng(7)
        qs = rng.uniform(
            np.maximum(lower, -math.pi), np.minimum(upper, math.pi), size=(args.poses, len(joints))
        )
        targets = [judge.pose(q) for q in qs]
        seeds = [np.clip(np.zeros(len(joints)), lower, upper)] * len(targets)  # q = 0, in limits
        name, prepare, solve = ours(urdf, base, tip)
        rows: list[tuple[str, tuple[str, Prepare, Solve] | str]] = [
            ("ours", (f"ours: {name}", prepare, solve))
        ]
        rows += [("trac", tracik(urdf, chain.base, chain.tip))]
        rows += [("ssik", ssik_solver(urdf, chain.base, chain.tip))]
        rows += [("prebuilt", ssik_prebuilt(arm, urdf, chain.base, chain.tip))]
        rows += [("eaik", eaik_solver(urdf, chain.base, chain.tip))]
        solvers: dict[str, tuple[Prepare, Solve]] = {}
        labels: dict[str, str] = {}
        for key, entry in rows:
            if isinstance(entry, str):
                print(f"{arm:<12} {key + ': ' + entry:<40}")
                continue
            labels[key], *pair = entry
            solvers[key] = (pair[0], pair[1])
        figures = measure(solvers, targets, seeds, judge, lower, upper, args.passes)
        mine = figures.get("ours")
        for key, figure in figures.items():
            if isinstance(figure, str):
                print(f"{arm:<12} {labels[key]:<40} {figure}")
                continue
            success, median, answers, passes = figure
            ratio = f"{mine[1] / median:>6.2f}x" if isinstance(mine, tuple) else ""
            note = "" if passes == args.passes else f"  ({passes} pass: slow)"
            print(
                f"{arm:<12} {labels[key]:<40} {success:>7.1f}% {median:>8.1f}us {answers:>8.2f} "
                f"{ratio:>7}" + note
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
