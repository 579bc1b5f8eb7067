"""Joint direction in the table (issue #21, item 4): ``direction = -1`` reverses a joint.

The DH angle of a reversed revolute row is ``theta - q``, the DH length of a reversed prismatic
row ``d - q``; the limits stay those of ``q``. Checked here: the Robotics Toolbox's Kinova Jaco and
Mico models (``flip=True`` on joint 1, ``tests/data/toolbox/``) against the plain NumPy DH product
of ``tests/support/dh_reference.py`` and, where it is installed, the toolbox's own ``fkine``; the URDF
(Pinocchio) and MJCF (MuJoCo) of a random table with mixed directions; the closed forms (single,
batched, free joint) on reversed arms, every solution verified and the limits mirrored; the table
writer's round trip; a bad direction's error; the audit's "q reversed" edit.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from support.dh_reference import fk_frames, load_reference, random_configurations, rotation_angle

from dh2urdf import DHRow, DHTable, TableError, get_robot, load_table
from dh2urdf.mjcf_writer import TOOL_SITE, mjcf_string
from dh2urdf.table_writer import table_text
from dh2urdf.urdf_writer import urdf_string
from kin import batch_forward_kinematics
from kin.ik.analytic.six_r.three_parallel import URWrist6R
from kin.robot_model import robot_from_table

TOOLBOX = Path(__file__).parents[1] / "data" / "toolbox"
#: FK agreement [m], [rad].
TOL = 1e-12
#: Random joint vectors per FK comparison.
SAMPLES = 1000


def _reversed(table: DHTable, rows: dict[int, dict], name: str) -> DHTable:
    """``table`` with rows (0-based) replaced by the given fields (a direction, limits)."""
    new = list(table.rows)
    for i, fields in rows.items():
        new[i] = dataclasses.replace(new[i], **fields)
    return dataclasses.replace(table, rows=tuple(new), name=name, path=None)


def _pinocchio_tool(table: DHTable, q: np.ndarray) -> np.ndarray:
    """Tool poses (N, 4, 4) by Pinocchio from the table's URDF."""
    robot = robot_from_table(table)
    data = robot.model.createData()
    frame = robot.model.getFrameId(robot.tool_frame)
    out = np.empty((len(q), 4, 4))
    for k, qk in enumerate(q):
        pin.framesForwardKinematics(robot.model, data, qk)
        out[k] = data.oMf[frame].homogeneous
    return out


def _assert_same_poses(got: np.ndarray, expected: np.ndarray, tol: float, what: str) -> None:
    position = float(np.linalg.norm(got[..., :3, 3] - expected[..., :3, 3], axis=-1).max())
    rotation = float(rotation_angle(got[..., :3, :3], expected[..., :3, :3]).max())
    assert position < tol, f"{what}: position error {position:.3e} m"
    assert rotation < tol, f"{what}: rotation error {rotation:.3e} rad"


# -- the toolbox's Jaco and Mico ----------------------------------------------------------------


@pytest.mark.parametrize("arm", ["jaco", "mico"])
def test_toolbox_tables_reverse_joint_1_only(arm):
    """The table files say direction = -1 where the toolbox says flip=True (joint 1)."""
    table = load_table(TOOLBOX / f"{arm}.toml")
    assert [row.direction for row in table.rows] == [-1, 1, 1, 1, 1, 1]
    assert table.directions.tolist() == [-1.0, 1.0, 1.0, 1.0, 1.0, 1.0]


@pytest.mark.parametrize("arm", ["jaco", "mico"])
def test_toolbox_table_fk_equals_the_plain_dh_product(arm):
    """Batched FK and Pinocchio's FK of the URDF equal the plain NumPy product, theta1 - q1."""
    path = TOOLBOX / f"{arm}.toml"
    table = load_table(path)
    reference = load_reference(path)
    q = random_configurations(reference.lower, reference.upper, SAMPLES, 21)
    expected = fk_frames(reference, q)
    _assert_same_poses(batch_forward_kinematics(table, q, frames=True), expected, TOL, arm)
    _assert_same_poses(_pinocchio_tool(table, q[:200]), expected[:200, -1], TOL, f"{arm} URDF")
    # The direction matters: the same rows without it put the tool elsewhere.
    forward = dataclasses.replace(reference, direction=None)
    moved = np.linalg.norm(fk_frames(forward, q)[:, -1, :3, 3] - expected[:, -1, :3, 3], axis=-1)
    assert moved.max() > 0.1


@pytest.mark.peer
@pytest.mark.parametrize("arm", ["Jaco", "Mico"])
def test_toolbox_table_fk_equals_the_toolbox_fkine(arm):
    """Where roboticstoolbox-python is installed, its fkine equals the table's FK."""
    rtb = pytest.importorskip("roboticstoolbox")
    robot = getattr(rtb.models.DH, arm)()
    table = load_table(TOOLBOX / f"{arm.lower()}.toml")
    q = random_configurations(table.lower, table.upper, 200, 22)
    expected = np.array([np.asarray(robot.fkine(qk).A) for qk in q])
    _assert_same_poses(batch_forward_kinematics(table, q), expected, 1e-12, arm)


# -- URDF and MJCF of a random table with mixed directions --------------------------------------


def _random_table(seed: int, convention: str) -> DHTable:
    """Six random rows, revolute and prismatic, half of them reversed, asymmetric limits."""
    rng = np.random.default_rng(seed)
    types = ["revolute", "prismatic", "revolute", "revolute", "prismatic", "revolute"]
    directions = [-1, -1, 1, -1, 1, 1]
    rows = []
    for i, (kind, direction) in enumerate(zip(types, directions, strict=True), start=1):
        low, high = (-2.5, 1.0) if kind == "revolute" else (-0.1, 0.3)
        rows.append(
            DHRow(
                index=i,
                name=f"j{i}",
                joint_type=kind,  # type: ignore[arg-type]
                a=float(rng.uniform(-0.3, 0.3)),
                alpha=float(rng.uniform(-math.pi, math.pi)),
                d=float(rng.uniform(-0.3, 0.3)),
                theta=float(rng.uniform(-math.pi, math.pi)),
                lower=low,
                upper=high,
                velocity=1.0,
                effort=1.0,
                direction=direction,
            )
        )
    base = pin.SE3(pin.exp3(rng.normal(size=3)), rng.uniform(-0.2, 0.2, 3)).homogeneous
    tool = pin.SE3(pin.exp3(rng.normal(size=3)), rng.uniform(-0.2, 0.2, 3)).homogeneous
    return DHTable(f"mixed_{convention}", "", "", convention, tuple(rows), base, tool)  # type: ignore[arg-type]


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_urdf_and_mjcf_fk_equal_the_table_fk_with_mixed_directions(convention, tmp_path):
    """Axis 0 0 -1 on the reversed rows, limits of q; Pinocchio, MuJoCo, NumPy agree."""
    table = _random_table(5, convention)
    text = urdf_string(table)
    assert text.count('<axis xyz="0.0 0.0 -1.0"/>') == 3
    assert text.count('<axis xyz="0.0 0.0 1.0"/>') == 3
    robot = robot_from_table(table)
    np.testing.assert_array_equal(robot.lower, table.lower)
    np.testing.assert_array_equal(robot.upper, table.upper)
    # The plain product reads the table file as written by table_writer.
    path = tmp_path / "mixed.toml"
    path.write_text(table_text(table), encoding="utf-8")
    reference = load_reference(path)
    assert reference.direction is not None
    assert reference.direction.tolist() == [-1.0, -1.0, 1.0, -1.0, 1.0, 1.0]
    q = random_configurations(table.lower, table.upper, SAMPLES, 23)
    expected = fk_frames(reference, q)
    _assert_same_poses(batch_forward_kinematics(table, q, frames=True), expected, TOL, "NumPy")
    _assert_same_poses(_pinocchio_tool(table, q), expected[:, -1], TOL, "URDF")
    model = mujoco.MjModel.from_xml_string(mjcf_string(table))
    reversed_rows = [row.name for row in table.rows if row.direction == -1]
    for name in table.joint_names:
        axis = model.jnt_axis[model.joint(name).id]
        assert axis.tolist() == [0.0, 0.0, -1.0 if name in reversed_rows else 1.0], name
        joint_range = model.jnt_range[model.joint(name).id].tolist()
        row = table.rows[table.joint_names.index(name)]
        assert joint_range == [row.lower, row.upper], name
    data = mujoco.MjData(model)
    addresses = [model.jnt_qposadr[model.joint(name).id] for name in table.joint_names]
    site = model.site(TOOL_SITE).id
    got = np.zeros((len(q), 4, 4))
    got[:, 3, 3] = 1.0
    for k, qk in enumerate(q):
        data.qpos[addresses] = qk
        mujoco.mj_kinematics(model, data)
        got[k, :3, :3] = data.site_xmat[site].reshape(3, 3)
        got[k, :3, 3] = data.site_xpos[site]
    _assert_same_poses(got, expected[:, -1], 1e-9, "MJCF")


def test_dh_values_of_a_reversed_row():
    """``DHRow.dh_values``: theta + direction * q (revolute), d + direction * q (prismatic)."""
    table = _random_table(6, "standard")
    revolute, prismatic = table.rows[0], table.rows[1]
    assert revolute.dh_values(0.25) == (revolute.theta - 0.25, revolute.d)
    assert prismatic.dh_values(0.25) == (prismatic.theta, prismatic.d - 0.25)
    assert table.rows[2].dh_values(0.25) == (table.rows[2].theta + 0.25, table.rows[2].d)


# -- the table file -----------------------------------------------------------------------------


@pytest.mark.parametrize("arm", ["jaco", "mico"])
def test_table_round_trips_through_the_writer(arm, tmp_path):
    """table_text writes direction = -1 on the reversed rows only; reading it gives the table."""
    table = load_table(TOOLBOX / f"{arm}.toml")
    text = table_text(table)
    assert text.count("direction = -1") == 1
    assert "direction = 1" not in text
    path = tmp_path / f"{arm}.toml"
    path.write_text(text, encoding="utf-8")
    assert load_table(path).rows == table.rows


@pytest.mark.parametrize("literal", ["0", "2", "-2", '"x"', "true", "1.0", "-1.0", "[-1]"])
def test_a_bad_direction_names_file_row_field_and_fix(literal, tmp_path):
    """Only 1 or -1: the error names the file, the row and the field, and says what to write."""
    text = (TOOLBOX / "jaco.toml").read_text(encoding="utf-8")
    text = text.replace("direction = -1", f"direction = {literal}")
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(TableError) as caught:
        load_table(path)
    error = caught.value
    assert (error.path, error.row, error.field) == (str(path), 1, "direction")
    message = str(error)
    assert message.startswith(f"{path}, joint row 1, field 'direction': expected 1 or -1")
    assert "write direction = -1" in message


def test_a_row_built_in_code_checks_its_direction():
    """DHRow itself refuses a direction other than 1 or -1 (the package's TableError)."""
    with pytest.raises(TableError, match="field 'direction'"):
        DHRow(1, "j1", "revolute", 0.0, 0.0, 0.0, 0.0, -1.0, 1.0, 1.0, 1.0, direction=0)


# -- closed forms on reversed arms --------------------------------------------------------------

#: ur5 with joints 1 and 4 reversed; joint 1's limits asymmetric (q1 in [-1, 2.5] rad).
Q1_LIMITS = (-1.0, 2.5)


def _reversed_ur5() -> DHTable:
    ur5 = get_robot("ur5").load_table()
    low, high = Q1_LIMITS
    return _reversed(
        ur5, {0: {"direction": -1, "lower": low, "upper": high}, 3: {"direction": -1}}, "ur5_rev"
    )


def _wrapped_gap(q: np.ndarray, expected: np.ndarray) -> float:
    step = q - expected
    return float(np.abs(step - 2 * math.pi * np.rint(step / (2 * math.pi))).max())


@pytest.mark.parametrize(
    "compiled",
    [
        pytest.param(
            True, marks=pytest.mark.skipif(URWrist6R.compiled_twin is None, reason="no twin")
        ),
        False,
    ],
)
def test_closed_form_solves_a_reversed_ur5_every_solution_verified(compiled):
    """Poses from the arm's own FK: every solution's FK is the pose, inside the limits of q."""
    from kin.ik import PoseTarget
    from kin.ik.analytic.closed_form import ClosedFormSolver

    table = _reversed_ur5()
    solver = ClosedFormSolver(robot_from_table(table), compiled=compiled)
    assert solver.name == "closed_form:ur_wrist"
    assert (solver._twin is not None) == compiled
    # The same arm written forward (q' = -q on joints 1 and 4, limits mirrored by hand).
    signs = np.array([-1.0, 1.0, 1.0, -1.0, 1.0, 1.0])
    ur5 = get_robot("ur5").load_table()
    forward = _reversed(ur5, {0: {"lower": -Q1_LIMITS[1], "upper": -Q1_LIMITS[0]}}, "ur5_fwd")
    twin = ClosedFormSolver(robot_from_table(forward), compiled=compiled)
    q_all = random_configurations(table.lower, table.upper, 100, 24)
    for q in q_all:
        pose = batch_forward_kinematics(table, q)[0]
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        result = solver.solve(target, seed=q + 0.01)
        assert result.success, result.message
        assert min(_wrapped_gap(s.q, q) for s in result.solutions) < 1e-5
        mirrored = twin.solve(target, seed=(q + 0.01) * signs)
        assert [s.branch for s in result.solutions] == [s.branch for s in mirrored.solutions]
        for mine, theirs in zip(result.solutions, mirrored.solutions, strict=True):
            np.testing.assert_allclose(mine.q, theirs.q * signs, rtol=0, atol=1e-12)
        for solution in (*result.solutions, *result.rejected):
            got = batch_forward_kinematics(table, solution.q)[0]
            _assert_same_poses(got, pose, 1e-8, f"q={q.tolist()}")
        for solution in result.solutions:
            assert np.all(solution.q >= table.lower - 1e-10), solution.q
            assert np.all(solution.q <= table.upper + 1e-10), solution.q
        for solution in result.rejected:
            outside = (solution.q < table.lower - 1e-10) | (solution.q > table.upper + 1e-10)
            assert outside.any(), solution.q


@pytest.mark.parametrize("compiled", [True, False])
def test_closed_form_mirrors_the_limits_of_a_reversed_joint(compiled):
    """q1 = 2.4 is inside [-1, 2.5]: solved there; q1 = -2 is outside: that branch rejected."""
    from kin.ik import PoseTarget
    from kin.ik.analytic.closed_form import ClosedFormSolver

    table = _reversed_ur5()
    solver = ClosedFormSolver(robot_from_table(table), compiled=compiled)
    inside = np.array([2.4, -0.7, 1.1, 0.4, 0.9, -0.3])
    pose = batch_forward_kinematics(table, inside)[0]
    result = solver.solve(PoseTarget(pose[:3, 3], pose[:3, :3]), seed=inside)
    assert result.success
    assert _wrapped_gap(result.solutions[0].q, inside) < 1e-9
    outside = inside.copy()
    outside[0] = -2.0
    pose = batch_forward_kinematics(table, outside)[0]
    result = solver.solve(PoseTarget(pose[:3, 3], pose[:3, :3]), seed=outside)
    assert all(_wrapped_gap(s.q, outside) > 1e-6 for s in result.solutions)
    assert any(_wrapped_gap(s.q, outside) < 1e-9 for s in result.rejected)


def test_batch_solver_on_a_reversed_ur5():
    """BatchSolver: valid branches inside the limits of q, FK on target, the original found."""
    from kin.ik.analytic.batch import BatchSolver

    table = _reversed_ur5()
    solver = BatchSolver(robot_from_table(table))
    q = random_configurations(table.lower, table.upper, 500, 25)
    poses = batch_forward_kinematics(table, q)
    result = solver.solve_poses(poses)
    valid = result.valid
    assert valid.any(axis=1).all()
    found = result.q[valid]
    assert np.all((found >= table.lower - 1e-10) & (found <= table.upper + 1e-10))
    again = batch_forward_kinematics(table, found)
    _assert_same_poses(again, np.repeat(poses[:, None], valid.shape[1], 1)[valid], 1e-8, "batch")
    step = result.q - q[:, None, :]
    gap = np.abs(step - 2 * math.pi * np.rint(step / (2 * math.pi))).max(-1)
    assert (np.where(valid, gap, np.inf).min(axis=1) < 1e-7).all()


@pytest.mark.parametrize(("arm", "rows"), [("panda", (1, 6)), ("humanoid7", (0, 3))])
def test_free_joint_closed_form_on_reversed_seven_joint_arms(arm, rows):
    """The numeric solver's free-joint stage answers reversed 7R arms, verified, inside limits."""
    from kin.ik import PoseTarget
    from kin.ik.numeric.solver import NumericIK

    base = get_robot(arm).load_table()
    table = _reversed(base, {i: {"direction": -1} for i in rows}, f"{arm}_rev")
    ik = NumericIK(robot_from_table(table), prepare=False)
    assert ik.closed_form is not None
    for q in random_configurations(table.lower, table.upper, 20, 26):
        pose = batch_forward_kinematics(table, q)[0]
        result = ik.solve(PoseTarget(pose[:3, 3], pose[:3, :3]), seed=q + 0.05)
        assert result.success, result.message
        assert result.method == "closed_form_free_joint"
        for solution in result.solutions:
            _assert_same_poses(batch_forward_kinematics(table, solution.q)[0], pose, 1e-6, arm)
            assert np.all((solution.q >= table.lower) & (solution.q <= table.upper))


def test_forward_table_helpers():
    """forward_table: every direction 1, reversed limits mirrored, the same FK at q' = d q."""
    from kin.ik.analytic.joint_directions import (
        forward_table,
        mirrored_limits,
        reversed_joints,
        to_joint,
    )

    table = _random_table(7, "modified")
    directions = reversed_joints(table)
    assert directions is not None
    forward = forward_table(table)
    assert reversed_joints(forward) is None
    assert forward_table(forward) is forward
    for row, new in zip(table.rows, forward.rows, strict=True):
        expected = (row.lower, row.upper) if row.direction == 1 else (-row.upper, -row.lower)
        assert (new.lower, new.upper) == expected
    low, high = mirrored_limits(table.lower, table.upper, directions)
    np.testing.assert_array_equal(low, forward.lower)
    np.testing.assert_array_equal(high, forward.upper)
    q_forward = random_configurations(forward.lower, forward.upper, 200, 27)
    q = to_joint(q_forward, directions)
    assert np.all((q >= table.lower) & (q <= table.upper))
    np.testing.assert_allclose(
        batch_forward_kinematics(forward, q_forward), batch_forward_kinematics(table, q), atol=1e-15
    )


# -- the audit and the seed cache ---------------------------------------------------------------


def test_audit_q_reversed_reading_says_write_direction():
    """The audit's 'q reversed' edit is the table field: write direction = -1 on row i."""
    from kin.audit.audited_table import AuditedTable
    from kin.audit.changes import elementary_changes

    table = load_table(TOOLBOX / "jaco.toml")
    changes = [c for c in elementary_changes(AuditedTable(table, "m", "deg", "jaco.toml"))]
    edits = {c.row: c.edit for c in changes if c.kind == "joint_sign"}
    assert edits[1] == "write direction = 1 on row 1"  # already reversed: back to 1
    assert edits[2] == "write direction = -1 on row 2"


def test_audit_reproduces_samples_of_a_reversed_joint(tmp_path):
    """Samples printed by a source whose joint 2 turns the other way: the 'q2 reversed' reading
    reproduces them, and the table with its edit (direction = -1) reproduces them as written."""
    from kin.audit.audited_table import AuditedTable
    from kin.audit.changes import elementary_changes
    from kin.audit.fk_many import many_tool_poses
    from kin.audit.readings import apply_changes

    table = load_table(TOOLBOX / "mico.toml")
    audited = AuditedTable(table, "m", "deg", "mico.toml")
    change = next(c for c in elementary_changes(audited) if c.kind == "joint_sign" and c.row == 2)
    reading = apply_changes(audited, (change,))
    q = random_configurations(table.lower, table.upper, 50, 28)
    source = _reversed(table, {1: {"direction": -1}}, "mico_source")
    printed = batch_forward_kinematics(source, q)
    np.testing.assert_allclose(
        many_tool_poses([reading.table], (q * reading.signs)[None])[0], printed, atol=1e-12
    )
    np.testing.assert_allclose(many_tool_poses([source], q[None])[0], printed, atol=1e-12)


def test_seed_cache_key_includes_the_direction():
    """A reversed joint names another seed-table cache file than the same arm without it."""
    from kin.ik.numeric.seed_cache import table_key

    ur5 = get_robot("ur5").load_table()
    reversed_once = _reversed(ur5, {3: {"direction": -1}}, "ur5")
    forward = dataclasses.replace(ur5, path=None)
    key = table_key(robot_from_table(forward), 100, 0, 0.1, 0.05)
    assert table_key(robot_from_table(reversed_once), 100, 0, 0.1, 0.05) != key


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_flipped_axes_keep_the_forward_kinematics(convention):
    """Twists of +-pi turned to 0 (:func:`flipped_axes`): FK at ``q' = flips * q`` equals the
    table's at ``q`` (Pinocchio from the table's URDF), limits mirrored on the turned joints;
    random tables with revolute and prismatic rows, pi twists anywhere (the last row too, and two
    in a row), random base and tool."""
    from support.arm_tables import random_pose

    from kin.ik.analytic.joint_directions import flipped_axes

    rng = np.random.default_rng(12)
    for k in range(40):
        dof = int(rng.integers(2, 8))
        twists = rng.choice([math.pi, -math.pi, math.pi / 2, 0.3, -1.1], size=dof)
        twists[int(rng.integers(dof))] = -math.pi
        if k % 4 == 0:
            twists[-1] = math.pi
        if k % 4 == 1 and dof > 2:
            twists[:2] = math.pi
        rows = tuple(
            DHRow(
                i + 1,
                f"j{i + 1}",
                "prismatic" if rng.random() < 0.2 else "revolute",
                *rng.uniform(-0.4, 0.4, 1),
                twists[i],
                *rng.uniform(-0.4, 0.4, 1),
                *rng.uniform(-math.pi, math.pi, 1),
                -0.5,
                0.8,
                1.0,
                1.0,
            )  # fmt: skip
            for i in range(dof)
        )
        table = DHTable(f"flip{k}", "", "", convention, rows, random_pose(rng), random_pose(rng))
        turned, flips = flipped_axes(table)
        assert all(abs(abs(row.alpha) - math.pi) > 1e-9 for row in turned.rows)
        q = rng.uniform(-0.5, 0.8, (SAMPLES // 10, dof))
        _assert_same_poses(
            _pinocchio_tool(turned, q * flips), _pinocchio_tool(table, q), TOL, table.name
        )
        for row, old, flip in zip(turned.rows, table.rows, flips):
            expected = (old.lower, old.upper) if flip > 0 else (-old.upper, -old.lower)
            assert (row.lower, row.upper) == expected
    plain = (dataclasses.replace(rows[0], alpha=0.3),)
    assert flipped_axes(DHTable("plain", "", "", convention, plain)) is None
