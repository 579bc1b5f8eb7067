"""The compiled twin of the seven-joint closed form changes nothing: same layout, same answers.

``kin/_native/ik/analytic/seven_r/_closed7.c`` declares its parameter layout once (``CLOSED7_PARAMS``, exported as
``LAYOUT``); :meth:`SevenDofIK.c_fields` fills it by name. The numeric solver with the twin and
with the Python module (``NumericIK(compiled=False)``) has the same defaults and returns the same
joint vectors over 1,000 humanoid7 targets, full pose and position.
"""

from __future__ import annotations

import numpy as np
import pytest
from support.arm_tables import assert_layout_matches, tool_poses
from support.solver_caps import NO_CAP

from kin import load_robot
from kin.ik.analytic.seven_r.seven_dof import COMPILED
from kin.ik.analytic.seven_r.subproblems import pack_params
from kin.ik.numeric.numeric_target import NumericTarget
from kin.ik.numeric.solver import DEFAULT_CLOSED_FORM_STEPS, NumericIK

ROBOT = "humanoid7"
TARGETS = 1000
#: Long enough that no stage runs out of time on a slow machine; ``max_attempts`` bounds the rest.
TIMEOUT = NO_CAP

needs_twin = pytest.mark.skipif(not COMPILED, reason="kin/ik/analytic/_closed7 not built")


@pytest.fixture(scope="module")
def solvers() -> tuple[NumericIK, NumericIK]:
    robot = load_robot(ROBOT)
    return NumericIK(robot, compiled=True), NumericIK(robot, compiled=False)


def test_defaults_do_not_depend_on_the_twin(solvers):
    """Both solvers scan joint 1 on the same grid; only the ``compiled`` flag differs."""
    fast, plain = solvers
    assert fast.closed_form_steps == plain.closed_form_steps == DEFAULT_CLOSED_FORM_STEPS
    assert fast.compiled is COMPILED
    assert plain.compiled is False
    assert fast.closed_form is not None and plain.closed_form is not None


@needs_twin
def test_layout_is_read_from_the_twin(solvers):
    """The C layout is contiguous, covers PARAM_COUNT values, and names exactly the Python fields
    with their sizes; ``c_params`` puts each field at the C offset."""
    from kin.ik.analytic.seven_r import _closed7

    assert_layout_matches(solvers[0].closed_form, _closed7)


def test_layout_mismatch_is_an_error(solvers):
    """``pack_params`` refuses a missing, resized, extra field or a gap."""
    fields = {"x": (1.0, 2.0), "y": (3.0,)}
    assert pack_params(fields, (("x", 0, 2), ("y", 2, 1))).tolist() == [1.0, 2.0, 3.0]
    for layout in (
        (("x", 0, 2),),  # y left over
        (("x", 0, 2), ("y", 2, 2)),  # wrong size
        (("x", 0, 2), ("y", 3, 1)),  # gap
        (("x", 0, 2), ("y", 2, 1), ("z", 3, 1)),  # missing in Python
    ):
        with pytest.raises(ValueError):
            pack_params(fields, layout)


@needs_twin
@pytest.mark.parametrize("kind", ["pose", "position"])
def test_same_joint_vectors_with_and_without_the_twin(solvers, kind):
    """1,000 targets: the same success, method and joint vector (1e-9 rad) from both solvers."""
    fast, plain = solvers
    closed_form = 0
    for i, (position, rotation) in enumerate(tool_poses(fast.robot, TARGETS, seed=120)):
        target = NumericTarget.from_arrays(position, rotation if kind == "pose" else None)
        a = fast.solve(target, timeout=TIMEOUT, max_attempts=40)
        b = plain.solve(target, timeout=TIMEOUT, max_attempts=40)
        context = f"{kind} target {i}: {a.method=} {b.method=}"
        assert a.success and b.success, context
        assert a.method == b.method, context
        gap = np.abs(a.solutions[0].q - b.solutions[0].q).max()
        assert gap < 1e-9, f"{context} {gap=}"
        closed_form += a.method == "closed_form_free_joint"
    # The closed form answered (nearly) all of them: the twin was really compared.
    assert closed_form >= 0.95 * TARGETS, f"{closed_form=}"
