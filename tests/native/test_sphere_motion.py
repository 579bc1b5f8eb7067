"""kin.plan.sphere_motion: the spheres' rule against its compiled twin and against coal.

* parity: the twin and the NumPy form reach the same verdicts (states and motions) and count the
  same midpoints, on random states and motions of UR5 (its maker's URDF and SRDF) in a shelf cell of scripts/bench_plan_problems.json;
* conservative: every state and motion the spheres show free is free by a direct coal check of
  the collision model's pairs (states; motions resampled every 0.005 rad).
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.scripts_helper import SCRIPTS, load_script

from kin._native import twin
from kin.collision.requests import CONTACT_TOLERANCE
from kin.plan.sphere_motion import SphereMotion, sphere_motion

pytestmark = pytest.mark.filterwarnings("ignore")


def _model():
    if str(SCRIPTS) not in sys.path:  # the scripts import each other by bare name
        sys.path.insert(0, str(SCRIPTS))
    plan_problems = load_script("plan_problems")
    arm = plan_problems.ARMS["ur5"]
    robot = plan_problems.load_arm(arm)
    boxes = plan_problems.Problem.from_json(_first_problem()).boxes
    folder = Path(tempfile.mkdtemp())
    scene = folder / "scene.toml"
    scene.write_text(plan_problems.scene_toml(boxes), encoding="utf-8")
    return robot, plan_problems.collision_model(arm, robot, scene)


def _first_problem() -> dict:
    problems = json.loads((SCRIPTS / "bench_plan_problems.json").read_text())["problems"]
    return next(p for p in problems if p["id"].startswith("ur5-shelves"))


def _coal_free(model, q: np.ndarray) -> bool:
    data = model.robot.model.createData()
    geometry_data = pin.GeometryData(model.geometry_model)
    pin.updateGeometryPlacements(model.robot.model, data, model.geometry_model, geometry_data, q)
    pin.computeDistances(model.geometry_model, geometry_data)
    return min(r.min_distance for r in geometry_data.distanceResults) - model.padding > 0.0


def _both_forms():
    """The robot, the twin's SphereMotion of its cell and the NumPy form of the same arrays."""
    if twin("_sphere_motion") is None:
        pytest.skip("the compiled twin is not built")
    robot, model = _model()
    native = sphere_motion(model)
    assert native is not None and native._capsule is not None
    python = SphereMotion(native.arrays)
    python._capsule = None
    return robot, native, python


def test_twin_and_numpy_agree():
    robot, native, python = _both_forms()
    rng = np.random.default_rng(0)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    shown = 0
    for _ in range(80):
        q0, q1 = rng.uniform(lower, upper), rng.uniform(lower, upper)
        q1 = q0 + 0.1 * (q1 - q0)
        assert native.state_free(q0) == python.state_free(q0)
        a = native.motion_free(q0, q1, 1e-4, 5000)
        b = python.motion_free(q0, q1, 1e-4, 5000)
        assert a == b
        shown += a[0]
    assert shown >= 5


def test_twin_and_numpy_agree_on_long_motions():
    """Long motions between states the spheres show free (many refused at their midpoint, one
    check; the rest halved): the same verdicts and counts; a motion refused at once has its
    midpoint's spheres within the contact tolerance, by the NumPy arithmetic."""
    robot, native, python = _both_forms()
    rng = np.random.default_rng(4)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    at_once = halved = 0
    while at_once < 10 or halved < 10:
        q0, q1 = rng.uniform(lower, upper), rng.uniform(lower, upper)
        if not (python.state_free(q0) and python.state_free(q1)):
            continue
        a = native.motion_free(q0, q1, 1e-4, 5000)
        assert a == python.motion_free(q0, q1, 1e-4, 5000), (q0, q1)
        if a == (False, 1):
            at_once += 1
            middle = python._values(python._centers(0.5 * (q0 + q1)))
            assert not python._group_holds(middle > CONTACT_TOLERANCE).all()
        elif a[1] > 1:
            halved += 1


def test_shown_free_is_free():
    robot, model = _model()
    spheres = sphere_motion(model)
    assert spheres is not None
    rng = np.random.default_rng(1)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    motions = 0
    for _ in range(80):
        q0, q1 = rng.uniform(lower, upper), rng.uniform(lower, upper)
        q1 = q0 + 0.1 * (q1 - q0)
        if spheres.state_free(q0):
            assert _coal_free(model, q0)
        if (
            spheres.state_free(q0)
            and spheres.state_free(q1)
            and spheres.motion_free(q0, q1, 1e-4, 5000)[0]
        ):
            motions += 1
            steps = int(np.ceil(np.abs(q1 - q0).max() / 0.005))
            for t in np.linspace(0.0, 1.0, steps + 1):
                assert _coal_free(model, q0 + t * (q1 - q0))
    assert motions >= 3


def test_twin_and_numpy_agree_on_hostile_motions():
    """A NaN joint value is never shown free (state or motion), and a motion whose midpoints run
    past the budget is not shown free: the twin and the NumPy form alike, the same counts."""
    robot, native, python = _both_forms()
    q = np.zeros(robot.nq)
    broken = q.copy()
    broken[2] = np.nan
    for form in (native, python):
        assert not form.state_free(broken)
        assert not form.motion_free(q, broken, 1e-4, 5000)[0]
    rng = np.random.default_rng(3)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    for _ in range(40):
        q0, q1 = rng.uniform(lower, upper), rng.uniform(lower, upper)
        a, b = native.motion_free(q0, q1, 1e-4, 1), python.motion_free(q0, q1, 1e-4, 1)
        assert a == b
        if a[0]:  # shown within one midpoint: the full budget shows it too
            assert native.motion_free(q0, q1, 1e-4, 5000)[0]
