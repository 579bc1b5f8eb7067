"""``DH_KINEMATICS_PURE_PYTHON=1``: no compiled twin loads, and the answers are the compiled ones.

The switch is read by :func:`kin._native.twin` at each call, so a process started with it set
never imports a twin. Each side runs in its own interpreter (the variable set, and removed), the
same script: a UR5 pose (closed form, every branch), a 7R pose (humanoid7, numeric with the
closed-form steps, every branch) and three pose targets (a rotation, one 1e-13 off, a
reflection). The pure-Python side must load no twin and give the same branches to 1e-12 rad.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from support.solver_caps import NO_CAP

from kin._native import PURE_PYTHON_VARIABLE, TWINS, pure_python, twin, why_missing

#: Printed as one JSON line: the answers, then which twins' modules were imported.
SCRIPT = f"""
import json, sys
import numpy as np
from kin import Configuration, load_robot
from kin.ik import PoseTarget, TargetError, solve_ik
from kin._native import TWINS

answers = {{}}
for name, q, options in (
    ("ur5", [0.3, -1.2, 1.4, -0.5, 1.1, 0.2], {{}}),
    ("humanoid7", [0.3, -0.6, 0.4, 1.2, -0.5, 0.7, 0.2], {{"timeout": {NO_CAP!r}, "all_branches": True}}),
):
    robot = load_robot(name)
    pose = Configuration(robot, q).transform_frame_to_world("tool")
    result = solve_ik(robot, PoseTarget(pose.translation, pose.rotation), **options)
    answers[name] = [result.solver, result.success, [s.q.tolist() for s in result.solutions]]
turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
checks = []
for rotation in (turn, turn + 1e-13, turn @ np.diag([1.0, 1.0, -1.0])):
    try:
        checks.append(PoseTarget(np.array([0.1, 0.2, 0.3]), rotation).rotation.tolist())
    except TargetError as error:
        checks.append(type(error).__name__)
answers["pose_checks"] = checks
answers["loaded"] = sorted(n for n, module in TWINS.items() if module in sys.modules)
print(json.dumps(answers))
"""


def _run(pure: bool) -> dict:
    env = {k: v for k, v in os.environ.items() if k != PURE_PYTHON_VARIABLE}
    if pure:
        env[PURE_PYTHON_VARIABLE] = "1"
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def _built(name: str) -> bool:
    spec = importlib.util.find_spec(TWINS[name])
    return spec is not None and str(spec.origin).endswith(
        tuple(importlib.machinery.EXTENSION_SUFFIXES)
    )


@pytest.fixture(scope="module")
def runs() -> tuple[dict, dict]:
    return _run(pure=False), _run(pure=True)


def test_with_the_variable_no_twin_loads(runs):
    """The pure run imports no twin; the other imports the built ones its solves use (six here)."""
    compiled, pure = runs
    assert pure["loaded"] == []
    used = {
        "_closed7",
        "_damped_step",
        "_pieper_arms",
        "_pose_check",
        "_shoulder7",
        "_three_parallel",
    }
    assert set(compiled["loaded"]) == {name for name in used if _built(name)}


@pytest.mark.parametrize("robot", ["ur5", "humanoid7"])
def test_the_pure_python_branches_are_the_compiled_ones(runs, robot):
    """Same solver, success and branches (same order) to 1e-12 rad, the original pose reached."""
    compiled, pure = runs
    assert compiled[robot][:2] == pure[robot][:2] and compiled[robot][1] is True, f"{robot=}"
    a, b = np.array(compiled[robot][2]), np.array(pure[robot][2])
    assert a.shape == b.shape and a.shape[0] >= (8 if robot == "ur5" else 2), f"{robot=}"
    np.testing.assert_allclose(a, b, rtol=0.0, atol=1e-12, err_msg=f"{robot=}")


def test_the_pure_python_pose_check_is_the_compiled_one(runs):
    """A rotation and one 1e-13 off are taken (the same matrix kept), a reflection is refused."""
    compiled, pure = runs
    assert compiled["pose_checks"] == pure["pose_checks"]
    assert pure["pose_checks"][2] == "TargetError"
    assert np.asarray(pure["pose_checks"][0]).shape == (3, 3)


def test_the_variable_is_read_at_each_call(monkeypatch):
    """Set: every twin is None and says why; removed: the built twins load again."""
    monkeypatch.setenv(PURE_PYTHON_VARIABLE, "1")
    assert pure_python()
    for name in TWINS:
        assert twin(name) is None
        assert why_missing(name) == (
            f"{TWINS[name]} is not loaded ({PURE_PYTHON_VARIABLE} is set); the Python form runs alone"
        )
    monkeypatch.setenv(PURE_PYTHON_VARIABLE, "0")
    assert not pure_python()
    monkeypatch.delenv(PURE_PYTHON_VARIABLE)
    for name in TWINS:
        assert (twin(name) is not None) == _built(name), f"{name=}"
