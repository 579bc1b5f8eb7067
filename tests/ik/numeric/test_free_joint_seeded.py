"""Stage 0 from the caller's seed in one compiled call changes no answer.

``kin/_native/ik/analytic/seven_r/_seeded7.h`` (the twins' ``seeded``, bound by
:func:`kin.ik.numeric.free_joint.compiled_seeded`) does what the stages do from a seed: the target
in the structure's frames, the free-joint scan from the seed, each answer measured by the table's
DH product. Compared here with the same solver going through the Python stages (its compiled
call removed), and its errors with Pinocchio's.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support.arm_tables import tool_poses

from kin import load_robot
from kin.ik import PoseTarget, PositionTarget, TargetError
from kin.ik.analytic.seven_r.seven_dof import COMPILED as CLOSED7
from kin.ik.analytic.seven_r.spherical_shoulder7 import COMPILED as SHOULDER7
from kin.ik.numeric.solver import NumericIK

pytestmark = pytest.mark.skipif(not (CLOSED7 and SHOULDER7), reason="7R twins not built")


@pytest.fixture(scope="module", params=["humanoid7", "panda"])
def pair(request) -> tuple[NumericIK, NumericIK]:
    robot = load_robot(request.param)
    fast, slow = NumericIK(robot), NumericIK(robot)
    slow._seeded = None  # the Python stages only
    assert fast._seeded is not None
    return fast, slow


def poses(robot, n: int, seed: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``(position [m], R_world_tool, seed q)``: tool poses of random joint vectors inside the
    limits, seeds q = 0 and random ones in turn."""
    rng = np.random.default_rng(seed + 1)
    starts = [
        rng.uniform(robot.lower, robot.upper) if i % 2 else np.zeros(robot.nq) for i in range(n)
    ]
    return [(p, r, q) for (p, r), q in zip(tool_poses(robot, n, seed), starts, strict=True)]


def pinocchio_errors(robot, q: np.ndarray, position, rotation) -> tuple[float, float | None]:
    model, data = robot.model, robot.model.createData()
    pin.forwardKinematics(model, data, q)
    pose = pin.updateFramePlacement(model, data, model.getFrameId(robot.tool_frame))
    p = float(np.linalg.norm(pose.translation - position))
    if rotation is None:
        return p, None
    return p, float(np.linalg.norm(pin.log3(pose.rotation.T @ rotation)))


def test_compiled_seed_call_gives_the_stages_answers(pair):
    """300 poses from zero and random seeds: same method, message and joint vector (1e-9 rad);
    the errors it reports are Pinocchio's (1e-12)."""
    fast, slow = pair
    robot = fast.robot
    for i, (p, R, seed) in enumerate(poses(robot, 300, 5)):
        a = fast.solve(PoseTarget(p, R), seed)
        b = slow.solve(PoseTarget(p, R), seed)
        context = f"pose {i}: {a.method=} {b.method=} {a.message=} {b.message=}"
        assert a.success and b.success, context
        assert (a.method, a.message, a.status) == (b.method, b.message, b.status), context
        qa = a.solutions[0].q
        assert np.abs(qa - b.solutions[0].q).max() < 1e-9, context
        position_error, rotation_error = pinocchio_errors(robot, qa, p, R)
        assert abs(a.solutions[0].position_error - position_error) < 1e-12, context
        assert abs(a.solutions[0].rotation_error - rotation_error) < 1e-10, context
        assert np.all(qa >= robot.lower) and np.all(qa <= robot.upper), context


def test_compiled_seed_call_takes_positions_where_the_closed_form_does(pair):
    """humanoid7's closed form solves positions (joints 5-7 from the seed): the same answers;
    Panda's does not (the stages answer, as before)."""
    fast, slow = pair
    robot = fast.robot
    for i, (p, _, seed) in enumerate(poses(robot, 100, 6)):
        a = fast.solve(PositionTarget(p), seed)
        b = slow.solve(PositionTarget(p), seed)
        context = f"position {i}: {a.method=} {b.method=}"
        assert a.success == b.success and a.method == b.method, context
        assert a.message == b.message, context
        if a.success:
            assert np.abs(a.solutions[0].q - b.solutions[0].q).max() < 1e-9, context
            assert a.solutions[0].rotation_error is None
            error, _ = pinocchio_errors(robot, a.solutions[0].q, p, None)
            assert abs(a.solutions[0].position_error - error) < 1e-12, context


def test_what_the_compiled_call_does_not_take_goes_the_long_way(pair):
    """A bad seed is the same error; a list seed, a target beyond reach, tolerances no branch
    meets: the same results as the stages give."""
    fast, slow = pair
    robot = fast.robot
    p, R, _ = poses(robot, 1, 7)[0]
    for solver in pair:
        with pytest.raises(TargetError, match="finite"):
            solver.solve(PoseTarget(p, R), [math.nan] * 7)
        with pytest.raises(TargetError):
            solver.solve(PoseTarget(p, R), np.zeros(6))
    a, b = (s.solve(PoseTarget(p, R), [0.0] * 7) for s in pair)
    assert a.success and np.abs(a.solutions[0].q - b.solutions[0].q).max() < 1e-9
    far = p + np.array([10.0, 0.0, 0.0])
    a, b = (s.solve(PoseTarget(far, R), np.zeros(7)) for s in pair)
    assert a.status == b.status == "out_of_reach"
    # No closed-form branch within 1e-30 m: the compiled call says "tried" and the stages go on
    # from the samples, alike.
    kwargs = {"position_tol": 1e-30, "timeout": 10.0, "max_attempts": 2}
    a, b = (s.solve(PoseTarget(p, R), np.zeros(7), **kwargs) for s in pair)
    assert a.method != "closed_form_free_joint"
    assert (a.success, a.status, a.method) == (b.success, b.status, b.method)


@given(
    q=st.lists(st.floats(-3.0, 3.0), min_size=7, max_size=7),
    seed=st.one_of(
        st.lists(st.floats(allow_nan=True, allow_infinity=True, width=64), min_size=7, max_size=7),
        st.lists(st.floats(-1e308, 1e308), min_size=7, max_size=7),
    ),
    scale=st.sampled_from([1.0, 1.5, 3.0]),
)
@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
def test_hostile_seeds_and_far_targets_answer_as_the_stages_do(pair, q, seed, scale):
    """Any seed (NaN, infinite, 1e308) and targets out to three times as far: the compiled call
    and the stages give the same result or the same error, never a traceback of their own."""
    fast, slow = pair
    robot = fast.robot
    model, data = robot.model, robot.model.createData()
    pin.forwardKinematics(model, data, np.clip(np.array(q), robot.lower, robot.upper))
    pose = pin.updateFramePlacement(model, data, model.getFrameId(robot.tool_frame))
    target = PoseTarget(pose.translation * scale, pose.rotation)
    outcomes = []
    for solver in pair:
        try:
            # The work bound (3 starts) decides; the cap is far above it on a loaded machine.
            result = solver.solve(target, np.array(seed), timeout=60.0, max_attempts=3)
        except TargetError as err:
            outcomes.append(("error", str(err)))
            continue
        best = result.solutions[0].q if result.success else None
        outcomes.append((result.success, result.status, result.method, best))
    (a, b) = outcomes
    assert a[:3] == b[:3], (a, b)
    if a[0] == "error":
        assert a == b
    elif a[0] and a[2] == "closed_form_free_joint":
        assert np.abs(a[3] - b[3]).max() < 1e-9
