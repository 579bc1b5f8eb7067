"""Stages 2-3 of the numeric pipeline: random restarts and mink QP runs, until the deadline.

When the nearest starts fail: ``random_starts`` cheap damped Newton runs from random joint vectors
inside the limits, then mink QP runs with hard limits (:mod:`kin.ik.numeric.differential_ik`,
the first from the best configuration so far) each followed by a damped Newton polish, with
``random_between`` random starts between two QP runs. Out of reach, the QP run comes first (it
finds the closest configuration). Stopped by ``max_attempts`` without a solution: a last QP run
from the best configuration tightens it.
"""

from __future__ import annotations

import time
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

#: Expected time to import mink and MuJoCo and compile the robot's MuJoCo model [s] (about
#: 0.17 s measured on a 2-core machine; counted with a margin).
MINK_COST = 0.3


def solve_with_restarts(ik: NumericContext, search: Search) -> IKResult | None:
    """Random starts and mink QP runs until the deadline; the first verified result, else None.

    Stopped early by ``search.max_attempts``; seeded by ``search.random_seed`` (reproducible).
    """
    rng = np.random.default_rng(search.random_seed)
    max_attempts = search.max_attempts
    fallback = qp_runs = 0
    nearest_best = search.best
    out_of_reach = search.out_of_reach
    while time.perf_counter() < search.deadline:
        k = fallback if out_of_reach else fallback - ik.random_starts
        use_qp = k >= 0 and k % (ik.random_between + 1) == 0
        fallback += 1
        if use_qp and not qp_runs and nearest_best is not None:
            q_next = nearest_best.q  # the first run: from the nearest starts' best
        else:
            q_next = rng.uniform(ik.lower, ik.upper)
        if use_qp:
            qp_runs += 1
            q_next, steps = _qp_run(ik, search, q_next)
            outcome = search.newton(q_next, None)
            label = f"mink QP ({steps} steps) + damped Newton"
        else:
            outcome = search.newton(q_next, ik.random_patience)
            label = "damped Newton from a random start"
        method = MINK_QP if use_qp else RANDOM_RESTART
        done = search.accept(outcome, method, f"{label}, attempt {search.attempts}", use_qp)
        if done is not None:
            return done
        if out_of_reach and search.attempts > ik.nearest + 2:
            break
        if max_attempts is not None and search.attempts >= max_attempts:
            break
    return None


def polish_best(ik: NumericContext, search: Search) -> IKResult | None:
    """A last mink QP run from the best configuration (a random start's, stopped early)."""
    best = search.best
    if best is None or search.best_from_qp or search.expired():
        return None
    q, _ = _qp_run(ik, search, best.q)
    outcome: NewtonOutcome = search.newton(q, None)
    return search.accept(outcome, MINK_QP, "mink QP from the best", from_qp=True)


def _qp_run(ik: NumericContext, search: Search, q0: np.ndarray) -> tuple[np.ndarray, int]:
    """Run mink QP steps from ``q0``: the final joint vector and the steps taken.

    The MuJoCo model is loaded on the first run when the call affords it (:data:`MINK_COST`
    before its hard end, :meth:`Search.affords`); else ``q0`` is returned as it is (0 steps) and
    the damped Newton run after it is one more start.
    """
    if not ik.differential_loaded and not search.affords(MINK_COST):
        return q0, 0
    differential = ik.differential
    differential.set_target(search.target)
    qp = differential.solve(
        q0,
        ik.qp_iterations,
        search.inner_position_tol,
        search.inner_rotation_tol,
        search.deadline,
    )
    search.iterations += qp.iterations
    return qp.q, qp.iterations
