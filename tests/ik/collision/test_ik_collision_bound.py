"""The distance bound inside the numeric solve (kin/ik/collision/collision_bound.py).

Judged apart from the code under test: the distance Jacobians against central differences of
coal's distances; every answer's clearance by the direct coal check of the maker's URDF
(tests/support/collision_reference.py) and its tool pose by Pinocchio's forward kinematics of that URDF
(not the DH model the solver uses).
"""

from __future__ import annotations

import threading
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.blocked_case import (
    SRDF,
    TIP,
    URDF,
    _blocked_case,
    _box_scene,
    _clearance,
    _reference,
    _tool,
)
from support.solver_caps import NO_CAP
from support.urdf_reference import erd

import kin
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.distance_jacobian import pair_rows
from kin.ik import AxisTarget, PoseTarget, PositionTarget
from kin.ik.collision.collision_aware import CollisionAwareSolver
from kin.ik.collision.collision_bound import METHOD, DistanceBoundedIK, held_in_scene, solve_clear
from kin.ik.collision.distance_bound import DistanceBound
from kin.ik.numeric.solver import NumericIK

#: Overlap the reference may find at a free answer [m] (its shapes are the checker's hulls).
CONTACT_TOL = 1e-6


@pytest.fixture(scope="module")
def panda():
    """(robot, URDF text, URDF path, base link) of the maker's Panda (example-robot-data)."""
    robot = kin.load_robot(erd(URDF), None, TIP)
    path, base, _ = robot.urdf_source
    return robot, Path(path).read_text(encoding="utf-8"), Path(path), base


def test_distance_jacobians_match_finite_differences(panda, tmp_path):
    """d d/d q of every pair (apart and overlapping) equals central differences of coal's distance."""
    robot = panda[0]
    scene = _box_scene(tmp_path / "box.toml", (0.3, 0.0, 0.5), 0.3)
    checker = CollisionChecker(load_collision_model(robot, srdf=erd(SRDF), scene=scene))
    model, geometry_model = robot.model, checker.model.geometry_model

    def distances(q):
        data, geometry_data = model.createData(), pin.GeometryData(geometry_model)
        pin.computeDistances(model, data, geometry_model, geometry_data, q)
        return np.array([r.min_distance for r in geometry_data.distanceResults])

    rng = np.random.default_rng(2)
    overlapping = 0
    for _ in range(20):
        q = rng.uniform(robot.lower, robot.upper)
        data, geometry_data = model.createData(), pin.GeometryData(geometry_model)
        pin.computeJointJacobians(model, data, q)
        pin.updateGeometryPlacements(model, data, geometry_model, geometry_data)
        pin.computeDistances(geometry_model, geometry_data)
        d, rows, smallest = pair_rows(model, data, geometry_model, geometry_data, 0.0, np.inf)
        np.testing.assert_allclose(d, distances(q), atol=1e-12)
        assert smallest == pytest.approx(d.min())
        eps = 1e-6
        columns = [
            (distances(q + eps * e) - distances(q - eps * e)) / (2 * eps) for e in np.eye(robot.nq)
        ]
        np.testing.assert_allclose(rows, np.array(columns).T, atol=1e-5)
        overlapping += int((d < 0).sum())
    assert overlapping > 0  # the overlapping pairs' normals were checked too


def test_bounded_solve_finds_a_free_answer_on_target(panda, tmp_path):
    """Panda, a box through the plain answer's forearm: the bounded solve's answer is free and on target."""
    target, seed, answer, checker, reference, pairs = _blocked_case(panda, tmp_path)
    assert _clearance(reference, pairs, answer) < -0.005  # the plain answer goes through the box
    result = DistanceBoundedIK(panda[0], checker).solve(target, [seed, answer])
    assert result.status == "ok" and result.method == METHOD, result.message
    q = result.solutions[0].q
    assert _clearance(reference, pairs, q) > -CONTACT_TOL
    T = _tool(reference, q)
    assert np.linalg.norm(T.translation - target.position) < 1e-5
    assert np.linalg.norm(pin.log3(T.rotation.T @ target.rotation)) < 1e-4
    assert np.all(q >= panda[0].lower) and np.all(q <= panda[0].upper)


def test_bounded_solve_gives_the_same_answer_under_load(panda, tmp_path):
    """Work, not time, decides: a busy thread beside the solve changes nothing in its answer."""
    target, seed, answer, checker, _, _ = _blocked_case(panda, tmp_path)
    solver = DistanceBoundedIK(panda[0], checker)
    idle = solver.solve(target, [seed, answer])
    stop = threading.Event()

    def busy() -> None:
        x = np.random.default_rng(0).normal(size=(200, 200))
        while not stop.is_set():
            x = np.tanh(x @ x.T / 200.0)

    thread = threading.Thread(target=busy)
    thread.start()
    try:
        loaded = solver.solve(target, [seed, answer])
    finally:
        stop.set()
        thread.join()
    assert idle.status == loaded.status == "ok"
    assert idle.iterations == loaded.iterations
    np.testing.assert_array_equal(idle.solutions[0].q, loaded.solutions[0].q)


def test_collision_aware_numeric_uses_the_bound(panda, tmp_path):
    """CollisionAwareSolver over a numeric solver: the bounded solve answers, free by the reference."""
    target, seed, answer, checker, reference, pairs = _blocked_case(panda, tmp_path)
    numeric = NumericIK(panda[0], closed_form=False)
    aware = CollisionAwareSolver(numeric, checker)
    result = aware.solve(target, answer)  # the plain answer's start: the first solve collides
    assert result.status == "ok", result.message
    assert result.method == METHOD
    assert any(s.reason for s in result.rejected)  # the first answer, rejected with its reason
    for s in result.solutions:
        assert _clearance(reference, pairs, s.q) > -CONTACT_TOL
        T = _tool(reference, s.q)
        assert np.linalg.norm(T.translation - target.position) < 1e-5


@pytest.mark.parametrize("kind", ["axis", "mask", "position"])
def test_partial_targets_through_the_bound(panda, tmp_path, kind):
    """An axis target, a pose with its yaw left free and a position get a free answer on target."""
    target, seed, answer, checker, reference, pairs = _blocked_case(panda, tmp_path)
    if kind == "axis":
        partial = AxisTarget(target.position, target.rotation[:, 2])
    elif kind == "mask":
        partial = PoseTarget(target.position, target.rotation, mask=(1, 1, 1, 1, 1, 0))
    else:
        partial = PositionTarget(target.position)
    result = DistanceBoundedIK(panda[0], checker).solve(partial, [seed, answer])
    assert result.status == "ok", result.message
    q = result.solutions[0].q
    assert _clearance(reference, pairs, q) > -CONTACT_TOL
    T = _tool(reference, q)
    assert np.linalg.norm(T.translation - target.position) < 1e-5
    if kind == "axis":
        assert float(T.rotation[:, 2] @ target.rotation[:, 2]) > 1.0 - 1e-8
    elif kind == "mask":  # roll and pitch: the rotation error's world x and y components
        error = pin.log3(target.rotation @ T.rotation.T)
        assert np.abs(error[:2]).max() < 1e-4


def test_every_answer_colliding_stays_in_collision(panda, tmp_path):
    """A ball around the tool point: the bound finds nothing free; the status stays in_collision."""
    robot = panda[0]
    q = np.array([0.2, -0.3, 0.1, -2.0, 0.1, 1.8, 0.6])
    T = _tool(_reference(panda, None), q)
    target = PoseTarget(T.translation, T.rotation)
    path = tmp_path / "ball.toml"
    xyz = ", ".join(repr(float(v)) for v in T.translation)
    path.write_text(f'[[sphere]]\nname = "ball"\nradius = 0.12\nxyz = [{xyz}]\n')
    checker = CollisionChecker(load_collision_model(robot, srdf=erd(SRDF), scene=path))
    # The links the tool's joint carries: panda_link7 and, since the whole robot is checked
    # (issue 43, item 2), the hand and its held fingers beyond the tip frame.
    carried = ("panda_link7", "panda_hand", "panda_leftfinger", "panda_rightfinger")
    inside = _reference(panda, path).signed_distances(q, [(link, "ball") for link in carried])
    assert inside[("panda_link7", "ball")][0] < 0.0  # the link the tool carries is in the ball
    found = held_in_scene(robot, checker, q)
    link, _, obstacle = found.partition("/")
    assert link in carried and obstacle == "ball", found
    assert inside[(link, "ball")][0] < 0.0, found  # the reference puts the named link in it
    assert held_in_scene(robot, CollisionChecker(load_collision_model(robot)), q) == ""
    bounded = DistanceBoundedIK(robot, checker).solve(target, [q])
    assert bounded.status == "not_found" and not bounded.solutions
    assert bounded.iterations > 0 and bounded.rejected  # the work was done; the best run kept
    assert DistanceBoundedIK(robot, checker).solve(target, [q], timeout=0.0).status == "timeout"
    aware = CollisionAwareSolver(NumericIK(robot, closed_form=False), checker)
    result = aware.solve(target, q, timeout=NO_CAP)
    assert result.status == "in_collision", result.message
    stopped = aware.solve(target, q, timeout=1e-9)
    assert stopped.status == "timeout", stopped.message


@pytest.mark.parametrize(
    ("field", "value", "words"),
    [
        ("gain", 0.0, "DistanceBound.gain: 0.0 must be a finite number in (0, 1]"),
        ("margin", float("nan"), "DistanceBound.margin: nan must be"),
        ("influence", 0.001, "DistanceBound.influence: 0.001 must be a finite number > margin"),
        ("iterations", 0, "DistanceBound.iterations: 0 must be"),
        ("qp_solver", "cvx", "unknown QP solver 'cvx'; choose one of: daqp, osqp"),
    ],
)
def test_bad_bound_settings_name_the_field(field, value, words):
    """A bad setting raises IKError in one line naming the field, its value and its range."""
    with pytest.raises(kin.ik.IKError) as error:
        DistanceBound(**{field: value})
    assert words in str(error.value) and "\n" not in str(error.value)


def test_target_kinds(panda, tmp_path):
    """A posture-preference target is solved as its pose; a kind the bound lacks is named."""
    from kin.ik import PitchTarget
    from kin.ik.numeric.numeric_target import NumericTarget

    target, seed, answer, checker, reference, pairs = _blocked_case(panda, tmp_path)
    preferred = NumericTarget.from_arrays(target.position, target.rotation, seed)
    result = solve_clear(panda[0], checker, preferred, seed, [], None)
    assert result is not None and result.status == "ok", result
    q = result.solutions[0].q
    assert _clearance(reference, pairs, q) > -CONTACT_TOL
    assert np.linalg.norm(_tool(reference, q).translation - target.position) < 1e-5
    pitch = PitchTarget(target.position, 0.3)
    assert solve_clear(panda[0], checker, pitch, seed, [], None) is None
    with pytest.raises(kin.ik.TargetError, match="pose, position or axis target"):
        DistanceBoundedIK(panda[0], checker).solve(pitch, [seed])
