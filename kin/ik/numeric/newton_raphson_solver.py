"""The paper's Newton-Raphson IK (position only, no limits) behind the common solver interface.

The ``nr`` row of the solver table (:mod:`kin.ik.solver_table`), ``kin ik --solver nr``.
"""

from __future__ import annotations

from typing import Any

import numpy.typing as npt

from ...robot_model import RobotModel
from ..exceptions import TargetError
from ..result import IKResult
from ..routing import REFUSED, own_search_routes
from ..targets.target import PositionTarget


class NewtonRaphsonSolver:
    """The paper's Newton-Raphson IK behind the common solver interface.

    Args:
        robot: The robot.
    """

    name = "nr"
    #: A position, by its one run (:func:`kin.ik.routing.own_search_routes`); no other kind.
    routes = own_search_routes((PositionTarget,))
    target_kinds: tuple[type, ...] = routes.kinds
    #: ``route(target)``: its one run, or none (:meth:`kin.ik.routing.Routes.of`).
    route = routes.of
    #: No closed form, no numeric or partial-pose solver behind it: one run from the seed.
    closed_form_kinds: tuple[type, ...] = ()
    numeric = None
    partial = None

    def __init__(self, robot: RobotModel):
        self.robot = robot

    def batch_route(self) -> None:
        """None: a batch solves target by target."""
        return None

    def solve(
        self,
        target: Any,
        seed: npt.ArrayLike | None = None,
        *,
        timeout: float | None = None,
        all_branches: bool = False,
    ) -> IKResult:
        """Solve a position target from ``seed`` [rad] (q = 0 if None).

        ``timeout`` and ``all_branches`` are unused (one run, one answer).

        Raises:
            TargetError: Not a position target.
        """
        from .newton_raphson import newton_raphson

        if self.routes.of(target) is REFUSED:
            raise TargetError(
                "--solver nr is the paper's position-only method: drop --rpy/--quat/--pitch"
            )
        return newton_raphson(self.robot, target.position, seed)
