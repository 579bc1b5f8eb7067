"""The frozen context of the numeric stages, built from a robot and the settings.

:func:`build_context` reads the robot once: its Pinocchio model and data, the tool frame, the
limits (as arrays and floats), the continuous joints, the reach bound, and the free-joint closed
form that fits the table (or its idealised twin). :class:`~.solver.NumericIK` builds one per
solver; the stages only read it (:class:`~.context.NumericContext`). Kept apart from
:mod:`.context` so that the stages, which import the context, never import :mod:`.free_joint`'s
builder through it (no import circle in ``kin/ik/numeric``).

Units: joint values [rad] (or [m] for prismatic joints), lengths [m].
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from kin import RobotModel

from ..analytic.idealised import Idealised, idealise
from ..judge import ToolJudge
from ..reach import reach_bound
from .context import NumericContext
from .damped_newton import COMPILED as COMPILED_STEP
from .differential_ik import import_mink
from .free_joint import (
    FreeJointClosedForm,
    SeededMany,
    compiled_seeded,
    compiled_seeded_many,
    free_joint_closed_form,
)
from .sampling_box import sampling_limits
from .settings import NumericSettings


def build_context(robot: RobotModel, settings: NumericSettings) -> NumericContext:
    """The frozen context of the numeric stages on ``robot`` with ``settings``.

    Joints without limits (``continuous`` rows) get limits of +-3 pi in the search model, so that
    damped Newton finds a solution across pi instead of clamping it away. The free-joint closed
    form, when asked for: the special forms on the true table, then on the idealised one (a
    rounded URDF); only then the general 7R form on the true table (slower, no compiled twin).
    Without a free-joint closed form, mink is imported here (once per process, about 0.3 s),
    not by the first call that falls back to a QP run; with one (humanoid7, Panda), which
    answers nearly every reachable pose, the import waits for a QP run (a one-shot command
    stays fast). So does a solver built inside a call (``prepare`` False: a closed form's
    numeric solver, built by the first target its closed form does not take).
    """
    model = robot.model
    data = model.createData()
    lower = model.lowerPositionLimit.copy()
    upper = model.upperPositionLimit.copy()
    continuous = tuple(i for i, row in enumerate(robot.table.rows) if row.continuous)
    search_model = model
    if continuous:
        search_model = model.copy()
        for i in continuous:
            search_model.lowerPositionLimit[i] = -3.0 * math.pi
            search_model.upperPositionLimit[i] = 3.0 * math.pi
    closed_form: FreeJointClosedForm | None = None
    idealised: Idealised | None = None
    if settings.closed_form:
        closed_form = free_joint_closed_form(robot.table, lower, upper, general=False)
        ideal = idealise(robot.table) if closed_form is None else None
        if ideal is not None:
            closed_form = free_joint_closed_form(ideal.table, lower, upper, general=False)
            idealised = ideal if closed_form is not None else None
        if closed_form is None:
            closed_form = free_joint_closed_form(robot.table, lower, upper)
    if closed_form is None and settings.prepare:
        import_mink()
    draw_lower, draw_upper = sampling_limits(robot.table, lower, upper)
    x, y, z = np.asarray(robot.table.T_world_base, dtype=float)[:3, 3].tolist()
    return NumericContext(
        settings=settings,
        robot=robot,
        nq=model.nq,
        judge=ToolJudge(robot, data),
        search_model=search_model,
        data=data,
        frame_id=model.getFrameId(robot.tool_frame),
        lower=lower,
        upper=upper,
        lows=tuple(lower.tolist()),
        highs=tuple(upper.tolist()),
        draw_lower=draw_lower,
        draw_upper=draw_upper,
        continuous=continuous,
        reach=reach_bound(robot),
        base_origin=(x, y, z),
        closed_form=closed_form,
        idealised=idealised,
        compiled=settings.compiled and closed_form is not None and closed_form.compiled_twin,
        compiled_step=settings.compiled and COMPILED_STEP,
    )


def compiled_stage0(context: NumericContext, solver: str) -> tuple[Any, SeededMany | None]:
    """Stage 0 from the caller's seed in one compiled call, a target's and a batch's.

    :func:`.free_joint.compiled_seeded` for a :class:`~kin.ik.PoseTarget` or
    :class:`~kin.ik.PositionTarget` (results named ``solver``) and
    :func:`.free_joint.compiled_seeded_many` (:func:`kin.ik.solve_batch`, ``kin ik --stdin``);
    ``(None, None)`` where the closed form has no compiled twin (the stages in Python).
    """
    closed, table, origin, reach = (
        context.closed_form,
        context.robot.table,
        context.base_origin,
        context.reach,
    )
    steps = context.settings.closed_form_steps
    seeded = compiled_seeded(closed, table, origin, reach, steps, solver)
    if seeded is None:
        return None, None
    lower, upper = context.lower, context.upper
    return seeded, compiled_seeded_many(closed, table, lower, upper, origin, reach)
