"""A DH row's Hayati tilt ``beta`` (issue 45): read, written, in the URDF/MJCF, every FK, the IK.

The convention (:mod:`dh2urdf.dh_table`, as :mod:`kin.calibration.parameters` fits it):
``Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta)`` (standard), ``Rx(alpha) Ry(beta) Tx(a) Rz(theta)
Tz(d)`` (modified). Checked against a plain NumPy product written here that reads the TOML itself
(``tomllib``: neither dh2urdf's reader nor its transforms), Pinocchio on the URDF dh2urdf writes
and MuJoCo on its MJCF; the IK's answers against the plain product.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import warnings
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

import numpy as np
import pinocchio as pin
import pytest
from support.solver_caps import NO_CAP

from dh2urdf import TableError, get_robot, load_table
from dh2urdf.command import main as dh2urdf_main
from dh2urdf.exceptions import UnitWarning
from dh2urdf.table_writer import table_text
from dh2urdf.urdf_writer import urdf_string
from kin import robot_from_table
from kin.batch_fk import batch_forward_kinematics
from kin.calibration import calibrate, calibrated_table, calibrated_urdf, true_arm
from kin.calibration.parameters import build_model
from kin.calibration.prediction import predict
from kin.calibration.synthetic import random_configurations
from kin.ik import PoseTarget, PositionTarget, StructureError, get_solver, recognise, solve_batch
from kin.ik.analytic.batch import BatchSolver
from kin.ik.analytic.closed_form import ClosedFormSolver
from kin.ik.judge import POSITION_TOLERANCE, ROTATION_TOLERANCE
from kin.ik.numeric.free_joint_form import free_joint_closed_form
from kin.ik.numeric.seed_cache import table_key

#: Tilts written into shipped tables: robot -> {1-based row: beta in the table's angle unit}.
TILTS = {
    "ur5": {1: 0.02, 2: -0.03, 3: 0.05, 6: 0.07},  # standard, rad; row 6: a tool-side tilt
    "panda": {1: 0.04, 3: -0.02, 4: 0.03, 7: 0.06},  # modified, rad; row 1: a base-side tilt
    "scorbot": {2: 1.5, 3: -0.7},  # standard, mm and deg
}


# --- the plain product: the TOML read here, 4x4 matrices multiplied here ---------------------


def _rx(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _ry(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]])


def _rz(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _move(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out


def _fixed(section: dict, meters: float, radians: float) -> np.ndarray:
    assert set(section) <= {"xyz", "rpy"}, "the plain product reads xyz/rpy sections only"
    x, y, z = (v * meters for v in section.get("xyz", [0.0, 0.0, 0.0]))
    roll, pitch, yaw = (v * radians for v in section.get("rpy", [0.0, 0.0, 0.0]))
    return _move(x, y, z) @ _rz(yaw) @ _ry(pitch) @ _rx(roll)


def plain_frames(text: str, q: np.ndarray) -> list[np.ndarray]:
    """``T_world_frame0 .. T_world_frame{n}, T_world_tool`` of one joint vector, from TOML text."""
    data = tomllib.loads(text)
    meters = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}[data["length_unit"]]
    radians = {"rad": 1.0, "deg": math.pi / 180.0}[data["angle_unit"]]
    frames = [_fixed(data.get("base", {}), meters, radians)]
    for row, value in zip(data["joints"], q, strict=True):
        a, d = row["a"] * meters, row["d"] * meters
        alpha, theta = row["alpha"] * radians, row["theta"] * radians
        beta = row.get("beta", 0.0) * radians
        move = row.get("direction", 1) * value
        if row["type"] == "revolute":
            theta += move
        else:
            d += move
        if data["convention"] == "standard":
            step = _rz(theta) @ _move(z=d) @ _move(x=a) @ _rx(alpha) @ _ry(beta)
        else:
            step = _rx(alpha) @ _ry(beta) @ _move(x=a) @ _rz(theta) @ _move(z=d)
        frames.append(frames[-1] @ step)
    return frames + [frames[-1] @ _fixed(data.get("tool", {}), meters, radians)]


def plain_tool(text: str, q: np.ndarray) -> np.ndarray:
    return plain_frames(text, q)[-1]


def tilted_text(name: str, tilts: dict[int, float]) -> str:
    """The shipped table's TOML with ``beta = value`` added to the given rows (1-based)."""
    lines, row, out = get_robot(name).table_path.read_text().splitlines(), 0, []
    for line in lines:
        if line.strip() == "[[joints]]":
            row += 1
        out.append(line)
        if line.startswith("theta =") and row in tilts:
            out.append(f"beta = {tilts[row]!r}")
    return "\n".join(out) + "\n"


def _write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / f"{name}_tilted.toml"
    path.write_text(text)
    return path


def _configurations(table, count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(np.maximum(table.lower, -math.pi), np.minimum(table.upper, math.pi),
                       (count, table.dof))  # fmt: skip


# --- FK -----------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(TILTS))
def test_fk_of_a_tilted_table_equals_pinocchio_and_the_plain_product(tmp_path, name):
    text = tilted_text(name, TILTS[name])
    table = load_table(_write(tmp_path, name, text))
    assert [row.beta != 0.0 for row in table.rows] == [
        i + 1 in TILTS[name] for i in range(table.dof)
    ]
    model = pin.buildModelFromXML(urdf_string(table))
    data = model.createData()
    q = _configurations(table, 25, 4)
    frames = batch_forward_kinematics(table, q, frames=True)
    names = [f"frame{k}" for k in range(table.dof + 1)] + ["tool"]
    for i, qi in enumerate(q):
        expected = plain_frames(text, qi)
        pin.framesForwardKinematics(model, data, qi)
        for k, frame in enumerate(names):  # every DH frame: the tilt in its place in the row
            assert np.abs(frames[i, k] - expected[k]).max() < 1e-12, frame
            pinocchio = data.oMf[model.getFrameId(frame)].homogeneous
            assert np.abs(pinocchio - expected[k]).max() < 1e-12, frame
        product = table.T_world_base
        for row, value in zip(table.rows, qi):  # the rows' own transforms (kin.mimic.arm's FK)
            product = product @ row.transform(table.convention, value)
        assert np.abs(product @ table.T_last_tool - expected[-1]).max() < 1e-12
    untilted = batch_forward_kinematics(get_robot(name).load_table(), q)
    assert np.abs(untilted - frames[:, -1]).max() > 1e-3  # the tilts move the tool


def test_mjcf_of_a_tilted_table_places_the_tool_as_the_plain_product(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    from dh2urdf.mjcf_writer import mjcf_string

    text = tilted_text("panda", TILTS["panda"])
    table = load_table(_write(tmp_path, "panda", text))
    model = mujoco.MjModel.from_xml_string(mjcf_string(table))
    data = mujoco.MjData(model)
    site = model.site("tool").id
    for qi in _configurations(table, 10, 5):
        data.qpos[:] = qi
        mujoco.mj_kinematics(model, data)
        expected = plain_tool(text, qi)
        assert np.abs(data.site_xpos[site] - expected[:3, 3]).max() < 1e-9
        assert np.abs(data.site_xmat[site].reshape(3, 3) - expected[:3, :3]).max() < 1e-9


# --- the file: read, written, refused -----------------------------------------------------------


def test_written_table_keeps_every_tilt_and_plain_rows_write_none(tmp_path):
    table = load_table(_write(tmp_path, "scorbot", tilted_text("scorbot", TILTS["scorbot"])))
    text = table_text(table)
    assert text.count("beta = ") == len(TILTS["scorbot"])
    again = tmp_path / "again.toml"
    again.write_text(text)
    assert [row.beta for row in load_table(again).rows] == [row.beta for row in table.rows]
    assert table.rows[1].beta == pytest.approx(math.radians(1.5), abs=1e-15)  # degrees read
    assert "beta" not in table_text(get_robot("scorbot").load_table())


@pytest.mark.parametrize(
    ("value", "words"),
    [
        ("nan", "expected a finite number, got nan"),
        ("inf", "expected a finite number, got inf"),
        ('"0.1"', "expected a number, got '0.1'"),
        ("true", "expected a number, got True"),
    ],
)
def test_bad_beta_is_one_line_naming_the_table_row_and_key(tmp_path, capsys, value, words):
    path = _write(
        tmp_path, "ur5", tilted_text("ur5", {2: 0.0}).replace("beta = 0.0", f"beta = {value}")
    )
    with pytest.raises(TableError) as caught:
        load_table(path)
    assert (caught.value.row, caught.value.field) == (2, "beta")
    out = tmp_path / "out.urdf"
    code = dh2urdf_main([str(path), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and not out.exists()
    assert err.strip().splitlines() == [
        f"dh2urdf: error: {path}, joint row 2, field 'beta': {words}"
    ]


def test_a_row_refuses_a_non_finite_tilt():
    row = get_robot("ur5").load_table().rows[1]
    with pytest.raises(TableError, match="joint row 2, field 'beta': expected a finite angle"):
        dataclasses.replace(row, beta=math.nan)


def test_a_tilt_of_more_than_a_turn_in_radians_warns(tmp_path):
    path = _write(tmp_path, "ur5", tilted_text("ur5", {3: 12.0}))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_table(path)
    said = [str(w.message) for w in caught if issubclass(w.category, UnitWarning)]
    assert said and "joint row 3, field 'beta': 12 rad is more than a turn" in said[0]


# --- IK: never a closed form that ignores the tilt ----------------------------------------------


def _tilted(name: str, row: int, beta: float):
    table = get_robot(name).load_table()
    rows = list(table.rows)
    rows[row - 1] = dataclasses.replace(rows[row - 1], beta=beta)
    return dataclasses.replace(table, rows=tuple(rows))


def _on_target(text: str, result, target: np.ndarray, oriented: bool) -> int:
    """The answers' count, each checked by the plain product against ``target`` (4x4)."""
    for solution in result.solutions:
        reached = plain_tool(text, np.asarray(solution.q))
        position = float(np.linalg.norm(reached[:3, 3] - target[:3, 3]))
        assert position <= POSITION_TOLERANCE
        assert abs(position - solution.position_error) < 1e-9  # the judge measured this arm
        if oriented:
            rotation = np.linalg.norm(pin.log3(reached[:3, :3].T @ target[:3, :3]))
            assert rotation <= ROTATION_TOLERANCE
    return len(result.solutions)


def test_ik_of_a_ur5_tilted_a_hundredth_of_a_degree_answers_on_target_only():
    table = _tilted("ur5", 2, math.radians(0.01))
    text = table_text(table)
    robot = robot_from_table(table)
    with pytest.raises(StructureError, match=r"row 2 \('shoulder_lift_joint'\): beta = 0.01 deg"):
        recognise(table)
    with pytest.raises(StructureError, match="beta"):
        ClosedFormSolver(robot)  # beyond the idealised route's snap: no closed form at all
    with pytest.raises(StructureError):
        BatchSolver(robot)  # nor the vectorized one (or its compiled twin)
    solver = get_solver(robot)
    assert not solver.name.startswith("closed_form")
    targets = batch_forward_kinematics(table, _configurations(table, 4, 7))
    answers = 0
    for target in targets:
        result = solver.solve(PoseTarget(target[:3, 3], target[:3, :3]), timeout=NO_CAP)
        assert result.status == "ok"
        answers += _on_target(text, result, target, True)
        result = solver.solve(PositionTarget(target[:3, 3]), timeout=NO_CAP)
        answers += _on_target(text, result, target, False)
    assert answers >= 8
    batch = solve_batch(robot, targets[:, :3, 3], targets[:, :3, :3], timeout=NO_CAP)
    for q, target in zip(batch.q, targets):
        assert np.linalg.norm(plain_tool(text, q)[:3, 3] - target[:3, 3]) <= POSITION_TOLERANCE


def test_a_tilt_within_the_snap_is_solved_on_the_plain_arm_and_polished_on_the_tilted_one():
    table = _tilted("ur5", 2, math.radians(0.001))
    text = table_text(table)
    solver = ClosedFormSolver(robot_from_table(table))
    assert solver.idealised is not None
    assert any(change.startswith("row 2 beta") for change in solver.idealised.changes)
    assert all(row.beta == 0.0 for row in solver.idealised.table.rows)
    assert solver._twin is None  # the compiled twin measures the plain arm: not asked
    for target in batch_forward_kinematics(table, _configurations(table, 4, 8)):
        result = solver.solve(PoseTarget(target[:3, 3], target[:3, :3]), timeout=NO_CAP)
        assert result.status == "ok" and len(result.solutions) >= 2
        for solution in result.solutions:
            reached = plain_tool(text, np.asarray(solution.q))
            assert np.abs(reached - target).max() < 1e-9  # polished onto the tilted arm


def test_a_tilted_seven_joint_arm_gets_no_free_joint_closed_form():
    table = _tilted("panda", 4, 0.01)
    assert free_joint_closed_form(table, table.lower, table.upper) is None
    assert free_joint_closed_form(get_robot("panda").load_table(), table.lower, table.upper)


def test_the_seed_cache_key_names_the_tilt():
    plain = robot_from_table(get_robot("ur5").load_table())
    tilted = robot_from_table(_tilted("ur5", 2, 1e-6))
    assert table_key(plain, 100, 0, 0.1, 0.05) != table_key(tilted, 100, 0, 0.1, 0.05)


# --- calibration: the table output carries the fitted tilts --------------------------------------


def test_calibrated_ur10_table_has_the_urdfs_fk(tmp_path):
    table = get_robot("ur10").load_table()
    arm = true_arm(table, seed=1)
    rng = np.random.default_rng(101)
    found = calibrate(
        table, arm.measure(random_configurations(table, 60, rng), False, rng), folds=0
    )
    text = table_text(calibrated_table(found))
    assert text.count("beta = ") == 2  # the shoulder-lift and elbow rows (axes 2 || 3 || 4)
    written = tmp_path / "ur10_calibrated.toml"
    written.write_text(text)
    calibrated = load_table(written)
    model = pin.buildModelFromXML(calibrated_urdf(found))
    data = model.createData()
    point = model.getFrameId("measured_point")
    q = random_configurations(table, 30, np.random.default_rng(3))
    fk = batch_forward_kinematics(calibrated, q)
    predicted = predict(found.model, found.x, q).points[:, 0]
    assert np.abs(fk[:, :3, 3] - predicted).max() < 1e-9
    for i, qi in enumerate(q):
        pin.framesForwardKinematics(model, data, qi)
        assert np.abs(data.oMf[point].translation - fk[i, :3, 3]).max() < 1e-9
        assert np.abs(plain_tool(text, qi)[:3, 3] - fk[i, :3, 3]).max() < 1e-9


def test_a_calibrated_table_calibrated_again_starts_from_its_tilts():
    table = _tilted("ur10", 2, 0.002)
    table = dataclasses.replace(
        table,
        rows=(*table.rows[:4], dataclasses.replace(table.rows[4], beta=-0.003), table.rows[5]),
    )
    model, x = build_model(table, 0, np.array(table.T_world_base), np.array(table.T_last_tool))
    assert 4 in model.beta_rows  # a tilt on a row whose axis is not parallel to the next: kept
    q = random_configurations(table, 20, np.random.default_rng(0))
    predicted = predict(model, x, q)
    reference = batch_forward_kinematics(table, q)
    assert np.abs(predicted.points[:, 0] - reference[:, :3, 3]).max() < 1e-12
    assert np.abs(predicted.rotations - reference[:, :3, :3]).max() < 1e-12


def test_the_audits_many_readings_honour_the_tilts(tmp_path):
    from kin.audit.fk_many import many_tool_poses

    for name in ("ur5", "panda"):
        text = tilted_text(name, TILTS[name])
        tilted = load_table(_write(tmp_path, name, text))
        plain = get_robot(name).load_table()
        q = np.stack([_configurations(plain, 6, 9)] * 2)
        poses = many_tool_poses([tilted, plain], q)
        for i, qi in enumerate(q[0]):
            assert np.abs(poses[0, i] - plain_tool(text, qi)).max() < 1e-12
        assert np.abs(poses[1] - batch_forward_kinematics(plain, q[1])).max() < 1e-12
