"""Stages 2-3 of the numeric pipeline: random restarts and mink QP runs, a fixed number of them.

When the nearest starts fail: ``random_starts`` cheap damped Newton runs from random joint vectors
inside the limits (drawn from ``random_seed``; a long rail's within the arm's size,
:mod:`.sampling_box`), then mink QP runs with hard limits
(:mod:`kin.ik.numeric.differential_ik`, ``qp_iterations`` steps, the first from the best
configuration so far) each followed by a damped Newton polish, with ``random_between`` random
starts between two QP runs, until the search has made ``max_attempts`` starts
(:data:`~.settings.MAX_ATTEMPTS`). Out of reach, the QP run comes first (it finds the closest
configuration) and ``nearest + 3`` starts end it. Without a solution, a last QP run from the best
configuration tightens it. The MuJoCo model of the QP runs is loaded on the first run, whatever
the time left; the cap (:meth:`~.search.Search.expired`) is checked before each start and after
each QP run, and stops the search (``timeout``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..result import IKResult

if TYPE_CHECKING:
    from .context import NumericContext
    from .damped_newton import NewtonOutcome
    from .search import Search

#: :attr:`IKResult.method` of a random start, and of a mink QP run (with its Newton polish).
RANDOM_RESTART = "random_restart"
MINK_QP = "mink_qp"


def solve_with_restarts(ik: NumericContext, search: Search) -> IKResult | None:
    """Random starts and mink QP runs; the first verified result, else None.

    At least one start, then until ``search.max_attempts`` starts in all (or the cap); seeded by
    ``search.random_seed`` (reproducible).
    """
    rng = np.random.default_rng(search.random_seed)
    max_attempts = search.max_attempts
    fallback = qp_runs = 0
    nearest_best = search.best
    out_of_reach = search.out_of_reach
    while not search.expired():
        k = fallback if out_of_reach else fallback - ik.settings.random_starts
        use_qp = k >= 0 and k % (ik.settings.random_between + 1) == 0
        fallback += 1
        if use_qp and not qp_runs and nearest_best is not None:
            q_next = nearest_best.q  # the first run: from the nearest starts' best
        else:
            q_next = rng.uniform(ik.draw_lower, ik.draw_upper)
        if use_qp:
            qp_runs += 1
            q_next, steps = _qp_run(ik, search, q_next)
            if search.expired():  # the cap came during the QP run: its end is not the work's
                break
            outcome = search.newton(q_next, None)
            label = f"mink QP ({steps} steps) + damped Newton"
        else:
            outcome = search.newton(q_next, ik.settings.random_patience)
            label = "damped Newton from a random start"
        method = MINK_QP if use_qp else RANDOM_RESTART
        done = search.accept(outcome, method, f"{label}, attempt {search.attempts}", use_qp)
        if done is not None:
            return done
        if out_of_reach and search.attempts > ik.settings.nearest + 2:
            break
        if search.attempts >= max_attempts:
            break
    return None


def polish_best(ik: NumericContext, search: Search) -> IKResult | None:
    """A last mink QP run from the best configuration (a random start's, stopped early)."""
    best = search.best
    if best is None or search.best_from_qp or search.expired():
        return None
    q, _ = _qp_run(ik, search, best.q)
    if search.expired():
        return None
    outcome: NewtonOutcome = search.newton(q, None)
    return search.accept(outcome, MINK_QP, "mink QP from the best", from_qp=True)


def _qp_run(ik: NumericContext, search: Search, q0: np.ndarray) -> tuple[np.ndarray, int]:
    """Run mink QP steps from ``q0``: the final joint vector and the steps taken.

    The MuJoCo model is loaded on the first run (about 0.2 s once per solver), whatever the time
    left; the run stops at the cap too (the caller then asks :meth:`~.search.Search.expired`).
    """
    differential = ik.differential
    differential.set_target(search.target)
    qp = differential.solve(
        q0,
        ik.settings.qp_iterations,
        search.inner_position_tol,
        search.inner_rotation_tol,
        search.deadline,
    )
    search.iterations += qp.iterations
    return qp.q, qp.iterations
