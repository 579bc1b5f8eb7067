"""`kin fk` prints roll-pitch-yaw and a quaternion beside the matrix, in the forms `kin ik --rpy`
and `kin ik --quat` take: the output of one pastes into the other, on every shipped robot."""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin
import pytest

from dh2urdf import ROBOTS
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
