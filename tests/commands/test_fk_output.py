"""`kin fk` prints roll-pitch-yaw and a quaternion beside the matrix, in the forms `kin ik --rpy`
and `kin ik --quat` take: the output of one pastes into the other, on every shipped robot."""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support.cli_helper import call, write_rrpr4
from support.dh_reference import dh_matrices, load_reference

from dh2urdf import ROBOTS, get_robot
from kin import Configuration, load_robot
from kin.commands import fk, ik


def _json(capsys, main, argv: list[str]) -> dict:
    code = main(argv)
    out = capsys.readouterr().out
    record = json.loads(out)
    assert code == (0 if record.get("success", True) else 1), out
    return record


@pytest.mark.parametrize("name", list(ROBOTS))
@pytest.mark.parametrize("deg", [False, True])
def test_fk_orientation_forms_agree_and_paste_into_ik(name, deg, capsys):
    """rpy and quat of kin fk rebuild its matrix; pasted into kin ik they give the same pose."""
    robot = load_robot(name)
    q = np.random.default_rng(len(name)).uniform(robot.lower, robot.upper)
    scale = 180 / math.pi if deg else 1.0
    q_text = [
        repr(float(v * scale if row.joint_type == "revolute" else v))
        for v, row in zip(q, robot.table.rows)
    ]
    flags = ["--deg"] if deg else []
    record = _json(capsys, fk.main, ["--robot", name, "--q", *q_text, *flags, "--json"])
    assert record["rpy_unit"] == ("deg" if deg else "rad")
    rotation = np.array(record["rotation"])
    rpy = np.array(record["rpy"]) / scale
    np.testing.assert_allclose(pin.rpy.rpyToMatrix(*rpy), rotation, atol=1e-12)
    w, x, y, z = record["quat_wxyz"]
    assert w >= 0 and abs(w * w + x * x + y * y + z * z - 1) < 1e-12
    np.testing.assert_allclose(pin.Quaternion(w, x, y, z).toRotationMatrix(), rotation, atol=1e-12)
    if robot.nq < 6:  # a full pose needs six joints (kin ik says so): the position only
        return
    target = ["--target", *map(repr, record["position_m"])]
    for form, values in (("--rpy", record["rpy"]), ("--quat", record["quat_wxyz"])):
        argv = ["--robot", name, *target, form, *map(repr, values), *flags, "--json"]
        answer = _json(capsys, ik.main, argv)
        assert answer["success"], f"{name=} {form=} {answer['message']}"
        reached = Configuration(robot).fk(np.array(answer["solutions"][0]["q"]))
        np.testing.assert_allclose(reached.translation, record["position_m"], atol=1e-6)
        angle = np.linalg.norm(pin.log3(reached.rotation.T @ rotation))
        assert angle < 1e-6, f"{name=} {form=} {angle=}"


def _text_pose(out: str) -> tuple[list[str], list[str], list[str]]:
    """Position, rpy and quat fields of kin fk's text output, as printed."""
    fields = {}
    for line in out.splitlines():
        for key in ("position [", "rpy [", "quat ("):
            if line.startswith(key):
                fields[key] = line.split(":", 1)[1].split()
    return fields["position ["], fields["rpy ["], fields["quat ("]


@pytest.mark.parametrize("name", ["ur5", "puma560", "panda", "humanoid7"])
@pytest.mark.parametrize("unit", ["m", "mm"])
def test_fk_text_pastes_into_ik_to_1e6(name, unit, capsys):
    """The printed text (6 decimals of position, rpy, quat) pasted into kin ik: the same pose to
    1e-6 m and 1e-6 rad, by Pinocchio's FK of the answer."""
    robot = load_robot(name)
    q_deg = np.degrees(np.random.default_rng(7).uniform(robot.lower, robot.upper))
    argv = ["--robot", name, "--q", *map(repr, q_deg.tolist()), "--deg", "--unit", unit]
    assert fk.main(argv) == 0
    position, rpy, quat = _text_pose(capsys.readouterr().out)
    pose = Configuration(robot).fk(q_deg * np.pi / 180)
    for form, values in (("--rpy", rpy), ("--quat", quat)):
        argv = ["--robot", name, "--target", *position, form, *values, "--deg", "--unit", unit]
        answer = _json(capsys, ik.main, [*argv, "--json"])
        assert answer["success"], f"{name=} {form=} {answer['message']}"
        reached = Configuration(robot).fk(np.array(answer["solutions"][0]["q"]))
        np.testing.assert_allclose(reached.translation, pose.translation, atol=1e-6)
        angle = np.linalg.norm(pin.log3(reached.rotation.T @ pose.rotation))
        assert angle < 1e-6, f"{name=} {form=} {angle=}"


#: Joint values the issues name (issue 19: 1e308, non-finite), signs included, and ordinary ones.
EXTREME = st.one_of(
    st.sampled_from(
        [0.0, -0.0, 5e-324, 1e-300, 1e3, -1e3, 1e6, 1e9, 1e200, -1e200, 1e308, -1e308]
        + [math.nan, math.inf, -math.inf]
    ),
    st.floats(min_value=-400.0, max_value=400.0),
)


def _reference_pose(path, q: np.ndarray) -> np.ndarray:
    """T_world_tool by a NumPy DH product; a revolute q as its own exact Rz(q) (math.cos/sin),
    so that a huge q is not absorbed by the joint's theta offset (1e308 + 0.3 == 1e308)."""
    ref = load_reference(path)
    T = ref.T_world_base.copy()
    for i in range(ref.dof):
        prismatic = bool(ref.prismatic[i])
        d = ref.d[i] + (q[i] if prismatic else 0.0)
        link = dh_matrices(
            ref.convention, ref.a[i : i + 1], ref.alpha[i : i + 1], [d], ref.theta[i : i + 1]
        )
        link = np.asarray(link).reshape(4, 4)
        if not prismatic:
            c, s = math.cos(q[i]), math.sin(q[i])
            turn = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
            # Rz(q) commutes with Rz(theta) Tz(d): before the standard row, after the modified one.
            link = turn @ link if ref.convention == "standard" else link @ turn
        T = T @ link
    return T @ ref.T_last_tool


@pytest.fixture(scope="module")
def table_files(tmp_path_factory) -> dict:
    """Table files of the test arms: rrpr4 (a prismatic joint in mm) and 'giant', ur5 with
    links of 1e6 m (the bound of a table's lengths)."""
    folder = tmp_path_factory.mktemp("fk_extreme")
    text = get_robot("ur5").table_path.read_text(encoding="utf-8")
    giant = text.replace("a = -0.425\n", "a = -1e6\n").replace("d = 0.089159\n", "d = 1e6\n")
    assert giant.count("1e6") == 2
    (folder / "giant.toml").write_text(giant, encoding="utf-8")
    return {"rrpr4": write_rrpr4(folder), "giant": folder / "giant.toml"}


@pytest.mark.parametrize("name", [*ROBOTS, "rrpr4", "giant"])
@settings(
    max_examples=30,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(data=st.data(), deg=st.booleans(), unit=st.sampled_from(["m", "mm"]), text=st.booleans())
def test_fk_any_joint_values_a_finite_answer_or_one_line(
    name, data, deg, unit, text, table_files, capsys
):
    """kin fk with extreme or non-finite --q (issue 19): never a traceback; exit 0 with finite
    numbers equal to a NumPy DH product at the q it reports, or exit 2 with one stderr line and
    nothing on stdout."""
    path = table_files[name] if name in table_files else get_robot(name).table_path
    dof = len(load_reference(path).names)
    q = data.draw(st.lists(EXTREME, min_size=dof, max_size=dof), label="q")
    argv = ["--robot", str(path) if name in table_files else name, "--q", *map(repr, q)]
    argv += ["--unit", unit] + (["--deg"] if deg else []) + ([] if text else ["--json"])
    code = call(fk.main, argv)
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err, captured.err
    if code == 2:
        assert len(captured.err.strip().splitlines()) == 1 and captured.out == "", captured
        assert not all(map(math.isfinite, q)) or name == "rrpr4", f"{name=} {q=} {captured.err}"
        return
    assert code == 0, (code, captured)
    if text:
        numbers = [float(v) for field in _text_pose(captured.out) for v in field]
        assert all(map(math.isfinite, numbers)), captured.out
        return
    record = json.loads(captured.out)
    values = np.array(record["q"])
    prismatic = load_reference(path).prismatic
    scales = np.where(prismatic, 1e-3 if unit == "mm" else 1.0, math.pi / 180 if deg else 1.0)
    np.testing.assert_allclose(values, np.array(q) * scales, rtol=1e-15, atol=0)
    T = _reference_pose(path, values)
    assert np.all(np.isfinite(T)), f"{name=} {q=}"
    scale = 1.0 + float(np.abs(T[:3, 3]).max())
    np.testing.assert_allclose(record["position_m"], T[:3, 3], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(record["rotation"], T[:3, :3], rtol=0, atol=1e-9)
    w, x, y, z = record["quat_wxyz"]
    np.testing.assert_allclose(pin.Quaternion(w, x, y, z).toRotationMatrix(), T[:3, :3], atol=1e-9)
