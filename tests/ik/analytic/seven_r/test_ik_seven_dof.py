"""Closed-form IK of the seven-joint arm (ik.structure.seven_dof, ik.seven_dof, kin/_native/ik/analytic/seven_r/_closed7.c).

Pinocchio's forward kinematics of the robot's URDF is the reference for the Python module; the
Python module is the reference for its compiled twin. Three arms of the structure are solved:
humanoid7 itself (world = DH frame 0, tool = DH frame 7: the fast path without NumPy), the same
arm with a rotated and translated base and tool (the NumPy path), and a "general" arm with other
twists, offsets and lengths everywhere the structure allows them, with that base and tool.

A joint vector found again by the round trip is compared to the original with the tolerance
``max(1e-9, ROUNDING / sigma)``: ``sigma`` is the smallest singular value of the Jacobian of the
joints the closed form solves (2-7 for a pose, 2-4 for a position), computed by Pinocchio. Near a
singularity (the stretched elbow of humanoid7 puts the wrist on the shoulder-roll axis too) the
joint values are ill-conditioned whatever the method; the tool pose itself is always required
within 1e-9 m / 1e-9 rad.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import pinocchio as pin
import pytest
from support.solver_caps import NO_CAP

import kin
from kin.ik.analytic.seven_r.seven_dof import COMPILED, SevenDofIK
from kin.ik.analytic.structure import seven_dof
from kin.ik.exceptions import StructureError
from kin.ik.numeric.numeric_target import (
    POSITION_TOLERANCE,
    ROTATION_TOLERANCE,
    NumericTarget,
    measure,
)
from kin.ik.numeric.solver import NumericIK, numeric_ik_for
from kin.robot_model import robot_from_table

ROBOT = "humanoid7"
SOLVER = "seven-joint (shoulder point, spherical wrist)"
#: Tool pose error of every branch [m] and [rad]; joint error of a well-conditioned round trip [rad].
TOL = 1e-9
#: Joint error allowed near a singularity: ROUNDING / sigma [rad] (sigma: see the module docstring;
#: the worst seen over 8000 samples of humanoid7 and the general arm is 2.3e-15 / sigma).
ROUNDING = 1e-12
SAMPLES = 1000
STEP = 0.05  # joint-1 scan step [rad]
TIMEOUT = NO_CAP  # [s] of a NumericIK solve: no load decides it; the first solution returns at once

BASE = pin.SE3(pin.exp3(np.array([0.3, -0.5, 0.7])), np.array([0.1, -0.2, 0.3])).homogeneous
TOOL = pin.SE3(pin.exp3(np.array([-0.4, 0.2, 0.9])), np.array([0.02, -0.03, 0.05])).homogeneous
_DEG = math.radians
#: Row changes (0-based rows) of the general arm: only a2, a5, a6, d6 stay 0.
GENERAL_ROWS = {
    0: dict(a=0.05, d=0.12, alpha=_DEG(-80), theta=0.2),
    1: dict(d=0.03, alpha=_DEG(-70), theta=_DEG(-90) + 0.1),
    2: dict(a=0.04, d=0.25, alpha=_DEG(100), theta=_DEG(90) - 0.3),
    3: dict(a=0.03, d=-0.02, alpha=_DEG(-75), theta=0.4),
    4: dict(d=0.22, alpha=_DEG(60), theta=-0.2),
    5: dict(alpha=_DEG(-110), theta=_DEG(90) + 0.3),
    6: dict(a=0.1, d=0.04, alpha=_DEG(35), theta=0.5),
}
ARMS = ("humanoid7", "moved", "general")
MODES = ("pose", "position")


# ---------------------------------------------------------------------------------------------
# Helpers


def with_rows(table, name: str, **changes_by_row):
    """A copy of ``table`` named ``name`` with ``row<i>={field: value}`` changes (1-based rows)."""
    rows = list(table.rows)
    for key, changes in changes_by_row.items():
        i = int(key.removeprefix("row")) - 1
        rows[i] = dataclasses.replace(rows[i], **changes)
    return dataclasses.replace(table, name=name, rows=tuple(rows), path=None)


@functools.cache
def arm_robot(name: str) -> kin.RobotModel:
    """humanoid7, or one of its variants built through its URDF."""
    robot = kin.load_robot(ROBOT)
    if name == "humanoid7":
        return robot
    table = robot.table
    if name == "general":
        table = with_rows(
            table, "humanoid7_general", **{f"row{i + 1}": GENERAL_ROWS[i] for i in range(7)}
        )
    table = dataclasses.replace(
        table, name=f"humanoid7_{name}", T_world_base=BASE, T_last_tool=TOOL, path=None
    )
    return robot_from_table(table)


@dataclasses.dataclass
class Arm:
    """A robot, its closed form (inside the robot's limits) and Pinocchio's judgement."""

    name: str
    robot: kin.RobotModel
    ik: SevenDofIK

    def __post_init__(self) -> None:
        self.data = self.robot.model.createData()
        self.frame_id = self.robot.model.getFrameId(self.robot.tool_frame)
        self.lower, self.upper = self.robot.lower, self.robot.upper

    def widened(self, limit: float = math.pi) -> SevenDofIK:
        """The closed form of the same arm with limits ``+-limit`` on every joint."""
        return SevenDofIK(self.ik.structure, [-limit] * 7, [limit] * 7)

    def fk(self, q) -> pin.SE3:
        model = self.robot.model
        pin.forwardKinematics(model, self.data, np.asarray(q, dtype=float))
        return pin.updateFramePlacement(model, self.data, self.frame_id).copy()

    def errors(self, q, target: pin.SE3) -> tuple[float, float]:
        """Position [m] and rotation [rad] errors of the tool at ``q`` from ``target``."""
        pose = self.fk(q)
        position = float(np.linalg.norm(pose.translation - target.translation))
        rotation = float(np.linalg.norm(pin.log3(pose.rotation.T @ target.rotation)))
        return position, rotation

    def joint_tolerance(self, q, mode: str) -> float:
        """``max(TOL, ROUNDING / sigma)`` for the joints the closed form solves at ``q``."""
        jacobian = pin.computeFrameJacobian(
            self.robot.model, self.data, np.asarray(q, dtype=float), self.frame_id, pin.LOCAL
        )
        block = jacobian[:, 1:] if mode == "pose" else jacobian[:3, 1:4]
        sigma = float(np.linalg.svd(block, compute_uv=False).min())
        return max(TOL, ROUNDING / sigma) if sigma > 0.0 else math.inf

    def random_q(self, rng, n: int) -> np.ndarray:
        return rng.uniform(self.lower, self.upper, size=(n, 7))


@functools.cache
def make_arm(name: str) -> Arm:
    robot = arm_robot(name)
    return Arm(name, robot, SevenDofIK(seven_dof(robot.table), robot.lower, robot.upper))


@pytest.fixture(scope="module", params=ARMS)
def arm(request) -> Arm:
    return make_arm(request.param)


def inside(q, lower, upper) -> bool:
    q = np.asarray(q)
    return bool(np.all(q >= lower) and np.all(q <= upper))


def branches(ik: SevenDofIK, mode: str, pose: pin.SE3, q1: float, start) -> list[list[float]]:
    """``pose`` or ``position`` of ``ik`` at joint 1 = ``q1`` (joints 5-7 of ``start``)."""
    if mode == "pose":
        return ik.pose(q1, ik.pose_frame(pose.translation, pose.rotation))
    return ik.position(q1, list(start[4:]), ik.frame0(pose.translation))


def prepared(ik: SevenDofIK, mode: str, pose: pin.SE3):
    return ik.prepare(pose.translation, pose.rotation if mode == "pose" else None)


def check_branches(arm: Arm, found, target: pin.SE3, mode: str, lower, upper) -> None:
    """Every branch is on target per Pinocchio and inside ``lower .. upper``."""
    for q in found:
        position_error, rotation_error = arm.errors(q, target)
        assert position_error < TOL, f"{arm.name} {mode} {q=}: {position_error=}"
        if mode == "pose":
            assert rotation_error < TOL, f"{arm.name} {mode} {q=}: {rotation_error=}"
        assert inside(q, lower, upper), f"{arm.name} {mode} {q=}"


def nearest_gap(found, q) -> float:
    """Largest joint difference [rad] of the branch nearest ``q`` (inf when there is none)."""
    return min((float(np.abs(np.subtract(b, q)).max()) for b in found), default=math.inf)


def check_contains(arm: Arm, found, q, mode: str) -> bool:
    """``q`` is among the branches (1e-9 rad, or its conditioning's tolerance); whether loosely."""
    gap = nearest_gap(found, q)
    if gap < TOL:
        return False
    assert gap < arm.joint_tolerance(q, mode), f"{arm.name} {mode} {q=}: {gap=}"
    return True


def scan_order(q1: float, step: float, low: float, high: float):
    """Joint-1 values in the documented scan order: q1, q1 + s, q1 - s, q1 + 2 s, ... in the limits."""
    yield q1
    if not step > 0.0:
        return
    j = 1
    while q1 + j * step <= high or q1 - j * step >= low:
        for value in (q1 + j * step, q1 - j * step):
            if low <= value <= high:
                yield value
        j += 1


# ---------------------------------------------------------------------------------------------
# 1. Structure recognition


def test_humanoid7_fits_and_its_parameters_are_read_from_the_table():
    table = kin.load_robot(ROBOT).table
    structure = seven_dof(table)
    assert structure.a == tuple(row.a for row in table.rows)
    assert structure.alpha == tuple(row.alpha for row in table.rows)
    assert structure.d == tuple(row.d for row in table.rows)
    assert structure.offsets == tuple(row.theta for row in table.rows)
    assert np.array_equal(structure.T_world_base, np.eye(4))
    assert np.array_equal(structure.T_last_tool, np.eye(4))
    # Other twists, offsets, a1, d1, a3, d3, a4, d4, d5, a7, d7, base and tool fit too.
    general = arm_robot("general").table
    structure = seven_dof(general)
    assert structure.alpha == tuple(row.alpha for row in general.rows)
    assert np.array_equal(structure.T_world_base, BASE)
    assert np.array_equal(structure.T_last_tool, TOOL)


NOT_FITTING = {
    "a2": (
        lambda t: with_rows(t, "bad", row2=dict(a=0.05)),
        "row 2 ('shoulder_pitch'): a = 0.05 m, expected 0 (the axes of joints 2 and 3 must meet)",
    ),
    "alpha2 = 0": (
        lambda t: with_rows(t, "bad", row2=dict(alpha=0.0)),
        "row 2 ('shoulder_pitch'): alpha = 0 deg, expected an angle other than 0 or 180 deg",
    ),
    "alpha2 = 180": (
        lambda t: with_rows(t, "bad", row2=dict(alpha=math.pi)),
        "row 2 ('shoulder_pitch'): alpha = 180 deg, expected an angle other than 0 or 180 deg",
    ),
    "a5": (
        lambda t: with_rows(t, "bad", row5=dict(a=0.01)),
        "row 5 ('wrist_roll'): a = 0.01 m, expected 0 (the wrist axes 5, 6 and 7 must meet)",
    ),
    "alpha5 = 0": (
        lambda t: with_rows(t, "bad", row5=dict(alpha=0.0)),
        "row 5 ('wrist_roll'): alpha = 0 deg, expected an angle other than 0 or 180 deg",
    ),
    "a6": (
        lambda t: with_rows(t, "bad", row6=dict(a=0.02)),
        "row 6 ('wrist_pitch'): a = 0.02 m, expected 0 (the wrist axes 5, 6 and 7 must meet)",
    ),
    "d6": (
        lambda t: with_rows(t, "bad", row6=dict(d=-0.03)),
        "row 6 ('wrist_pitch'): d = -0.03 m, expected 0 (the wrist axes 5, 6 and 7 must meet)",
    ),
    "six joints": (
        lambda t: dataclasses.replace(t, name="bad", rows=t.rows[:6]),
        "6 joints, expected 7",
    ),
    "modified convention": (
        lambda t: dataclasses.replace(t, name="bad", convention="modified"),
        "convention is 'modified', expected 'standard'",
    ),
    "prismatic joint": (
        lambda t: with_rows(t, "bad", row4=dict(joint_type="prismatic")),
        "row 4 ('elbow') is prismatic, expected revolute",
    ),
}


@pytest.mark.parametrize("case", NOT_FITTING)
def test_table_that_does_not_fit_names_the_row_and_parameter(case):
    change, expected = NOT_FITTING[case]
    table = change(kin.load_robot(ROBOT).table)
    with pytest.raises(StructureError) as caught:
        seven_dof(table)
    error = caught.value
    assert error.robot == "bad" and error.solver == SOLVER
    assert expected in error.mismatch, error.mismatch
    assert str(error).startswith(f"'bad' does not fit the {SOLVER} solver: ")


def test_panda_does_not_fit_its_table_is_modified_dh():
    """Panda has 7 revolute joints but a modified (Craig) DH table: rejected on the convention.

    (Its wrist is not spherical either: a = 0.088 m between axes 6 and 7.) Its free-joint closed
    form is the spherical-shoulder one (joint 7 free), not this structure's.
    """
    panda = kin.load_robot("panda")
    assert panda.table.dof == 7
    with pytest.raises(StructureError, match="convention is 'modified', expected 'standard'"):
        seven_dof(panda.table)
    closed_form = NumericIK(panda).closed_form
    assert closed_form is not None and not isinstance(closed_form, SevenDofIK)


def test_numeric_ik_has_a_closed_form_only_when_asked_and_the_arm_fits():
    robot = kin.load_robot(ROBOT)
    assert isinstance(NumericIK(robot).closed_form, SevenDofIK)
    assert NumericIK(robot, closed_form=False).closed_form is None
    assert NumericIK(kin.load_robot("ur5")).closed_form is None  # 6 joints


# ---------------------------------------------------------------------------------------------
# 2 and 4. Round trips against Pinocchio (plain and transformed base / tool)


def test_both_target_paths_are_exercised():
    """humanoid7 takes the path without transforms, the variants the NumPy one."""
    assert make_arm("humanoid7").ik._plain
    assert not make_arm("moved").ik._plain and not make_arm("general").ik._plain
    # The variants' base and tool really move the tool (their URDF carries the transforms).
    q = np.full(7, 0.3)
    assert make_arm("moved").fk(q).translation != pytest.approx(
        make_arm("humanoid7").fk(q).translation
    )


def test_round_trip_pose_and_position_contains_q_and_every_branch_is_on_target(arm):
    """FK(q) -> ``pose`` / ``position`` at q's joint 1 (and joints 5-7): q among the branches."""
    rng = np.random.default_rng(11)
    ik = arm.ik
    loose = 0
    for q in arm.random_q(rng, SAMPLES):
        target = arm.fk(q)
        found = ik.pose(q[0], ik.pose_frame(target.translation, target.rotation))
        assert 1 <= len(found) <= 8
        check_branches(arm, found, target, "pose", arm.lower, arm.upper)
        loose += check_contains(arm, found, q, "pose")
        found = ik.position(q[0], q[4:], ik.frame0(target.translation))
        assert 1 <= len(found) <= 4
        check_branches(arm, found, target, "position", arm.lower, arm.upper)
        assert all(b[0] == q[0] and b[4:] == q[4:].tolist() for b in found)
        loose += check_contains(arm, found, q, "position")
    assert loose < 0.01 * SAMPLES  # all but a few samples are found again within 1e-9 rad


@pytest.mark.parametrize(
    "compiled",
    [
        False,
        pytest.param(True, marks=pytest.mark.skipif(not COMPILED, reason="ik/_closed7 not built")),
    ],
)
@pytest.mark.parametrize("mode", MODES)
def test_round_trip_through_first(arm, mode, compiled):
    """``first(prepare(FK(q)), [q])`` returns 0 and q itself (the branch nearest q)."""
    rng = np.random.default_rng(12)
    out = np.empty(7)
    for q in arm.random_q(rng, 200):
        target = arm.fk(q)
        out[:] = np.nan
        index = arm.ik.first(prepared(arm.ik, mode, target), q[None], out, compiled=compiled)
        assert index == 0, f"{arm.name} {mode} {q=}"
        check_branches(arm, [out], target, mode, arm.lower, arm.upper)
        assert out[0] == q[0]
        if mode == "position":
            assert np.array_equal(out[4:], q[4:])
        check_contains(arm, [out], q, mode)


# ---------------------------------------------------------------------------------------------
# 3. Branch counts with wide limits


def test_wide_limits_give_up_to_eight_pose_and_four_position_branches(arm):
    """Limits +-pi: counts reach 8 (pose) and 4 (position) and never exceed them; all on target."""
    rng = np.random.default_rng(13)
    wide = arm.widened()
    lower, upper = np.full(7, -math.pi), np.full(7, math.pi)
    pose_counts, position_counts = [], []
    for q in rng.uniform(-math.pi, math.pi, size=(200, 7)):
        target = arm.fk(q)
        found = wide.pose(q[0], wide.pose_frame(target.translation, target.rotation))
        pose_counts.append(len(found))
        check_branches(arm, found, target, "pose", lower, upper)
        check_contains(arm, found, q, "pose")
        found = wide.position(q[0], q[4:], wide.frame0(target.translation))
        position_counts.append(len(found))
        check_branches(arm, found, target, "position", lower, upper)
        check_contains(arm, found, q, "position")
    assert max(pose_counts) == 8 and min(pose_counts) >= 1
    assert max(position_counts) == 4 and min(position_counts) >= 1
    # The robot's own limits (+-90 deg on every joint) keep a subset of them.
    q = arm.random_q(rng, 1)[0]
    target = arm.fk(q)
    every = branches(wide, "pose", target, q[0], q)
    for branch in branches(arm.ik, "pose", target, q[0], q):
        assert nearest_gap(every, branch) == 0.0


# ---------------------------------------------------------------------------------------------
# 5. The compiled twin equals the Python module


def random_targets(arm: Arm, rng, n: int) -> list[tuple[pin.SE3, np.ndarray]]:
    """Targets ``(T_world_tool, q)``: FK of q inside the limits, a quarter of them moved away
    (some unreachable, some reachable only by other joint-1 values)."""
    targets = []
    for q in arm.random_q(rng, n):
        target = arm.fk(q)
        if rng.random() < 0.25:
            target = pin.SE3(
                target.rotation @ pin.exp3(rng.normal(0.0, 0.5, 3)),
                target.translation + rng.normal(0.0, 0.15, 3),
            )
        targets.append((target, q))
    return targets


def random_starts(arm: Arm, rng, q: np.ndarray) -> np.ndarray:
    """1 to 5 starts: near q, anywhere inside the limits, or outside them (clipped by ``first``)."""
    rows = []
    span = arm.upper - arm.lower
    for _ in range(rng.integers(1, 6)):
        kind = rng.integers(3)
        if kind == 0:
            rows.append(q + rng.normal(0.0, 0.05, 7))
        elif kind == 1:
            rows.append(rng.uniform(arm.lower, arm.upper))
        else:
            rows.append(rng.uniform(arm.lower - 0.5 * span, arm.upper + 0.5 * span))
    return np.array(rows)


@pytest.mark.skipif(not COMPILED, reason="ik/_closed7 not built")
@pytest.mark.parametrize("step", [0.0, STEP])
@pytest.mark.parametrize("mode", MODES)
def test_compiled_twin_equals_python(arm, mode, step):
    """Same index, same ``out`` (1e-12), ``out`` untouched on -1; Fortran-ordered starts too."""
    rng = np.random.default_rng(14)
    outcomes = []
    for target, q in random_targets(arm, rng, 60):
        values = prepared(arm.ik, mode, target)
        starts = random_starts(arm, rng, q)
        if rng.random() < 0.2:
            starts = np.asfortranarray(starts)
        out_c, out_py = np.full(7, np.nan), np.full(7, np.nan)
        index_c = arm.ik.first(values, starts, out_c, step, compiled=True)
        index_py = arm.ik.first(values, starts, out_py, step, compiled=False)
        context = f"{arm.name} {mode} {step=} {starts=}"
        assert index_c == index_py, context
        if index_py < 0:
            assert np.isnan(out_c).all() and np.isnan(out_py).all(), context
        else:
            assert np.abs(out_c - out_py).max() < 1e-12, context
        outcomes.append(index_py)
    # Both outcomes and later starts are exercised.
    assert outcomes.count(-1) >= 1 and sum(i >= 0 for i in outcomes) >= 25
    if step == 0.0:
        assert any(i > 0 for i in outcomes)


# ---------------------------------------------------------------------------------------------
# 6. Joint-1 scan semantics


@pytest.mark.parametrize("mode", MODES)
def test_scan_takes_the_first_joint_one_value_with_a_branch(arm, mode):
    """``first`` with a step: the start's clipped joint 1, then +-step, +-2 step, ... (up first);
    the first value with a branch is taken, on the grid exactly, with the branch nearest the
    start; earlier starts (and all starts on -1) have no branch anywhere on their grid. (The
    compiled twin when it is built: it equals the Python module, see above.)"""
    rng = np.random.default_rng(15)
    low, high = arm.lower[0], arm.upper[0]
    scanned = failed = 0
    for target, q in random_targets(arm, rng, 50):
        starts = random_starts(arm, rng, q)
        out = np.full(7, np.nan)
        index = arm.ik.first(prepared(arm.ik, mode, target), starts, out, STEP)
        rows = len(starts) if index < 0 else index + 1
        for r in range(rows):
            clipped = np.clip(starts[r], arm.lower, arm.upper)
            expected = None
            for q1 in scan_order(float(clipped[0]), STEP, low, high):
                found = branches(arm.ik, mode, target, q1, clipped)
                if found:
                    expected = q1, found
                    break
            context = f"{arm.name} {mode} {starts=} {r=} {index=}"
            if r < index or index < 0:
                assert expected is None, context
                continue
            assert expected is not None, context
            q1, found = expected
            assert out[0] == q1, context  # on the grid, the first value with a branch
            j = (q1 - clipped[0]) / STEP
            assert abs(j - round(j)) < 1e-6, context
            scanned += q1 != clipped[0]
            distances = [float(np.sum((np.array(b) - clipped) ** 2)) for b in found]
            nearest = found[int(np.argmin(distances))]
            assert np.abs(out - nearest).max() < 1e-12, context
            check_branches(arm, [out], target, mode, arm.lower, arm.upper)
        failed += index < 0
    assert scanned >= 5 and failed >= 1


@pytest.mark.parametrize("mode", MODES)
def test_scan_tries_up_before_down(mode):
    """A start in a gap between two ranges of joint-1 values with branches, at one step from
    both: the scan takes ``q1 + step``, not ``q1 - step`` (Python and compiled twin)."""
    arm = make_arm("humanoid7")
    rng = np.random.default_rng(17)
    grid = np.linspace(arm.lower[0], arm.upper[0], 201)
    out = np.empty(7)
    ties = 0
    for q in arm.random_q(rng, 60):
        target = arm.fk(q)
        values = prepared(arm.ik, mode, target)
        feasible = [bool(branches(arm.ik, mode, target, v, q)) for v in grid]
        for i in range(1, len(grid) - 1):
            if not (feasible[i - 1] and not feasible[i]) or True not in feasible[i:]:
                continue  # not the first value of a gap with branches on both sides
            below, above = grid[i - 1], grid[feasible.index(True, i)]
            step = 0.5 * (above - below)
            start = q.copy()
            start[0] = below + step
            up, down = start[0] + step, start[0] - step
            if branches(arm.ik, mode, target, start[0], q) or not (
                branches(arm.ik, mode, target, up, q) and branches(arm.ik, mode, target, down, q)
            ):
                continue
            ties += 1
            for compiled in {False, COMPILED}:
                out[:] = np.nan
                assert arm.ik.first(values, start[None], out, step, compiled=compiled) == 0
                assert out[0] == up, f"{mode} {compiled=} {start=} {step=} {out=}"
    assert ties >= 3


# ---------------------------------------------------------------------------------------------
# 7. NumericIK


@functools.cache
def numeric_targets(n: int = 30) -> tuple[tuple[pin.SE3, np.ndarray], ...]:
    """``(FK(q), q)`` of ``n`` random q inside the limits with the elbow bent by 0.1 rad or more.

    Near the stretched elbow the joint-1 values with a branch inside the limits can span less
    than NumericIK's scan step (0.01 rad; e.g. q4 = 0.0046: 0.006 rad) and the scan can step over
    them; NumericIK then (correctly) falls back to damped Newton.
    """
    arm = make_arm("humanoid7")
    rng = np.random.default_rng(16)
    targets = []
    while len(targets) < n:
        q = arm.random_q(rng, 1)[0]
        if abs(q[3]) >= 0.1:
            targets.append((arm.fk(q), q))
    return tuple(targets)


def verify(robot, result, target: NumericTarget) -> np.ndarray:
    """The result is a success Pinocchio confirms (ik.numeric_target.measure); its q."""
    assert result.success, result.message
    q = result.solutions[0].q
    verdict = measure(robot, robot.model.createData(), q, target)
    assert verdict.within_limits, f"{q=}"
    assert verdict.position_error < POSITION_TOLERANCE, result.message
    assert verdict.rotation_error < ROTATION_TOLERANCE, result.message
    return q


@pytest.mark.parametrize("position_only", [False, True])
def test_numeric_ik_solves_in_closed_form_first(position_only):
    robot = kin.load_robot(ROBOT)
    solver = numeric_ik_for(ROBOT)
    for pose, _ in numeric_targets():
        target = NumericTarget.from_se3(pose, position_only=position_only)
        result = solver.solve(target, timeout=TIMEOUT)
        verify(robot, result, target)
        assert result.message.startswith("closed form with the free joints of "), result.message


@pytest.mark.parametrize("position_only", [False, True])
def test_numeric_ik_without_closed_form_uses_damped_newton_or_mink(position_only):
    robot = kin.load_robot(ROBOT)
    solver = NumericIK(robot, closed_form=False)
    for pose, _ in numeric_targets():
        target = NumericTarget.from_se3(pose, position_only=position_only)
        result = solver.solve(target, timeout=TIMEOUT)
        verify(robot, result, target)
        assert not result.message.startswith("closed form"), result.message


@pytest.mark.parametrize("closed_form", [True, False])
@pytest.mark.parametrize("position_only", [False, True])
def test_numeric_ik_seed_at_a_solution_keeps_its_joint_one(position_only, closed_form):
    """A seed that solves the target is tried first and comes back with its joint 1 (continuity):
    the closed form keeps joint 1 (and joints 5-7 for a position) exactly, damped Newton stops at
    the seed itself."""
    robot = kin.load_robot(ROBOT)
    arm = make_arm("humanoid7")
    solver = numeric_ik_for(ROBOT) if closed_form else NumericIK(robot, closed_form=False)
    mode = "position" if position_only else "pose"
    for pose, q in numeric_targets():
        target = NumericTarget.from_se3(pose, position_only=position_only)
        result = solver.solve(target, seed=q, timeout=TIMEOUT)
        got = verify(robot, result, target)
        assert got[0] == q[0]
        if closed_form:
            assert result.message == "closed form with the free joints of the given seed"
            if position_only:
                assert np.array_equal(got[4:], q[4:])
            check_contains(arm, [got], q, mode)
        else:
            assert result.message.startswith("damped Newton from the given seed")
            assert np.array_equal(got, q)


# ---------------------------------------------------------------------------------------------
# 8. Bad inputs to the compiled function


def _c_args():
    ik = make_arm("humanoid7").ik
    return dict(
        params=ik.c_params.copy(),
        mode=0,
        target=np.zeros(12),
        starts=np.zeros((2, 7)),
        out=np.full(7, np.nan),
        step=0.0,
    )


@pytest.mark.skipif(not COMPILED, reason="ik/_closed7 not built")
@pytest.mark.parametrize(
    "changes, error, message",
    [
        (dict(params=np.zeros(67)), ValueError, "params: wrong size"),
        (dict(params=np.zeros(69)), ValueError, "params: wrong size"),
        (dict(params=np.zeros(0)), ValueError, "params: wrong size"),
        (dict(mode=2), ValueError, "mode must be 0"),
        (dict(mode=-1), ValueError, "mode must be 0"),
        (dict(target=np.zeros(3)), ValueError, "target: wrong size"),
        (dict(mode=1, target=np.zeros(12)), ValueError, "target: wrong size"),
        (dict(target=np.zeros(13)), ValueError, "target: wrong size"),
        (dict(starts=np.zeros(8)), ValueError, "starts: not k x 7 float64"),
        (dict(starts=np.zeros((1, 6))), ValueError, "starts: not k x 7 float64"),
        (dict(out=np.zeros(6)), ValueError, "out: not 7 float64"),
        (dict(out=np.zeros(14)), ValueError, "out: not 7 float64"),
        (dict(out=bytes(56)), BufferError, "not writable"),  # read-only buffer
        (dict(out=np.zeros(14)[::2]), ValueError, "contiguous"),  # not contiguous
        (dict(out=np.zeros(7, dtype=np.float32)), TypeError, "float64"),
        (dict(starts=np.zeros((2, 7), dtype=np.float32)), TypeError, "float64"),
        (dict(target=np.zeros(12, dtype=np.int64)), TypeError, "float64"),
        (dict(starts=np.zeros((14, 1))[::2]), ValueError, "contiguous"),
        (dict(params=[0.0] * 68), TypeError, "bytes-like"),
        (dict(step="0.1"), TypeError, "must be real number"),
    ],
)
def test_compiled_function_rejects_bad_inputs(changes, error, message):
    from kin.ik.analytic.seven_r import _closed7

    args = {**_c_args(), **changes}
    with pytest.raises(error, match=message):
        _closed7.first(*args.values())
    if "out" not in changes:
        assert np.isnan(args["out"]).all()  # nothing written


@pytest.mark.skipif(not COMPILED, reason="ik/_closed7 not built")
def test_compiled_function_with_no_start_or_read_only_out():
    from kin.ik.analytic.seven_r import _closed7

    args = {**_c_args(), "starts": np.zeros((0, 7))}
    assert _closed7.first(*args.values()) == -1
    readonly = np.zeros(7)
    readonly.setflags(write=False)
    with pytest.raises((TypeError, ValueError, BufferError)):
        _closed7.first(*{**_c_args(), "out": readonly}.values())


@pytest.mark.skipif(not COMPILED, reason="ik/_closed7 not built")
def test_first_with_float32_starts_matches_python():
    arm = make_arm("humanoid7")
    q = np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2])
    values = prepared(arm.ik, "pose", arm.fk(q))
    starts = np.tile(q, (2, 1)).astype(np.float32)
    out_c, out_py = np.full(7, np.nan), np.full(7, np.nan)
    assert arm.ik.first(values, starts, out_py, compiled=False) == 0
    assert arm.ik.first(values, starts, out_c, compiled=True) == 0


@pytest.mark.parametrize("compiled", [False, True])
def test_start_that_is_not_finite_is_skipped(compiled):
    """A start with a NaN joint is skipped (no joint 1 to keep), even when joint 1 is scanned."""
    arm = make_arm("humanoid7")
    q = np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2])
    for mode in ("pose", "position"):
        values = prepared(arm.ik, mode, arm.fk(q))
        starts = np.vstack((q, q))
        starts[0, 0] = np.nan
        out = np.full(7, np.nan)
        assert arm.ik.first(values, starts, out, step=0.05, compiled=compiled) == 1
        np.testing.assert_allclose(out, q, atol=1e-9)
        assert arm.ik.first(values, starts[:1], out, step=0.05, compiled=compiled) == -1
