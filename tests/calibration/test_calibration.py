"""Kinematic calibration (kin.calibration): model, Jacobian, fit, identifiability, outputs.

Checked against something else: the model's FK against kin.batch_fk (another engine) and the
synthetic arm's plain product of URDF-style origins, the Jacobian against central finite
differences, the calibrated URDF with Pinocchio, and every fit against the TRUE arm of a
synthetic case on fresh configurations (kin.calibration.synthetic).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

from dh2urdf import get_robot
from kin.batch_fk import batch_forward_kinematics
from kin.calibration import calibrate, calibrated_table, calibrated_urdf, held_out_errors, true_arm
from kin.calibration.exceptions import CalibrationError
from kin.calibration.fit import Noise, residuals, rotation_errors
from kin.calibration.measurements import Measurements
from kin.calibration.parameters import build_model
from kin.calibration.prediction import predict
from kin.calibration.synthetic import nominal_origins, random_configurations

ARMS = ("ur10", "panda", "humanoid7", "scorbot")


def _table(name: str):
    return get_robot(name).load_table()


def _case(name: str, count: int, poses: bool, seed: int = 1, markers: int = 1):
    table = _table(name)
    arm = true_arm(table, seed=seed, markers=markers)
    rng = np.random.default_rng(seed + 100)
    return table, arm, arm.measure(random_configurations(table, count, rng), poses, rng)


@pytest.mark.parametrize("name", ARMS)
def test_model_at_nominal_values_is_the_tables_fk(name):
    table = _table(name)
    model, x = build_model(table, 0, np.array(table.T_world_base), np.array(table.T_last_tool))
    q = random_configurations(table, 50, np.random.default_rng(0))
    pred = predict(model, x, q)
    reference = batch_forward_kinematics(table, q)
    assert np.abs(pred.points[:, 0] - reference[:, :3, 3]).max() < 1e-12
    assert np.abs(pred.rotations - reference[:, :3, :3]).max() < 1e-12


@pytest.mark.parametrize("name", ARMS)
def test_unperturbed_synthetic_arm_is_the_tables_fk(name):
    table = _table(name)
    arm = true_arm(table, seed=3, origin_mm=0.0, origin_deg=0.0, offset_deg=0.0)
    q = random_configurations(table, 20, np.random.default_rng(1))
    last = arm.last_frames(q) @ nominal_origins(table)[-1]
    reference = arm.T_measurement_world @ batch_forward_kinematics(table, q)
    assert np.abs(last - reference).max() < 1e-12


@pytest.mark.parametrize("name", ARMS)
@pytest.mark.parametrize("markers", [0, 2])
def test_jacobian_matches_finite_differences(name, markers):
    table = _table(name)
    model, x = build_model(
        table, markers, np.array(table.T_world_base), np.array(table.T_last_tool)
    )
    rng = np.random.default_rng(2)
    x = x + rng.normal(0.0, 1e-2, x.shape)  # away from the references: rotation Jacobians too
    q = random_configurations(table, 15, rng)
    rot = Rotation.random(15, random_state=3).as_matrix() if markers == 0 else None
    data = Measurements(q, rng.normal(0.0, 1.0, (15, max(markers, 1), 3)), rot, np.arange(15))
    noise = Noise(1e-3, 1e-2)
    _, J = residuals(model, x, data, noise, jacobian=True)
    step = 1e-6
    numeric = np.zeros_like(J)
    for i in range(len(x)):
        up, down = x.copy(), x.copy()
        up[i] += step
        down[i] -= step
        numeric[:, i] = (
            residuals(model, up, data, noise)[0] - residuals(model, down, data, noise)[0]
        ) / (2 * step)
    assert np.abs(J - numeric).max() < 1e-5 * max(1.0, np.abs(J).max())


def test_parallel_axes_get_a_tilt_and_others_do_not():
    assert build_model(_table("ur10"), 1, np.eye(4), np.eye(4))[0].beta_rows == (1, 2)
    assert build_model(_table("panda"), 1, np.eye(4), np.eye(4))[0].beta_rows == ()


def test_rotation_error_is_the_log_map_across_half_a_turn():
    a = Rotation.from_rotvec([0.0, 0.0, np.pi - 1e-4]).as_matrix()[None]
    b = Rotation.from_rotvec([0.0, 0.0, -(np.pi - 1e-4)]).as_matrix()[None]
    # roll-pitch-yaw differ by almost 360 deg; the rotations by 2e-4 rad
    assert np.linalg.norm(rotation_errors(a, b)) == pytest.approx(2e-4, rel=1e-6)


@pytest.mark.parametrize(
    ("name", "poses"), [("ur10", False), ("panda", True), ("humanoid7", False)]
)
def test_fit_from_100_rows_predicts_the_true_arm(name, poses):
    table, arm, data = _case(name, 100, poses)
    found = calibrate(table, data, folds=0)
    held = held_out_errors(arm, found, count=500)
    rms, rot_rms = held.rms()
    assert rms < 0.04e-3
    assert held.max()[0] < 3 * rms
    assert found.before.rms()[0] > 0.5e-3  # the nominal arm was millimetres off
    if poses:
        assert np.degrees(rot_rms) < 0.006


def test_identifiability_names_what_absorbs_the_unknown_frames():
    table, _, data = _case("ur10", 40, True)
    found = calibrate(table, data, folds=0)
    absorbed = {u.name: dict(u.combination) for u in found.identifiability.unidentifiable}
    assert absorbed["shoulder_pan_joint.theta"] == {"base.rz": pytest.approx(1.0)}
    assert absorbed["shoulder_pan_joint.d"] == {"base.z": pytest.approx(1.0)}
    assert absorbed["wrist_3_joint.d"] == {"tool.z": pytest.approx(1.0)}
    # parallel shoulder, elbow and wrist 1 axes: their d values are one
    assert absorbed["elbow_joint.d"] == {"shoulder_lift_joint.d": pytest.approx(1.0)}
    assert np.isnan(found.std[~found.identifiability.identifiable]).all()
    assert np.isfinite(found.std[found.identifiability.identifiable]).all()


def test_a_joint_held_still_is_unidentifiable_and_the_rest_fits():
    table = _table("panda")
    arm = true_arm(table, seed=4)
    rng = np.random.default_rng(5)
    q = random_configurations(table, 60, rng)
    q[:, 4] = 0.3
    found = calibrate(table, arm.measure(q, False, rng), folds=0)
    reasons = {u.name: u.reason for u in found.identifiability.unidentifiable}
    assert reasons["panda_joint5.theta"] == "joint 'panda_joint5' never moves in the data"
    assert found.after.rms()[0] < 0.1e-3
    fresh = random_configurations(table, 200, np.random.default_rng(6))
    fresh[:, 4] = 0.3  # where the data holds it, the calibrated arm is right
    truth = arm.measure(fresh, False)
    assert (
        np.linalg.norm(predict(found.model, found.x, fresh).points - truth.points, axis=2).max()
        < 0.2e-3
    )


def test_standard_deviations_cover_the_scatter_of_repeated_fits():
    table = _table("humanoid7")
    arm = true_arm(table, seed=8)
    q = random_configurations(table, 40, np.random.default_rng(9))
    values, stds = [], []
    for seed in range(12):
        found = calibrate(table, arm.measure(q, False, np.random.default_rng(seed)), folds=0)
        values.append(found.x[found.model.index("elbow.a")])
        stds.append(found.std[found.model.index("elbow.a")])
    assert 0.5 < np.std(values, ddof=1) / np.mean(stds) < 2.0


def test_robust_loss_shrugs_off_outliers():
    table, arm, data = _case("panda", 80, False, seed=11)
    points = data.points.copy()
    points[::10] += 5e-3  # 8 rows 8.7 mm off
    bad = Measurements(data.q, points, None, data.lines)
    plain = held_out_errors(arm, calibrate(table, bad, folds=0), count=300).rms()[0]
    robust = held_out_errors(arm, calibrate(table, bad, folds=0, loss="cauchy"), count=300).rms()[0]
    assert robust < 0.06e-3 < plain


def test_cross_validated_errors_are_of_held_out_rows():
    table, _, data = _case("humanoid7", 50, False)
    found = calibrate(table, data, folds=5)
    assert found.cross_validated is not None
    assert found.cross_validated.rms()[0] > found.after.rms()[0]
    assert found.cross_validated.rms()[0] < 2.0 * found.after.rms()[0]


@pytest.mark.parametrize(("name", "markers"), [("ur10", 1), ("panda", 2), ("humanoid7", 0)])
def test_calibrated_urdf_predicts_the_measurements_alone(name, markers):
    table, _, data = _case(name, 60, markers == 0, markers=max(markers, 1))
    found = calibrate(table, data, folds=0)
    model = pin.buildModelFromXML(calibrated_urdf(found))
    frames = [f.name for f in model.frames]
    assert frames[1] == "measurement_frame"
    points = (
        ["measured_point"]
        if markers <= 1
        else [f"measured_point_{k}" for k in range(1, markers + 1)]
    )
    q = random_configurations(table, 20, np.random.default_rng(7))
    pred = predict(found.model, found.x, q)
    state = model.createData()
    for i in range(len(q)):
        pin.framesForwardKinematics(model, state, q[i])
        for k, point in enumerate(points):
            assert (
                np.abs(state.oMf[model.getFrameId(point)].translation - pred.points[i, k]).max()
                < 1e-9
            )
        if markers == 0:
            assert (
                np.abs(
                    state.oMf[model.getFrameId("measured_point")].rotation - pred.rotations[i]
                ).max()
                < 1e-9
            )


def test_nothing_explodes_joint_origins_move_by_the_correction():
    from dh2urdf.urdf_writer import urdf_elements

    table, _, data = _case("ur10", 80, False)
    found = calibrate(table, data, folds=0)
    nominal = {j.name: j.origin for j in urdf_elements(table).joints}
    for joint in pin.buildModelFromXML(calibrated_urdf(found)).names[1:]:
        assert joint in nominal
    import xml.etree.ElementTree as ET

    from dh2urdf.urdf_elements import Robot  # noqa: F401  (the elements' type)

    root = ET.fromstring(calibrated_urdf(found).split("?>", 1)[1])
    for element in root.iter("joint"):
        name = element.get("name")
        if name in ("base_joint", "tool_joint"):
            continue  # the measurement frame and the marker: unknowns, not corrections
        xyz = np.array([float(v) for v in element.find("origin").get("xyz").split()])
        assert np.linalg.norm(xyz - nominal[name][:3, 3]) < 5e-3, name


def test_table_of_a_calibration_without_tilts_has_the_urdfs_fk():
    table, _, data = _case("panda", 60, False)
    found = calibrate(table, data, folds=0)
    calibrated = calibrated_table(found)
    q = random_configurations(table, 30, np.random.default_rng(3))
    assert (
        np.abs(
            batch_forward_kinematics(calibrated, q)[:, :3, 3]
            - predict(found.model, found.x, q).points[:, 0]
        ).max()
        < 1e-9
    )


def test_a_tilted_calibration_writes_its_tilts_into_the_dh_table():
    table, _, data = _case("ur10", 60, False)
    found = calibrate(table, data, folds=0)
    rows = calibrated_table(found).rows
    fitted = {i: found.x[found.model.index(f"{table.rows[i].name}.beta")] for i in (1, 2)}
    assert {i: row.beta for i, row in enumerate(rows) if row.beta} == fitted
    assert all(abs(b) > 1e-5 for b in fitted.values())  # tilts the old format could not hold


def test_too_few_rows_for_the_identifiable_parameters():
    table, _, data = _case("panda", 8, False)
    with pytest.raises(
        CalibrationError,
        match="8 rows are too few for the 31 parameters this arm.s calibration identifies: measure at least 11 rows",
    ):
        calibrate(table, data)


def test_public_names_exist_and_are_sorted():
    import kin.calibration

    names = list(kin.calibration.__all__)
    assert [n for n in names if not hasattr(kin.calibration, n)] == []
    assert names == sorted(set(names))
