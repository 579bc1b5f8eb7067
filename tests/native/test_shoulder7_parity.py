"""The compiled twin of the spherical-shoulder closed form changes nothing: same layout, same answers.

``kin/_native/ik/analytic/seven_r/_shoulder7.c`` declares its parameter layout once (``SHOULDER7_PARAMS``, exported
as ``LAYOUT``); :meth:`SphericalShoulder7RIK.c_fields` fills it by name. Over 1,000 Panda and
1,000 xArm7 full poses (FK of random joint vectors inside the limits), from the ready pose or
q = 0 and from random starts, with the default joint-7 scan steps: the twin's and the Python
``first`` pick the same start and the same joint vector, and the numeric solver with the twin and
with the Python module (``NumericIK(compiled=False)``) returns the same joint vectors.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from support.arm_tables import assert_layout_matches, tool_poses
from support.solver_caps import NO_CAP

from kin import load_robot
from kin.ik.analytic.seven_r.spherical_shoulder7 import COMPILED, SphericalShoulder7RIK
from kin.ik.numeric.numeric_target import NumericTarget
from kin.ik.numeric.solver import DEFAULT_CLOSED_FORM_STEPS, NumericIK

ROBOTS = ("panda", "xarm7")
TARGETS = 1000
#: Panda's limits exclude q = 0 (joints 4 and 6): it starts from its ready pose, as in the bench.
READY = {"panda": (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)}
#: Long enough that no stage runs out of time on a slow machine; ``max_attempts`` bounds the rest.
TIMEOUT = NO_CAP
#: Joint vectors of the twin and the Python module agree to this [rad].
TOL = 1e-12

needs_twin = pytest.mark.skipif(not COMPILED, reason="kin/ik/analytic/_shoulder7 not built")


@functools.cache
def solvers(name: str) -> tuple[NumericIK, NumericIK]:
    robot = load_robot(name)
    return NumericIK(robot, compiled=True), NumericIK(robot, compiled=False)


def closed_form(name: str) -> SphericalShoulder7RIK:
    ik = solvers(name)[0].closed_form
    assert isinstance(ik, SphericalShoulder7RIK), f"{name=}"
    return ik


def home(name: str) -> np.ndarray:
    """The bench's first start: the ready pose, or q = 0."""
    return np.array(READY.get(name, (0.0,) * 7), dtype=float)


@functools.cache
def targets(name: str, n: int, seed: int) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """Tool poses ``(position [m], R_world_tool)`` of random joint vectors inside the limits."""
    return tuple(tool_poses(load_robot(name), n, seed))


@pytest.mark.parametrize("name", ROBOTS)
def test_defaults_do_not_depend_on_the_twin(name):
    """Both solvers scan joint 7 on the same grid; only the ``compiled`` flag differs."""
    fast, plain = solvers(name)
    assert fast.closed_form_steps == plain.closed_form_steps == DEFAULT_CLOSED_FORM_STEPS
    assert plain.compiled is False
    assert fast.compiled is COMPILED  # its own twin decides, not humanoid7's
    assert isinstance(fast.closed_form, SphericalShoulder7RIK), f"{name=}"
    assert isinstance(plain.closed_form, SphericalShoulder7RIK), f"{name=}"


@needs_twin
@pytest.mark.parametrize("name", ROBOTS)
def test_layout_is_read_from_the_twin(name):
    """The C layout is contiguous, covers PARAM_COUNT values, and names exactly the Python fields
    with their sizes; ``c_params`` puts each field at the C offset."""
    from kin.ik.analytic.seven_r import _shoulder7

    assert_layout_matches(closed_form(name), _shoulder7)


@needs_twin
def test_twin_refuses_malformed_arguments():
    """Wrong shapes and a short target raise, as the Python path does for the starts."""
    ik = closed_form("panda")
    position, rotation = targets("panda", 1, seed=7)[0]
    prepared = ik.prepare(position, rotation)
    out = np.empty(7)
    with pytest.raises(ValueError, match="starts"):
        ik.first(prepared, np.zeros((2, 6)), out, 0.05)
    with pytest.raises(ValueError, match="starts"):
        ik.first(prepared, np.zeros((2, 6)), out, 0.05, compiled=False)
    with pytest.raises(ValueError, match="out"):
        ik.first(prepared, home("panda")[None], np.empty(6), 0.05)
    with pytest.raises(ValueError, match="12"):
        ik.first(prepared[:11], home("panda")[None], out, 0.05)


@pytest.mark.slow  # CI runs it; the default run stays under 5 minutes
@needs_twin
@pytest.mark.parametrize("name", ROBOTS)
def test_first_gives_the_same_start_and_joint_vector(name):
    """1,000 full poses, each from the home start then from random starts (one not finite, one
    a strided view, one outside the limits), at every default step and without a scan: the same
    index and the same joint vector (1e-12 rad)."""
    ik = closed_form(name)
    robot = load_robot(name)
    rng = np.random.default_rng(31)
    checked = found = 0
    for i, (position, rotation) in enumerate(targets(name, TARGETS, seed=130)):
        prepared = ik.prepare(position, rotation)
        wide = rng.uniform(robot.lower - 0.3, robot.upper + 0.3, size=(4, 7))
        wide[1, rng.integers(7)] = np.nan
        random = np.vstack((wide, rng.uniform(robot.lower, robot.upper, size=(3, 7))))
        blocks = (home(name)[None], random, np.asfortranarray(random), random[::2])
        for starts in blocks:
            for step in (*DEFAULT_CLOSED_FORM_STEPS, 0.0):
                a, b = np.full(7, np.nan), np.full(7, np.nan)
                index_a = ik.first(prepared, starts, a, step, compiled=True)
                index_b = ik.first(prepared, starts, b, step, compiled=False)
                context = f"{name=} target {i} {step=} {index_a=} {index_b=}"
                assert index_a == index_b, context
                if index_a >= 0:
                    gap = np.abs(a - b).max()
                    assert gap <= TOL, f"{context} {gap=}"
                    found += 1
                else:
                    assert np.isnan(a).all(), f"{context}: out written without a start"
                checked += 1
    # Most calls found a branch: the twin's solving was really compared, not only its refusals.
    assert found >= 0.8 * checked, f"{name=} {found=} {checked=}"


@needs_twin
@pytest.mark.parametrize("name", ROBOTS)
@pytest.mark.parametrize("start", ["home", "random"])
def test_numeric_solver_gives_the_same_joint_vectors(name, start):
    """1,000 full poses: the same success, method and joint vector (1e-12 rad) from both solvers."""
    fast, plain = solvers(name)
    robot = fast.robot
    rng = np.random.default_rng(140)
    answered = 0
    for i, (position, rotation) in enumerate(targets(name, TARGETS, seed=150)):
        seed = home(name) if start == "home" else rng.uniform(robot.lower, robot.upper)
        target = NumericTarget.from_arrays(position, rotation)
        a = fast.solve(target, seed, timeout=TIMEOUT, max_attempts=40)
        b = plain.solve(target, seed, timeout=TIMEOUT, max_attempts=40)
        context = f"{name=} {start} target {i}: {a.method=} {b.method=}"
        assert a.success and b.success, context
        assert a.method == b.method, context
        gap = np.abs(a.solutions[0].q - b.solutions[0].q).max()
        assert gap <= TOL, f"{context} {gap=}"
        answered += a.method == "closed_form_free_joint"
    # The closed form answered (nearly) all of them: the twin was really compared.
    assert answered >= 0.95 * TARGETS, f"{name=} {answered=}"
