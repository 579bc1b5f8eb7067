"""A mimic joint in series on a URDF arm is followed: q = multiplier * q_leader + offset, in FK
(against a plain NumPy product of the URDF's own origins and axes, and Pinocchio's mimic model)
and in IK (round trips), the user's joint vector holding the independent joints only."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from cli_helper import assert_one_line_error, call

from dh2urdf.command import main as dh2urdf_main
from dh2urdf.urdf_chain import UrdfChainError, read_chain
from kin import ModelLoadError, load_robot
from kin.mimic_arm import load_mimic_arm

#: (name, origin xyz [m], origin rpy [rad], axis, limits [rad]) of a general 6R arm, with a
#: mimic joint "j3m" right after j3 (inserted by _urdf).
JOINTS = [
    ("j1", (0.0, 0.0, 0.33), (0.0, 0.0, 0.1), (0.0, 0.0, 1.0), (-2.8, 2.8)),
    ("j2", (0.05, 0.02, 0.1), (0.2, 0.0, 0.0), (0.0, 1.0, 0.0), (-2.0, 2.0)),
    ("j3", (0.0, 0.0, 0.4), (0.0, 0.1, 0.0), (0.0, 1.0, 0.0), (-2.5, 2.5)),
    ("j3m", (0.12, 0.0, 0.03), (0.0, 0.0, 0.3), (0.0, 0.6, 0.8), (-2.0, 2.0)),
    ("j4", (0.3, 0.01, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (-3.0, 3.0)),
    ("j5", (0.1, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 1.0, 0.0), (-2.0, 2.0)),
    ("j6", (0.08, 0.0, 0.02), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (-3.0, 3.0)),
]
TIP_ORIGIN = ((0.05, 0.0, 0.0), (0.0, 0.2, 0.0))
OFFSET = 0.3


def _urdf(multiplier: float, leader: str = "j3") -> str:
    links = ["base"] + [f"l{i}" for i in range(1, len(JOINTS) + 1)] + ["tip"]
    parts = ['<robot name="mimic6r">'] + [f'<link name="{name}"/>' for name in links]
    for i, (name, xyz, rpy, axis, (low, high)) in enumerate(JOINTS):
        mimic = (
            f'<mimic joint="{leader}" multiplier="{multiplier}" offset="{OFFSET}"/>'
            if name == "j3m"
            else ""
        )
        parts.append(
            f'<joint name="{name}" type="revolute"><parent link="{links[i]}"/>'
            f'<child link="{links[i + 1]}"/><origin xyz="{" ".join(map(str, xyz))}" '
            f'rpy="{" ".join(map(str, rpy))}"/><axis xyz="{" ".join(map(str, axis))}"/>'
            f'<limit lower="{low}" upper="{high}" effort="10" velocity="2"/>{mimic}</joint>'
        )
    xyz, rpy = TIP_ORIGIN
    parts.append(
        f'<joint name="flange" type="fixed"><parent link="{links[-2]}"/><child link="tip"/>'
        f'<origin xyz="{" ".join(map(str, xyz))}" rpy="{" ".join(map(str, rpy))}"/></joint>'
    )
    return "\n".join([*parts, "</robot>"])


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


def _in_limits(q: np.ndarray, multiplier: float) -> bool:
    values = [*q[:3], multiplier * q[2] + OFFSET, *q[3:]]
    return all(lo <= v <= hi for v, (*_, (lo, hi)) in zip(values, JOINTS, strict=True))


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


def test_commands_say_what_to_do_in_one_line(arm_file, tmp_path, capsys):
    """`kin fk` and `dh2urdf from-urdf` on the coupled chain: exit 2, one line naming the mimic
    joint and its leader; load_robot raises ModelLoadError."""
    from kin.commands import main

    path, _ = arm_file
    with pytest.raises(ModelLoadError, match="'j3m' follows 'j3'"):
        load_robot(path)
    code = call(main, ["fk", "--robot", str(path), "--q", *["0"] * 6])
    assert_one_line_error(code, capsys.readouterr().err, "kin.mimic_arm")
    out = tmp_path / "t.toml"
    code = call(dh2urdf_main, ["from-urdf", str(path), "-o", str(out)])
    assert_one_line_error(code, capsys.readouterr().err, "'j3m' follows 'j3' (mimic)")
    assert not out.exists()
