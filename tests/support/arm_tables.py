"""Tables of arms for the closed-form tests: a DHTable from parameter lists, random base/tool poses."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pinocchio as pin

import kin
from dh2urdf import DHRow, DHTable, get_robot, load_table


def make_table(
    a, alpha, d, theta, convention: str = "standard", base=None, tool=None, name: str = "arm"
) -> DHTable:
    """A revolute DHTable (limits +-2 pi) from parameter lists [m], [rad], one row per value."""
    rows = tuple(
        DHRow(
            i + 1,
            f"j{i + 1}",
            "revolute",
            a[i],
            alpha[i],
            d[i],
            theta[i],
            -2 * math.pi,
            2 * math.pi,
            1.0,
            1.0,
        )  # fmt: skip
        for i in range(len(a))
    )
    eye = np.eye(4)
    return DHTable(name, "", "", convention, rows,
                   eye if base is None else base, eye if tool is None else tool)  # fmt: skip


def tool_poses(robot: kin.RobotModel, n: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Tool poses ``(position [m], R_world_tool)`` of ``n`` seeded random joint vectors inside the
    limits, by Pinocchio's forward kinematics."""
    rng = np.random.default_rng(seed)
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.tool_frame)
    out = []
    for q in rng.uniform(robot.lower, robot.upper, size=(n, robot.nq)):
        pin.forwardKinematics(model, data, q)
        pose = pin.updateFramePlacement(model, data, frame)
        out.append((pose.translation.copy(), pose.rotation.copy()))
    return out


def random_pose(rng: np.random.Generator) -> np.ndarray:
    """A random rigid transform (4x4): rotation from a normal rotation vector, offset +-0.3 m."""
    return pin.SE3(pin.exp3(rng.normal(size=3)), rng.uniform(-0.3, 0.3, 3)).homogeneous


def random_family_table(
    family: str,
    convention: str,
    seed: int,
    offset_reach: float,
    twists_first: bool,
    shape: Callable[[str, np.random.Generator, np.ndarray, np.ndarray, np.ndarray, int], None],
) -> DHTable:
    """A random 6R arm of a closed-form family: lengths ``a`` in +-0.5 m, offsets ``d`` in
    +-``offset_reach`` [m], twists and joint offsets in +-pi (twists drawn first or second, as
    the family's tests fixed), then ``shape(family, rng, a, alpha, d, j)`` sets the family's
    structural values in place (``j``: 1 in the modified convention, whose row i + 1 holds joint
    i's a and alpha), then a random base and tool. The generator is seeded with ``seed`` (+50
    in the modified convention); the table is named ``{family}_{convention}_{seed}``."""
    rng = np.random.default_rng(seed + (0 if convention == "standard" else 50))
    a = rng.uniform(-0.5, 0.5, 6)
    d = rng.uniform(-offset_reach, offset_reach, 6)
    first, second = rng.uniform(-math.pi, math.pi, (2, 6))
    alpha, theta = (first, second) if twists_first else (second, first)
    shape(family, rng, a, alpha, d, 0 if convention == "standard" else 1)
    return make_table(a, alpha, d, theta, convention, random_pose(rng), random_pose(rng),
                      f"{family}_{convention}_{seed}")  # fmt: skip


def ur5_or_random(name: str, random: Callable[[str], DHTable]) -> DHTable:
    """The shipped UR5 table (``"ur5"``), the same rows on a random base and tool
    (``"ur5_moved"``, seed 5), else ``random(name)``."""
    table = load_table(get_robot("ur5").table_path)
    if name == "ur5":
        return table
    if name == "ur5_moved":
        rng = np.random.default_rng(5)
        return DHTable(name, "", "", "standard", table.rows, random_pose(rng), random_pose(rng))
    return random(name)


def wrapped_gap(branches: np.ndarray, q) -> np.ndarray:
    """Largest joint difference modulo 2 pi of each branch from ``q`` [rad]."""
    return np.abs(np.remainder(branches - np.asarray(q) + math.pi, 2 * math.pi) - math.pi).max(
        axis=1
    )


#: Tolerance of a round trip [m], [rad], and of a recovered joint vector away from singularities.
TOL = 1e-9
#: Joint error allowed near a singularity: ROUNDING / sigma_min(J) [rad].
ROUNDING = 1e-12


class Reference:
    """Pinocchio FK of a table's URDF, tool frame.

    Args:
        table: The arm.
        solved: The joints the closed form solves (the others given): the columns of the
            Jacobian whose smallest singular value bounds the joint error; None: all.
    """

    def __init__(self, table: DHTable, solved: slice | None = None):
        self.robot = kin.robot_from_table(table)
        self.model = self.robot.model
        self.data = self.model.createData()
        self.frame = self.model.getFrameId(self.robot.tool_frame)
        self.solved = slice(None) if solved is None else solved

    def fk(self, q) -> pin.SE3:
        """``T_world_tool`` at ``q`` [rad]."""
        pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        return pin.updateFramePlacement(self.model, self.data, self.frame).copy()

    def errors(self, q, target: pin.SE3) -> tuple[float, float]:
        """Position [m] and rotation [rad] errors of the tool at ``q`` from ``target``."""
        pose = self.fk(q)
        return (
            float(np.linalg.norm(pose.translation - target.translation)),
            float(np.linalg.norm(pin.log3(pose.rotation.T @ target.rotation))),
        )

    def joint_tolerance(self, q) -> float:
        """Largest joint error [rad] a correct solve may show at ``q``: near a singularity the
        rounding of the target is amplified by 1 / sigma_min of the solved joints' Jacobian."""
        jac = pin.computeFrameJacobian(self.model, self.data, np.asarray(q), self.frame, pin.LOCAL)
        sigma = float(np.linalg.svd(jac[:, self.solved], compute_uv=False).min())
        return max(TOL, ROUNDING / sigma) if sigma > 0.0 else math.inf

    def check_branches(self, branches: np.ndarray, q, target: pin.SE3, label: str) -> float:
        """Assert every branch reaches ``target`` to :data:`TOL` and ``q`` is among them.

        Returns:
            The worst position [m] or rotation [rad] error of the branches.
        """
        worst = 0.0
        for branch in branches:
            position_error, rotation_error = self.errors(branch, target)
            worst = max(worst, position_error, rotation_error)
            assert position_error < TOL and rotation_error < TOL, f"{label} {q=} {branch=}"
        gap = wrapped_gap(branches, q).min()
        assert gap < self.joint_tolerance(q), f"{label} {q=}: {gap=}"
        return worst


def assert_layout_matches(ik, twin) -> None:
    """A compiled twin's LAYOUT is contiguous, covers PARAM_COUNT values, and names exactly the
    Python closed form's ``c_fields`` with their sizes; ``c_params`` puts each at the C offset."""
    fields = ik.c_fields()
    layout = twin.LAYOUT
    assert [name for name, _, _ in layout] == list(fields), "field names or order differ"
    offset = 0
    for name, start, size in layout:
        assert start == offset, f"{name=} {start=} {offset=}"
        assert size == len(fields[name]), f"{name=} {size=}"
        offset += size
    assert offset == twin.PARAM_COUNT == ik.c_params.size
    for name, start, size in layout:
        assert ik.c_params[start : start + size].tolist() == list(fields[name]), name


def assert_round_trips(structure, ref: Reference, samples: int, seed: int, label: str) -> None:
    """``samples`` random q in +-pi: every branch of ``structure.solve(FK(q))`` (8 rows, angles in
    (-pi, pi]) reaches FK(q) to :data:`TOL` by Pinocchio, q is among them, and on average at least
    2 branches exist per target."""
    counted = 0
    for q in np.random.default_rng(seed).uniform(-math.pi, math.pi, (samples, 6)):
        target = ref.fk(q)
        found = structure.solve(target.translation, target.rotation)
        assert found.shape == (8, 6)
        exist = found[~np.isnan(found[:, 0])]
        assert not np.isnan(exist).any()
        assert np.all((exist > -math.pi) & (exist <= math.pi)), f"{label} {exist=}"
        assert ref.check_branches(exist, q, target, label) < TOL
        counted += len(exist)
    assert counted >= 2 * samples, f"{label}: {counted=}"
