"""IK takes any target and seed in stride, on every shipped robot (hypothesis).

Target components are drawn from zeros, denormals, ordinary values, 1e3, 1e200, 1e308, NaN and
infinities; rotations are proper, nearly orthonormal (printed with six decimals), sheared,
mirrored or non-finite; seeds are absent, inside or outside the limits, huge or NaN. Through the
library, ``kin ik`` and ``kin ik --stdin``: never an exception other than the package's own, never
a traceback, never a success that Pinocchio's forward kinematics of the answer (an independent
``Configuration``, not the solver's judge) finds off target or outside the limits; a target
farther than the links laid end to end is ``out_of_reach`` without a search.
"""

from __future__ import annotations

import functools
import io
import json
import math
import warnings

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dh2urdf import ROBOTS
from kin import Configuration, KinError, load_robot
from kin.commands import ik
from kin.ik import PoseTarget, PositionTarget, TargetError, get_solver
from kin.ik.reach import reach_bound

NAMES = tuple(ROBOTS)

#: The values the issue names, signs included.
SPECIAL = st.sampled_from(
    [0.0, -0.0, 5e-324, -5e-324, 1e-300, 1e3, -1e3, 1e200, -1e200, 1e308, -1e308]
    + [math.nan, math.inf, -math.inf]
)
COMPONENT = st.one_of(SPECIAL, st.floats(min_value=-1.5, max_value=1.5))
POSITION = st.lists(COMPONENT, min_size=3, max_size=3)
ROTATION_KIND = st.sampled_from(["proper", "printed", "sheared", "mirrored", "nan", "huge"])
SEED_KIND = st.sampled_from(["none", "inside", "outside", "huge", "nan"])
SETTINGS = settings(
    max_examples=25,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


@functools.cache
def _solver(name: str):
    return get_solver(load_robot(name))


def _rotation(kind: str, angles: tuple[float, float, float]) -> np.ndarray:
    rotation = pin.rpy.rpyToMatrix(*angles)
    if kind == "printed":
        return np.round(rotation, 6)
    if kind == "sheared":
        return rotation + np.array([[0, 0.2, 0], [0, 0, 0], [0, 0, 0]])
    if kind == "mirrored":
        return rotation @ np.diag([1.0, 1.0, -1.0])
    if kind == "nan":
        rotation = rotation.copy()
        rotation[1, 2] = math.nan
    if kind == "huge":
        return rotation * 1e308
    return rotation


def _seed(kind: str, robot, fraction: float) -> np.ndarray | None:
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    if kind == "none":
        return None
    if kind == "inside":
        return lower + fraction * (upper - lower)
    if kind == "outside":
        return upper + 1.0 + fraction
    if kind == "huge":
        return np.full(robot.nq, 1e308 * (1 if fraction > 0.5 else -1))
    return np.full(robot.nq, math.nan)


def _check_answer(robot, target, result) -> None:
    """A success is on target and inside the limits by an independent Pinocchio FK."""
    configuration = Configuration(robot)
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    for solution in result.solutions:
        q = np.asarray(solution.q, dtype=float)
        assert np.all(q >= lower - 1e-12) and np.all(q <= upper + 1e-12), f"{robot.name=} {q=}"
        reached = configuration.fk(q)
        assert np.linalg.norm(reached.translation - target.position) < 1e-5, f"{robot.name=}"
        if isinstance(target, PoseTarget):
            angle = np.linalg.norm(pin.log3(reached.rotation.T @ target.rotation))
            assert angle < 1e-4, f"{robot.name=} {angle=}"
    distance = math.hypot(*(target.position - robot.table.T_world_base[:3, 3]).tolist())
    if distance > reach_bound(robot) * (1 + 1e-9):
        assert result.status == "out_of_reach" and not result.success, f"{robot.name=}"
        assert result.iterations == 0, "searched although surely out of reach"


@pytest.mark.parametrize("name", NAMES)
@SETTINGS
@given(
    position=POSITION,
    full=st.booleans(),
    rotation_kind=ROTATION_KIND,
    angles=st.tuples(*[st.floats(-math.pi, math.pi)] * 3),
    seed_kind=SEED_KIND,
    fraction=st.floats(0.0, 1.0),
)
def test_library_answers_or_raises_its_own_error(
    name, position, full, rotation_kind, angles, seed_kind, fraction
):
    """solve() of any values: an IKResult, or a TargetError (never another exception)."""
    robot = load_robot(name)
    solver = _solver(name)
    try:
        target = (
            PoseTarget(position, _rotation(rotation_kind, angles))
            if full
            else PositionTarget(position)
        )
    except TargetError:
        finite = all(map(math.isfinite, position))
        assert not finite or (full and rotation_kind != "proper"), f"{position=}"
        return
    seed = _seed(seed_kind, robot, fraction)
    try:
        result = solver.solve(target, seed, timeout=0.02)
    except KinError as err:
        assert isinstance(err, TargetError), f"{type(err).__name__}: {err}"
        return
    _check_answer(robot, target, result)


@pytest.mark.parametrize("name", NAMES)
def test_far_targets_answer_out_of_reach_at_once(name):
    """1e308, 1e200 and 1e3 m away: out_of_reach without a search (20 us; 50 ms allowed)."""
    solver = _solver(name)
    solver.solve(PositionTarget([1e3, 0, 0]), timeout=0.05)  # the reach, once
    kinds = [PositionTarget] + ([PoseTarget] if PoseTarget in solver.target_kinds else [])
    for value in (1e308, -1e200, 1e3):
        for kind in kinds:
            target = (
                PositionTarget([value, value, 0])
                if kind is PositionTarget
                else PoseTarget([value, 0, -value], np.eye(3))
            )
            result = solver.solve(target, timeout=0.05)
            assert result.status == "out_of_reach", f"{name=} {value=} {result.message}"
            assert result.distance_to_workspace is not None and result.distance_to_workspace > 0
            assert not result.iterations, f"{name=} {value=} {result.iterations=}"  # no search


@pytest.mark.parametrize("name", NAMES)
def test_far_positions_warn_nothing(name):
    """A position 1e200 m away, seeded or not: out_of_reach, no search and no numeric warning.

    The 6R arms' near-seed route (position_near_seed) took its damped least-squares steps
    toward such a target first, and their products overflowed: a warning per process that
    ``kin ik --stdin`` printed on stderr amid the stream.
    """
    robot = load_robot(name)
    solver = _solver(name)
    for seed in (None, _seed("inside", robot, 0.3)):
        for value in (1e200, -1e308, 1e3):
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                result = solver.solve(PositionTarget([0.0, value, value]), seed, timeout=0.05)
            assert result.status == "out_of_reach", f"{name=} {value=} {result.message}"
            assert not result.iterations, f"{name=} {value=} {result.iterations=}"


def test_stdin_far_line_after_others_keeps_stderr_empty(monkeypatch, capsys):
    """kin ik --stdin: a line 1e200 m away after three others is answered; stderr stays empty."""
    lines = ['{"target": [0.0, 0.0, 0.0]}'] * 3 + ['{"target": [0.0, 0.0, 1e200]}']
    monkeypatch.setattr("sys.stdin", io.StringIO("\n".join(lines) + "\n"))
    ik.main(["--robot", "ur5", "--stdin", "--timeout", "20"])
    captured = capsys.readouterr()
    answers = [json.loads(line) for line in captured.out.splitlines()]
    assert [answer["line"] for answer in answers] == [1, 2, 3, 4]
    assert answers[3]["status"] == "out_of_reach" and captured.err == "", captured.err


def _number(value: float) -> str:
    return repr(float(value))


@pytest.mark.parametrize("name", NAMES)
@settings(
    max_examples=10,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(position=POSITION, full=st.booleans(), angles=st.tuples(*[SPECIAL] * 3))
def test_kin_ik_command_never_tracebacks(name, position, full, angles, capsys):
    """kin ik with any numbers: exit 0, 1 or 2; on 2 exactly one line on stderr."""
    argv = ["--robot", name, "--target", *map(_number, position), "--timeout", "20"]
    if full:
        argv += ["--rpy", *map(_number, angles)]
    try:
        code = ik.main(argv)
    except SystemExit as exit:  # argparse's one-line error
        code = exit.code
    captured = capsys.readouterr()
    assert code in (0, 1, 2), f"{argv=} {code=}"
    if code == 2:
        assert len(captured.err.strip().splitlines()) == 1, captured.err
        assert "Traceback" not in captured.err
    else:
        assert "Traceback" not in captured.err


@pytest.mark.parametrize("name", NAMES)
@settings(
    max_examples=5,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(
    lines=st.lists(
        st.tuples(POSITION, st.booleans(), st.tuples(*[SPECIAL] * 3), SEED_KIND),
        min_size=1,
        max_size=6,
    )
)
def test_stdin_stream_answers_every_line_in_order(name, lines, monkeypatch, capsys):
    """kin ik --stdin: exactly one JSON answer per input line, in order, whatever each holds."""
    robot = load_robot(name)
    text = []
    for position, full, angles, seed_kind in lines:
        # JSON allows NaN and Infinity as Python writes them: a hostile client may send them.
        record: dict = {"target": position}
        if full:
            record["rpy"] = list(angles)
        seed = _seed(seed_kind, robot, 0.3)
        if seed is not None:
            record["seed_q"] = seed.tolist()
        text.append(json.dumps(record))
    monkeypatch.setattr("sys.stdin", io.StringIO("\n".join(text) + "\n"))
    code = ik.main(["--robot", name, "--stdin", "--timeout", "20"])
    captured = capsys.readouterr()
    answers = [json.loads(line) for line in captured.out.splitlines()]
    assert [answer["line"] for answer in answers] == list(range(1, len(lines) + 1))
    failed = any("error" in answer or not answer["success"] for answer in answers)
    assert code == (1 if failed else 0) and captured.err == ""
    internal = [answer for answer in answers if "internal error" in answer.get("error", "")]
    assert not internal, internal
