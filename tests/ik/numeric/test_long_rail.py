"""Every random draw of the IK over a long rail's limits is cut to the arm's size (issue 47).

A Panda on a turning base and a +-999,999 m rail (tests/support/long_rail_arm.py, the Robotics Toolbox's
Frankie). Drawn over the rail's whole travel, the reach's samples put the tool kilometres away (the
out-of-reach check never triggered: a target 10 m above the arm ran every start and QP run) and
the distance-bounded solve's random starts began kilometres from any target. Judged apart from the
code under test: heights and tool positions by Pinocchio's FK of the URDF text, clearances by the
spheres' centres against the box in plain NumPy.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from support.long_rail_arm import PANDA, SPHERE_LINKS, frankie_urdf, srdf_text
from support.solver_caps import NO_CAP

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.ik import PoseTarget, PositionTarget, get_solver
from kin.ik.collision.collision_aware import CollisionAwareSolver, _limits
from kin.ik.collision.collision_bound import DistanceBoundedIK
from kin.ik.reach import arm_reach

#: Sphere radius on the arm's links [m]; the box's centre and side [m].
RADIUS, BOX, SIDE = 0.06, (0.5, 0.0, 0.75), 0.2
#: Damped Newton and QP steps an out-of-reach call may take (it took 120 on the cut reach).
OUT_OF_REACH_STEPS = 400


@pytest.fixture(scope="module")
def frankie(tmp_path_factory: pytest.TempPathFactory):
    """(robot, Pinocchio model of the URDF text, checker with a box in front of the arm)."""
    folder = tmp_path_factory.mktemp("long_rail")
    (folder / "frankie.urdf").write_text(frankie_urdf(RADIUS))
    (folder / "frankie.srdf").write_text(srdf_text())
    xyz = ", ".join(map(repr, BOX))
    (folder / "box.toml").write_text(
        f'[[box]]\nname = "box"\nsize = [{SIDE}, {SIDE}, {SIDE}]\nxyz = [{xyz}]\n'
    )
    robot = load_robot(folder / "frankie.urdf", "base0", "flange")
    model = load_collision_model(robot, srdf=folder / "frankie.srdf", scene=folder / "box.toml")
    return robot, pin.buildModelFromXML(frankie_urdf()), CollisionChecker(model)


def _positions(model: pin.Model, q: np.ndarray, links) -> list[np.ndarray]:
    data = model.createData()
    pin.framesForwardKinematics(model, data, np.asarray(q, dtype=float))
    return [data.oMf[model.getFrameId(link)].translation.copy() for link in links]


def test_the_reach_is_measured_across_the_rail(frankie):
    """The rail runs in the floor's plane: the reach is a height, the largest Pinocchio finds."""
    robot, model, _ = frankie
    reach = arm_reach(robot)
    assert np.allclose(reach.across, np.diag([0.0, 0.0, 1.0]), atol=1e-9)
    rng = np.random.default_rng(7)
    lower = np.maximum(model.lowerPositionLimit, -10.0)  # the rail changes no height
    upper = np.minimum(model.upperPositionLimit, 10.0)
    heights = [
        abs(_positions(model, q, ["flange"])[0][2])
        for q in rng.uniform(lower, upper, (20000, model.nq))
    ]
    assert max(heights) <= reach.maximum + 1e-9
    assert max(heights) > reach.maximum - 0.05
    assert arm_reach(load_robot("ur5")).across is None


@pytest.mark.parametrize("kind", ["position", "pose"])
def test_a_target_far_above_the_arm_is_out_of_reach(frankie, kind):
    robot, _, _ = frankie
    position = np.array([0.3, -0.2, 10.0])
    target = PositionTarget(position) if kind == "position" else PoseTarget(position, np.eye(3))
    result = get_solver(robot).solve(target, timeout=NO_CAP)
    assert result.status == "out_of_reach", result.message
    assert result.iterations <= OUT_OF_REACH_STEPS


def test_a_target_far_along_the_rail_is_still_found(frankie):
    robot, model, _ = frankie
    position = np.array([-40.0, 25.0, 0.6])
    result = get_solver(robot).solve(PositionTarget(position), timeout=NO_CAP)
    assert result.status == "ok", result.message
    tool = _positions(model, result.solutions[0].q, ["flange"])[0]
    assert np.linalg.norm(tool - position) < 1e-5


def _clear_and_on_target(model: pin.Model, q: np.ndarray, position: np.ndarray) -> None:
    tool = _positions(model, q, ["flange"])[0]
    assert np.linalg.norm(tool - position) < 1e-5
    for centre in _positions(model, q, SPHERE_LINKS):
        outside = np.maximum(np.abs(centre - np.asarray(BOX)) - SIDE / 2, 0.0)
        assert np.linalg.norm(outside) > RADIUS


def test_random_starts_of_the_bounded_solve_find_a_free_answer(frankie):
    """No start given: the random starts alone, drawn near the arm, find a free answer."""
    robot, model, checker = frankie
    position = np.array([0.45, 0.25, 0.7])
    result = DistanceBoundedIK(robot, checker).solve(PositionTarget(position), [])
    assert result.status == "ok", result.message
    _clear_and_on_target(model, result.solutions[0].q, position)


def test_collision_aware_ik_on_the_long_rail_finds_answers(frankie):
    """Targets beside the box whose plain answer collides: the bounded solve finds free ones."""
    robot, model, checker = frankie
    plain = get_solver(robot)
    aware = CollisionAwareSolver(plain, checker)
    for position in ([0.5, 0.0, 0.95], [0.75, 0.0, 0.75], [0.65, 0.0, 0.6]):
        target = PositionTarget(np.array(position))
        assert checker.in_collision(plain.solve(target, timeout=NO_CAP).solutions[0].q)
        result = aware.solve(target, timeout=NO_CAP)
        assert (result.status, result.method) == ("ok", "collision_bound"), result.message
        _clear_and_on_target(model, result.solutions[0].q, np.array(position))


def test_the_collision_aware_extra_starts_draw_the_rail_near_the_arm(frankie):
    """Its extra starts' box: the rail within the arm's size (summed by hand), the rest kept."""
    robot = frankie[0]
    lower, upper = _limits(robot)
    size = sum(abs(x) for xyz, *_ in PANDA for x in xyz) + 0.15 + 0.38 + 0.107
    rail = robot.joint_names.index("base_rail")
    assert (lower[rail], upper[rail]) == pytest.approx((-size, size), abs=1e-9)
    others = [i for i in range(robot.nq) if i != rail]
    assert np.array_equal(lower[others], robot.lower[others])
    assert np.array_equal(upper[others], robot.upper[others])
    ur5 = load_robot("ur5")
    assert np.array_equal(_limits(ur5)[0], np.where(np.isfinite(ur5.lower), ur5.lower, -np.pi))
