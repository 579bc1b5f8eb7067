"""A mimic joint in series on a URDF arm is followed: q = multiplier * q_leader + offset, in FK
(against a plain NumPy product of the URDF's own origins and axes, and Pinocchio's mimic model)
and in IK (round trips), the user's joint vector holding the independent joints only."""

from __future__ import annotations

import io
import json
import math

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import assert_one_line_error, call
from support.mimic_reference import (
    JOINTS,
    OFFSET,
    TIP_ORIGIN,
    _in_limits,
    _pinocchio_mimic_fk,
    _urdf,
)

from dh2urdf.command import main as dh2urdf_main
from dh2urdf.urdf_chain import UrdfChainError, read_chain
from kin import ModelLoadError, load_robot
from kin.mimic.arm import load_mimic_arm


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' formula."""
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def _origin(xyz, rpy) -> np.ndarray:
    roll, pitch, yaw = rpy
    out = np.eye(4)
    out[:3, :3] = (
        _rotation([0, 0, 1], yaw) @ _rotation([0, 1, 0], pitch) @ _rotation([1, 0, 0], roll)
    )
    out[:3, 3] = xyz
    return out


def _numpy_fk(q: np.ndarray, multiplier: float) -> np.ndarray:
    """``T_base_tip`` by a plain product of the URDF's origins and axis rotations."""
    values = dict(zip(["j1", "j2", "j3", "j4", "j5", "j6"], q, strict=True))
    values["j3m"] = multiplier * values["j3"] + OFFSET
    product = np.eye(4)
    for name, xyz, rpy, axis, _ in JOINTS:
        motion = np.eye(4)
        motion[:3, :3] = _rotation(np.array(axis), values[name])
        product = product @ _origin(xyz, rpy) @ motion
    return product @ _origin(*TIP_ORIGIN)


@pytest.fixture(params=[1.0, -1.0], ids=["multiplier+1", "multiplier-1"])
def arm_file(request, tmp_path):
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(request.param), encoding="utf-8")
    return path, request.param


def test_the_chain_reads_the_coupling(arm_file):
    """The mimic joint is on the chain with its leader, multiplier and offset; 6 independent."""
    path, multiplier = arm_file
    chain = read_chain(path)
    assert [joint.name for joint in chain.joints] == [name for name, *_ in JOINTS]
    mimic = chain.joints[3].mimic
    assert mimic is not None
    assert (mimic.leader, mimic.multiplier, mimic.offset) == ("j3", multiplier, OFFSET)
    assert [joint.name for joint in chain.independent] == ["j1", "j2", "j3", "j4", "j5", "j6"]
    q = np.arange(1.0, 7.0) / 10
    assert chain.expand(q)[3] == pytest.approx(multiplier * 0.3 + OFFSET, abs=1e-15)


def test_fk_equals_a_numpy_product_and_pinocchio_with_mimic(arm_file):
    """Over 200 random q: the arm's FK equals the plain NumPy product of the URDF and
    Pinocchio's FK of the file built with mimic joints, to 1e-12."""
    path, multiplier = arm_file
    arm = load_mimic_arm(path)
    assert arm.nq == 6 and arm.joint_names == ("j1", "j2", "j3", "j4", "j5", "j6")
    model = pin.buildModelFromUrdf(str(path), mimic=True)
    assert model.nq == 6
    data = model.createData()
    tip = model.getFrameId("tip")
    rng = np.random.default_rng(3)
    for q in rng.uniform(-2.0, 2.0, size=(200, 6)):
        expected = _numpy_fk(q, multiplier)
        pin.framesForwardKinematics(model, data, q)
        assert np.abs(data.oMf[tip].homogeneous - expected).max() < 1e-12, f"{q=}"
        assert np.abs(arm.fk(q) - expected).max() < 1e-12, f"{multiplier=} {q=}"


def test_the_mimic_limits_narrow_the_leader(arm_file):
    """j3m in [-2, 2] with q3m = m q3 + 0.3 bounds q3 to [-2.3, 1.7] (m = 1) or [-1.7, 2.3]."""
    path, multiplier = arm_file
    arm = load_mimic_arm(path)
    expected = (-2.3, 1.7) if multiplier > 0 else (-1.7, 2.3)
    assert (arm.lower[2], arm.upper[2]) == pytest.approx(expected, abs=1e-12)
    assert arm.lower[0] == -2.8 and arm.upper[5] == 3.0


def test_ik_round_trips(arm_file):
    """FK(q) -> IK (from a random seed) -> FK equals the target (NumPy product) to 1e-5 m and
    1e-4 rad, inside every joint's limits (mimic included), for 12 random q."""
    path, multiplier = arm_file
    arm = load_mimic_arm(path)
    rng = np.random.default_rng(5)
    for _ in range(12):
        q = rng.uniform(arm.lower, arm.upper)
        target = _numpy_fk(q, multiplier)
        answer = arm.solve_ik(target, seed=rng.uniform(arm.lower, arm.upper))
        assert answer is not None, f"{multiplier=} {q=}"
        reached = _numpy_fk(answer.q, multiplier)
        assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) < 1e-5, f"{q=} {answer.q=}"
        cosine = (np.trace(reached[:3, :3].T @ target[:3, :3]) - 1) / 2
        assert math.acos(min(1.0, cosine)) < 1e-4, f"{q=} {answer.q=}"
        assert _in_limits(answer.q, multiplier), f"{answer.q=}"


def test_ik_reports_no_answer_for_an_unreachable_target(arm_file):
    """A target 5 m away gets None, never an answer off target."""
    path, _ = arm_file
    arm = load_mimic_arm(path)
    target = np.eye(4)
    target[:3, 3] = (5.0, 0.0, 0.0)
    assert arm.solve_ik(target, restarts=3, max_iter=50) is None


def test_a_leader_off_the_chain_is_one_clear_error(tmp_path):
    """j3m following a joint that is not on the chain names both and the fix."""
    path = tmp_path / "off.urdf"
    path.write_text(_urdf(1.0, leader="elsewhere"), encoding="utf-8")
    with pytest.raises(UrdfChainError, match="mimics 'elsewhere', which is not on the chain"):
        read_chain(path)


def test_other_commands_say_what_to_do_in_one_line(arm_file, tmp_path, capsys):
    """`kin drives` and `dh2urdf from-urdf` on the coupled chain (one variable per DH row):
    exit 2, one line naming the mimic joint, its leader and the commands that follow it;
    load_robot raises ModelLoadError."""
    from kin.commands import main

    path, _ = arm_file
    with pytest.raises(ModelLoadError, match="'j3m' follows 'j3'"):
        load_robot(path)
    code = call(main, ["drives", "--robot", str(path), "--q", *["0"] * 6])
    assert_one_line_error(code, capsys.readouterr().err, "kin fk and kin ik follow it")
    out = tmp_path / "t.toml"
    code = call(dh2urdf_main, ["from-urdf", str(path), "-o", str(out)])
    assert_one_line_error(code, capsys.readouterr().err, "'j3m' follows 'j3' (mimic)")
    assert not out.exists()


def _kin_json(capsys, argv: list[str]) -> tuple[int, dict]:
    from kin.commands import main

    code = call(main, argv)
    out = capsys.readouterr().out
    return code, json.loads(out)


def test_kin_fk_equals_pinocchio_mimic_fk(arm_file, capsys):
    """`kin fk --json` on the mimic arm, for 10 random independent q (some of them putting j3m
    outside its limits): the pose equals Pinocchio's mimic FK of the file and the NumPy product
    to 1e-12; the joint names are the six independent ones; the mimic coupling is reported;
    within_limits says whether every joint, j3m included, is inside its limits."""
    path, multiplier = arm_file
    rng = np.random.default_rng(11)
    for q in rng.uniform(-1.7, 1.7, size=(10, 6)):
        argv = ["fk", "--robot", str(path), "--q", *map(repr, q.tolist()), "--json"]
        code, record = _kin_json(capsys, argv)
        assert code == 0
        assert record["joint_names"] == ["j1", "j2", "j3", "j4", "j5", "j6"]
        assert record["mimic"] == [
            {"joint": "j3m", "leader": "j3", "multiplier": multiplier, "offset": OFFSET}
        ]
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = record["rotation"], record["position_m"]
        expected = _pinocchio_mimic_fk(path, q)
        assert np.abs(pose - expected).max() < 1e-12, f"{multiplier=} {q=}"
        assert np.abs(pose - _numpy_fk(q, multiplier)).max() < 1e-12, f"{multiplier=} {q=}"
        assert record["within_limits"] == _in_limits(q, multiplier), f"{q=}"


def test_kin_fk_text_names_the_independent_joints_and_the_coupling(arm_file, capsys):
    """The text output lists the six independent joints and how j3m follows j3 (in degrees with
    --deg for the joint values)."""
    from kin.commands import main

    path, multiplier = arm_file
    code = call(main, ["fk", "--robot", str(path), "--q", "0", "10", "20", "30", "40", "50"])
    out = capsys.readouterr().out
    assert code == 0
    lines = out.splitlines()
    assert lines[1] == "q: j1 0 rad, j2 10 rad, j3 20 rad, j4 30 rad, j5 40 rad, j6 50 rad"
    assert (
        lines[2] == f"mimic: j3m = {multiplier:g} * j3 + 0.3 rad (q holds the independent joints)"
    )


@pytest.mark.parametrize("count", [5, 7])
def test_kin_fk_and_ik_with_a_wrong_joint_count_are_one_line(arm_file, count, capsys):
    """Five or seven values (the chain has seven joints, six independent): one line naming the
    six independent joints, exit 2, for --q of kin fk and --seed-q of kin ik."""
    from kin.commands import main

    path, _ = arm_file
    values = ["0.1"] * count
    code = call(main, ["fk", "--robot", str(path), "--q", *values])
    assert_one_line_error(code, capsys.readouterr().err, "needs 6 values for 'mimic6r' (j1 [rad]")
    argv = ["ik", "--robot", str(path), "--target", "0.3", "0.2", "0.6", "--seed-q", *values]
    code = call(main, argv)
    assert_one_line_error(code, capsys.readouterr().err, "--seed-q needs 6 values")


def test_kin_ik_round_trips_judged_by_pinocchio_mimic_fk(arm_file, capsys):
    """FK(q) -> `kin ik --rpy --json` -> Pinocchio's mimic FK of the file at the answer equals
    the target to 1e-5 m and 1e-4 rad, inside every joint's limits, for 6 random q; and a
    position target (--json, no --rpy) is reached to 1e-5 m."""
    path, multiplier = arm_file
    arm = load_mimic_arm(path)
    rng = np.random.default_rng(17)
    for _ in range(6):
        q = rng.uniform(arm.lower, arm.upper)
        target = _pinocchio_mimic_fk(path, q)
        rpy = pin.rpy.matrixToRpy(target[:3, :3])
        argv = ["ik", "--robot", str(path), "--target", *map(repr, target[:3, 3].tolist())]
        argv += ["--rpy", *map(repr, rpy.tolist()), "--json", "--timeout", "5000"]
        code, record = _kin_json(capsys, argv)
        assert code == 0 and record["success"] and record["status"] == "ok", f"{q=} {record=}"
        assert record["joint_names"] == ["j1", "j2", "j3", "j4", "j5", "j6"]
        answer = np.array(record["solutions"][0]["q"])
        reached = _pinocchio_mimic_fk(path, answer)
        assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) < 1e-5, f"{q=} {answer=}"
        cosine = (np.trace(reached[:3, :3].T @ target[:3, :3]) - 1) / 2
        assert math.acos(min(1.0, cosine)) < 1e-4, f"{q=} {answer=}"
        assert _in_limits(answer, multiplier), f"{answer=}"
        argv = ["ik", "--robot", str(path), "--target", *map(repr, target[:3, 3].tolist())]
        code, record = _kin_json(capsys, [*argv, "--json", "--timeout", "5000"])
        assert code == 0 and record["success"], f"{q=} {record=}"
        answer = np.array(record["solutions"][0]["q"])
        reached = _pinocchio_mimic_fk(path, answer)
        assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) < 1e-5, f"{q=} {answer=}"
        assert _in_limits(answer, multiplier), f"{answer=}"


def test_kin_ik_far_target_is_not_found_never_a_success(arm_file, capsys):
    """A target 5 m away: exit 1, status not_found (the search proves nothing), the best
    attempt rejected with its true position error (over 3.5 m by Pinocchio's mimic FK)."""
    path, _ = arm_file
    argv = ["ik", "--robot", str(path), "--target", "5", "0", "0", "--rpy", "0", "0", "0"]
    code, record = _kin_json(capsys, [*argv, "--json"])
    assert code == 1
    assert (record["success"], record["status"], record["solutions"]) == (
        False,
        "not_found",
        [],
    )
    best = record["rejected"][0]
    reached = _pinocchio_mimic_fk(path, np.array(best["q"]))
    error = float(np.linalg.norm(reached[:3, 3] - (5.0, 0.0, 0.0)))
    assert error > 3.5 and best["position_error_m"] == pytest.approx(error, abs=1e-9)


def test_kin_ik_refuses_what_it_cannot_solve_in_one_line(arm_file, capsys):
    """--mask and --solver on the mimic arm: one line, exit 2."""
    from kin.commands import main

    path, _ = arm_file
    argv = ["ik", "--robot", str(path), "--target", "0.3", "0.2", "0.6", "--rpy", "0", "0", "0"]
    code = call(main, [*argv, "--mask", "1", "1", "1", "0", "0", "1"])
    assert_one_line_error(code, capsys.readouterr().err, "no --mask")
    code = call(main, [*argv, "--solver", "mink"])
    assert_one_line_error(code, capsys.readouterr().err, "drop --solver")


def test_kin_ik_stdin_answers_each_line_over_the_independent_joints(arm_file, capsys, monkeypatch):
    """`kin ik --stdin`: a reachable pose gets an answer on target by Pinocchio's mimic FK, a
    seed_q of seven values gets an error naming the six independent joints; exit 1 (one bad
    line), one answer per line."""
    from kin.commands import main

    path, _ = arm_file
    q = np.array([0.3, -0.4, 0.5, 0.2, -0.6, 0.1])
    target = _pinocchio_mimic_fk(path, q)
    rpy = pin.rpy.matrixToRpy(target[:3, :3]).tolist()
    good = {"target": target[:3, 3].tolist(), "rpy": rpy, "seed_q": [0.2, -0.3, 0.4, 0, 0, 0]}
    bad = {"target": [0.3, 0.2, 0.6], "seed_q": [0.0] * 7}
    monkeypatch.setattr("sys.stdin", io.StringIO(f"{json.dumps(good)}\n{json.dumps(bad)}\n"))
    code = call(main, ["ik", "--robot", str(path), "--stdin", "--timeout", "5000"])
    answers = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert code == 1 and [a["line"] for a in answers] == [1, 2]
    assert answers[0]["success"], answers[0]
    reached = _pinocchio_mimic_fk(path, np.array(answers[0]["solutions"][0]["q"]))
    assert np.abs(reached - target).max() < 1e-4, answers[0]
    assert "6 values" in answers[1]["error"] and "j6" in answers[1]["error"], answers[1]
