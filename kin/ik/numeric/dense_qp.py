"""One small dense QP with box bounds, for the steps of the distance-bounded solve.

::

    min  x^T P x / 2 + q^T x   s.t.  G x <= h,  lb <= x <= ub

``daqp`` (the default) is called directly, with the arrays qpsolvers' own ``daqp`` wrapper
would pass it (the box rows first, then ``G``; no lower bound on ``G x``): the same answers, without
importing qpsolvers (about 0.5 s of CPU at the first call: it loads every solver it finds) and
without its per-call checks (about 6 us of a 19 us solve of 7 variables). Another solver
(``osqp``) goes through qpsolvers' ``solve_qp``.
"""

from __future__ import annotations

from ctypes import c_int

import numpy as np

__all__ = ["solve_dense_qp"]

#: daqp's "no bound" value (qpsolvers' wrapper uses the same).
_FREE = -1e30


def solve_dense_qp(
    P: np.ndarray,
    q: np.ndarray,
    G: np.ndarray,
    h: np.ndarray,
    lb: np.ndarray,
    ub: np.ndarray,
    solver: str = "daqp",
) -> np.ndarray | None:
    """The minimizer, or None when the QP is infeasible (or the solver fails).

    Args:
        P: Cost matrix (n, n), symmetric positive definite.
        q: Cost vector (n,).
        G: Inequality rows (m, n), m may be 0.
        h: Inequality bounds (m,).
        lb: Lower bounds of ``x`` (n,).
        ub: Upper bounds of ``x`` (n,).
        solver: ``"daqp"`` (direct) or another qpsolvers name.
    """
    if solver != "daqp":
        from qpsolvers import solve_qp

        return solve_qp(P, q, G, h, lb=lb, ub=ub, solver=solver)  # type: ignore[no-any-return]
    import daqp

    n, m = len(q), len(h)
    upper = np.empty(n + m)
    upper[:n] = ub
    upper[n:] = h
    lower = np.full(n + m, _FREE)
    lower[:n] = lb
    rows = G if m else np.zeros((0, n))
    x, _, exitflag, _ = daqp.solve(P, q, rows, upper, lower, np.zeros(n + m, dtype=c_int))
    return x if exitflag > 0 else None
