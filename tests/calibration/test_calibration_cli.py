"""dh2urdf calibrate: reports, output files, and one-line errors (exit 2) for bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from dh2urdf import get_robot, load_table
from kin.batch_fk import batch_forward_kinematics
from kin.calibration import true_arm
from kin.calibration.synthetic import random_configurations
from kin.commands.dh2urdf_program import main as dh2urdf_main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "calibration" / "panda_tracker.csv"


def _write_case(
    path: Path, name: str, rows: int, *, poses: bool = False, markers: int = 1, mm: bool = False
) -> None:
    """A synthetic tracker file of ``rows`` rows (radians, meters or mm)."""
    table = get_robot(name).load_table()
    arm = true_arm(table, seed=1, markers=markers)
    rng = np.random.default_rng(2)
    q = random_configurations(table, rows, rng)
    data = arm.measure(q, poses, rng)
    scale = 1e3 if mm else 1.0
    if poses:
        from scipy.spatial.transform import Rotation

        head = ["x", "y", "z", "qx", "qy", "qz", "qw"]
        values = np.hstack(
            [data.points[:, 0] * scale, Rotation.from_matrix(data.rotations).as_quat()]
        )
    else:
        head = [f"{c}{k}" if markers > 1 else c for k in range(1, markers + 1) for c in "xyz"]
        values = data.points.reshape(rows, -1) * scale
    lines = [",".join(list(table.joint_names) + head)]
    lines += [",".join(repr(float(v)) for v in [*qi, *vi]) for qi, vi in zip(q, values)]
    path.write_text("\n".join(lines) + "\n")


def _run(argv, capsys):
    code = dh2urdf_main(["calibrate", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def _assert_same_fk(table, urdf: Path) -> None:
    """The table's measured point (kin's batched FK) is the URDF's (Pinocchio) to 1e-9 m."""
    model = pin.buildModelFromXML(urdf.read_text())
    state = model.createData()
    q = random_configurations(table, 20, np.random.default_rng(0))
    fk = batch_forward_kinematics(table, q)
    for i in range(len(q)):
        pin.framesForwardKinematics(model, state, q[i])
        point = state.oMf[model.getFrameId("measured_point")].translation
        assert np.abs(point - fk[i, :3, 3]).max() < 1e-9


def test_example_writes_a_table_and_a_urdf_with_the_same_fk(tmp_path, capsys):
    toml, urdf = tmp_path / "panda_calibrated.toml", tmp_path / "panda_calibrated.urdf"
    code, out, err = _run(
        [
            "panda",
            "--measurements",
            str(EXAMPLE),
            "--unit",
            "mm",
            "--deg",
            "-o",
            str(toml),
            "-o",
            str(urdf),
        ],
        capsys,
    )
    assert code == 0, err
    assert "identifiable parameters: 31 of 37" in out
    assert "panda_joint1.theta: +1 base.rz" in out
    table = load_table(toml)
    _assert_same_fk(table, urdf)
    # the table predicts the file's measurements as well as the report says
    rows = np.loadtxt(EXAMPLE, delimiter=",", skiprows=3)
    predicted = batch_forward_kinematics(table, np.radians(rows[:, :7]))[:, :3, 3] * 1e3
    rms = np.sqrt(np.mean(np.sum((predicted - rows[:, 7:]) ** 2, axis=1)))
    reported = next(line for line in out.splitlines() if line.strip().startswith("after (fit)"))
    assert float(reported.split()[2]) == pytest.approx(rms, abs=1e-4)  # [mm], 4 decimals


def test_json_report_in_si_units(tmp_path, capsys):
    path = tmp_path / "poses.csv"
    _write_case(path, "humanoid7", 40, poses=True)
    code, out, _ = _run(
        ["humanoid7", "--measurements", str(path), "--json", "--folds", "4"], capsys
    )
    assert code == 0
    report = json.loads(out)
    assert report["after"]["position_rms_m"] < 0.1e-3
    assert report["after"]["rotation_rms_rad"] < np.radians(0.02)
    assert report["cross_validated"]["position_rms_m"] > report["after"]["position_rms_m"]
    assert report["folds"] == 4
    assert {p["name"] for p in report["parameters"]} >= {"elbow.a", "base.rz", "tool.rx"}


def test_plot_and_two_markers(tmp_path, capsys):
    path, png = tmp_path / "markers.csv", tmp_path / "residuals.png"
    _write_case(path, "panda", 30, markers=2)
    code, out, err = _run(
        ["panda", "--measurements", str(path), "--plot", str(png), "-o", str(tmp_path / "a.urdf")],
        capsys,
    )
    assert code == 0, err
    assert "positions of 2 points" in out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    model = pin.buildModelFromXML((tmp_path / "a.urdf").read_text())
    assert model.existFrame("measured_point_1") and model.existFrame("measured_point_2")


def test_tilted_calibration_writes_a_table_and_a_urdf_with_the_same_fk(tmp_path, capsys):
    path = tmp_path / "ur10.csv"
    _write_case(path, "ur10", 40)
    toml, urdf = tmp_path / "ur10.toml", tmp_path / "ur10.urdf"
    code, out, err = _run(
        ["ur10", "--measurements", str(path), "-o", str(urdf), "-o", str(toml)], capsys
    )
    assert code == 0, err
    assert f"wrote {toml}" in out and f"wrote {urdf}" in out
    table = load_table(toml)
    assert [row.name for row in table.rows if row.beta] == ["shoulder_lift_joint", "elbow_joint"]
    _assert_same_fk(table, urdf)


def _header(name: str) -> str:
    return ",".join(get_robot(name).load_table().joint_names)


BAD = {
    "nan": (
        lambda rows: rows[:3] + [rows[3].replace(rows[3].split(",")[8], "nan", 1)] + rows[4:],
        "line 4 column 'y': 'nan' is not a finite number",
    ),
    "columns": (
        lambda rows: (
            [rows[0].replace("panda_joint7,", "")] + [r.split(",", 1)[1] for r in rows[1:]]
        ),
        "the header names 6 joint columns; the robot 'panda' has 7 joints",
    ),
    "short_row": (
        lambda rows: rows[:5] + [rows[5].rsplit(",", 1)[0]] + rows[6:],
        "line 6: 9 values; the header names 10 columns",
    ),
    "limits": (
        lambda rows: rows[:2] + ["3.5," + rows[2].split(",", 1)[1]] + rows[3:],
        "line 3 column 'panda_joint1': 3.5 rad is outside the joint's limits",
    ),
    "few": (lambda rows: rows[:6], "5 rows are too few for the 31 parameters"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_measurements_are_one_line_naming_file_line_and_column(tmp_path, capsys, case):
    good = tmp_path / "good.csv"
    _write_case(good, "panda", 30)
    change, message = BAD[case]
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(change(good.read_text().splitlines())) + "\n")
    out_file = tmp_path / "out.urdf"
    code, out, err = _run(["panda", "--measurements", str(bad), "-o", str(out_file)], capsys)
    assert code == 2
    assert err.count("\n") == 1 and str(bad) in err and message in err, err
    assert not out_file.exists() and out == ""


def test_millimetres_read_as_metres_is_the_slip_warning(tmp_path, capsys):
    path = tmp_path / "mm.csv"
    _write_case(path, "panda", 30, mm=True)
    code, _, err = _run(["panda", "--measurements", str(path)], capsys)
    assert code == 2
    assert (
        "millimetres read as meters? pass --unit mm" in err
        and str(path) in err
        and "column 'x'" in err
    )
    code, out, _ = _run(
        ["panda", "--measurements", str(path), "--unit", "mm", "--folds", "0"], capsys
    )
    assert code == 0 and "after (fit)" in out


def test_json_lines_and_roll_pitch_yaw_in_degrees(tmp_path, capsys):
    from scipy.spatial.transform import Rotation

    table = get_robot("humanoid7").load_table()
    arm = true_arm(table, seed=1)
    rng = np.random.default_rng(3)
    q = random_configurations(table, 40, rng)
    data = arm.measure(q, True, rng)
    rpy = np.degrees(Rotation.from_matrix(data.rotations).as_euler("xyz"))
    path = tmp_path / "poses.jsonl"
    path.write_text(
        "\n".join(
            json.dumps(
                {
                    "q": list(np.degrees(qi)),
                    "x": p[0],
                    "y": p[1],
                    "z": p[2],
                    "roll": r[0],
                    "pitch": r[1],
                    "yaw": r[2],
                }
            )
            for qi, p, r in zip(q, data.points[:, 0], rpy)
        )
        + "\n"
    )
    code, out, _ = _run(
        ["humanoid7", "--measurements", str(path), "--deg", "--json", "--folds", "0"], capsys
    )
    assert code == 0
    report = json.loads(out)
    assert report["kind"] == "poses" and report["after"]["rotation_rms_rad"] < np.radians(0.02)


def test_plan_poses_inside_the_limits_and_free_of_the_scene(capsys):
    table = get_robot("ur5").load_table()
    code, out, err = _run(
        ["ur5", "--plan-poses", "12", "--scene", str(ROOT / "examples" / "cell.toml")], capsys
    )
    assert code == 0, err
    lines = [line for line in out.splitlines() if not line.startswith("#")]
    assert lines[0] == ",".join(table.joint_names)
    q = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert q.shape == (12, 6)
    assert np.all(q >= table.lower - 1e-6) and np.all(q <= table.upper + 1e-6)
    assert "D-optimal" in out and "colliding left out" in out
    from kin.collision import CollisionChecker, load_collision_model
    from kin.robot_model import robot_from_table

    checker = CollisionChecker(
        load_collision_model(robot_from_table(table), scene=ROOT / "examples" / "cell.toml")
    )
    assert not any(checker.in_collision(qi) for qi in q)


def test_planned_poses_identify_what_random_ones_do_with_a_better_condition():
    from kin.calibration import calibrate
    from kin.calibration.pose_plan import plan_poses

    table = get_robot("panda").load_table()
    plan = plan_poses(table, 25)
    arm = true_arm(table, seed=1)
    planned = calibrate(table, arm.measure(plan.q, False, np.random.default_rng(0)), folds=0)
    random = calibrate(
        table,
        arm.measure(
            random_configurations(table, 25, np.random.default_rng(1)),
            False,
            np.random.default_rng(0),
        ),
        folds=0,
    )
    assert planned.identifiability.rank == random.identifiability.rank
    assert planned.identifiability.condition_number < random.identifiability.condition_number
