"""Which part of a solver answers each kind of target: the routes, decided here once.

Every solver of the table (:mod:`.solver_table`) holds its :class:`Routes`, built by one rule of
this module when the solver is built, and asks them in each solve; the collision search asks
the wrapped solver's (:meth:`kin.ik.solver.IKSolver.route`). No other module decides by a
target's kind which part answers it.

=============  ===================================================================================
route (value)  what answers
=============  ===================================================================================
``TWIN``       the closed form's compiled twin: a whole pose solved, moved into the limits and
               measured in one C call (:mod:`.analytic.six_r.six_r_twin`)
``CLOSED``     the closed form: every branch in one solve
``BRANCHES``   a whole pose on an arm of fewer than six joints whose closed form solves positions
               or projects poses: its branches measured on the whole pose, then ``SHORT``
``SHORT``      the partial-pose solver (:mod:`.partial_pose`) of a whole pose on an arm of fewer
               than six joints: the nearest pose it reaches, or the pose
``PARTIAL``    the partial-pose solver of a target that leaves components free (an axis target,
               a masked pose): every roll of its sweep is a further answer
``NUMERIC``    a search near the seed (the numeric pipeline, Newton-Raphson, the mimic descent)
``REFUSED``    none: a :class:`~kin.ik.TargetError` names the kinds the solver takes
=============  ===================================================================================

Each route is a constant of this module whose value is its name in lower case (``CLOSED`` is
``"closed_form"``). A masked pose is ``PARTIAL`` wherever a partial-pose solver is, else ``REFUSED``. Routes are per
target class (a subclass of a kind is routed as its rule says, by ``issubclass``) and, for a
:class:`~.targets.target.PoseTarget`, whether it has a mask.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Final, Literal

from .targets.target import AxisTarget, PitchTarget, PoseTarget, PositionTarget

__all__ = [
    "BRANCHES",
    "CLOSED",
    "NUMERIC",
    "PARTIAL",
    "REFUSED",
    "ROUTES",
    "SHORT",
    "TWIN",
    "Route",
    "Routes",
    "closed_form_routes",
    "numeric_routes",
    "own_search_routes",
]


#: The part of a solver that answers a target (see the module's table): one of the names below,
#: compared by ``is`` on the solvers' fast paths (a name, like :attr:`IKResult.status`, costs no
#: enum lookup there).
Route = Literal["twin", "closed_form", "branches", "short", "partial", "numeric", "refused"]
TWIN: Final = "twin"
CLOSED: Final = "closed_form"
BRANCHES: Final = "branches"
SHORT: Final = "short"
PARTIAL: Final = "partial"
NUMERIC: Final = "numeric"
REFUSED: Final = "refused"
#: Every route, in the module table's order.
ROUTES: tuple[Route, ...] = (TWIN, CLOSED, BRANCHES, SHORT, PARTIAL, NUMERIC, REFUSED)


#: The target classes every solver is routed for when built (others on first use).
KNOWN_KINDS = (PositionTarget, PoseTarget, PitchTarget, AxisTarget)


class _ByClass(dict[type, Route]):
    """The routes of an unmasked target by its class.

    The known kinds' are made when built; any other class's by the rule when first asked (a
    user's subclass; a wrong object: ``REFUSED``).
    """

    def __init__(self, rule: Callable[[type], Route], kinds: tuple[type, ...]) -> None:
        super().__init__((kind, rule(kind)) for kind in kinds)
        self._rule = rule

    def __missing__(self, cls: type) -> Route:
        route = self[cls] = self._rule(cls)  # the same route whichever thread asks first
        return route


@dataclass(frozen=True)
class Routes:
    """One solver's routes, built by a rule of this module.

    The rules: :func:`closed_form_routes`, :func:`numeric_routes`, :func:`own_search_routes`.

    Attributes:
        kinds: The target classes the solver takes (its ``target_kinds``; the error of another
            names them).
        masked: The route of a masked :class:`~.targets.target.PoseTarget`.
        by_class: The route of an unmasked target, by its class (``by_class[cls]``: a plain
            subscript, no call, on the solvers' fast paths).
    """

    kinds: tuple[type, ...]
    masked: Route
    by_class: Mapping[type, Route] = field(repr=False)

    def of(self, target: object) -> Route:
        """The route of ``target``."""
        cls = target.__class__
        if cls is PoseTarget and target.mask is not None:  # type: ignore[attr-defined]
            return self.masked
        return self.by_class[cls]


def _routes(kinds: tuple[type, ...], masked: Route, rule: Callable[[type], Route]) -> Routes:
    return Routes(kinds, masked, _ByClass(rule, (*KNOWN_KINDS, *kinds)))


def closed_form_routes(solved: tuple[type, ...], nq: int, *, projects: bool, twin: bool) -> Routes:
    """The routes of a closed-form solver (:class:`~.analytic.closed_form.ClosedFormSolver`).

    Args:
        solved: The target classes its structure solves (``structure.target_kinds``).
        nq: The arm's number of joints.
        projects: The structure projects a pose on the poses the arm reaches (a SCARA's).
        twin: The structure has a compiled twin that verifies, and it is used.

    The kinds it takes: the structure's, a position and a whole pose (the numeric solver or the
    partial-pose solver answer those it does not), an axis target (the partial-pose solver).
    A whole pose goes to the partial-pose solver on an arm of fewer than six joints (``SHORT``),
    unless the closed form takes poses without projecting them (a five-joint arm's takes them,
    with its own reasons); it is first measured on the closed form's branches when the closed
    form solves positions only or projects poses (``BRANCHES``).
    """
    takes = solved if PositionTarget in solved else (*solved, PositionTarget)
    takes = (*takes, *(kind for kind in (PoseTarget, AxisTarget) if kind not in takes))
    short = nq < 6 and not (PoseTarget in solved and not projects)
    by_branches = (PositionTarget in solved and PoseTarget not in solved) or projects

    def rule(cls: type) -> Route:
        if cls is PoseTarget:
            if twin:
                return TWIN
            if short:
                return BRANCHES if by_branches else SHORT
        elif cls is AxisTarget and AxisTarget not in solved:
            return PARTIAL
        if issubclass(cls, solved):
            return CLOSED
        return NUMERIC if issubclass(cls, takes) else REFUSED

    return _routes(takes, PARTIAL, rule)


def numeric_routes(nq: int, kinds: tuple[type, ...]) -> Routes:
    """The routes of the numeric pipeline (:class:`~.numeric.solver.NumericIK`).

    Args:
        nq: The arm's number of joints.
        kinds: The target classes it takes (a position, a whole pose, an axis target, its
            numeric target with a posture).

    A whole pose on an arm of fewer than six joints and an axis target go to the partial-pose
    solver; every other kind it takes to the search.
    """

    def rule(cls: type) -> Route:
        if cls is PoseTarget and nq < 6:
            return SHORT
        if cls is AxisTarget:
            return PARTIAL
        return NUMERIC if issubclass(cls, kinds) else REFUSED

    return _routes(kinds, PARTIAL, rule)


def own_search_routes(kinds: tuple[type, ...]) -> Routes:
    """The routes of a solver that is one search of its own (Newton-Raphson, the mimic descent).

    ``kinds``: the target classes it takes, each answered by its search; a masked pose and every
    other kind refused.
    """

    def rule(cls: type) -> Route:
        return NUMERIC if issubclass(cls, kinds) else REFUSED

    return _routes(kinds, REFUSED, rule)
