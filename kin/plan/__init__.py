"""Collision-free motion planning (OMPL): from where the arm is to a joint vector or any IK target.

:func:`plan` returns a :class:`PlanResult` whose path is certified collision-free between its
samples by :mod:`kin.path.collision_check`'s rule. See ``docs/planning.md``.
"""

from .ompl_problem import prepare
from .planner import DEFAULT_CHECKS, DEFAULT_PLANNER, PLANNERS, PlanError, plan
from .result import STATUSES, PlanResult, PlanStatus

__all__ = [
    "DEFAULT_CHECKS",
    "DEFAULT_PLANNER",
    "PLANNERS",
    "STATUSES",
    "PlanError",
    "PlanResult",
    "PlanStatus",
    "plan",
    "prepare",
]
