"""The distance bound's direct daqp call (kin/ik/numeric/dense_qp.py) against qpsolvers' solve_qp."""

from __future__ import annotations

import numpy as np
import pytest
from qpsolvers import solve_qp

from kin.ik.numeric.dense_qp import solve_dense_qp


def _problem(rng: np.random.Generator, n: int, m: int):
    a = rng.normal(size=(6, n))
    P = a.T @ a + 1e-3 * np.eye(n)
    return P, rng.normal(size=n), rng.normal(size=(m, n)), rng.normal(0.0, 0.05, m)


@pytest.mark.parametrize("m", [0, 1, 3])
def test_same_answer_as_qpsolvers(m):
    """200 random QPs of 7 variables with m inequalities: the same minimizer as solve_qp's."""
    rng = np.random.default_rng(m)
    compared = 0
    for _ in range(200):
        P, q, G, h = _problem(rng, 7, m)
        lb, ub = -rng.uniform(0.05, 0.3, 7), rng.uniform(0.05, 0.3, 7)
        expected = solve_qp(P, q, G, h, lb=lb, ub=ub, solver="daqp")
        got = solve_dense_qp(P, q, G, h, lb, ub)
        assert (got is None) == (expected is None), f"{m=}"
        if expected is not None:
            np.testing.assert_array_equal(got, expected)
            assert np.all(got >= lb - 1e-6) and np.all(got <= ub + 1e-6)  # daqp primal_tol
            compared += 1
    assert compared > 100, compared


def test_infeasible_gives_none():
    """x >= 0.5 inside |x| <= 0.2: no answer (None), as solve_qp."""
    P, q = np.eye(2), np.zeros(2)
    G, h = np.array([[-1.0, 0.0]]), np.array([-0.5])
    lb, ub = np.full(2, -0.2), np.full(2, 0.2)
    assert solve_qp(P, q, G, h, lb=lb, ub=ub, solver="daqp") is None
    assert solve_dense_qp(P, q, G, h, lb, ub) is None


def test_other_solver_through_qpsolvers():
    """osqp goes through qpsolvers: the box-bounded minimum of |x - c|^2 / 2 (to its 1e-3)."""
    P, q = np.eye(3), -np.array([1.0, -1.0, 0.05])
    G, h = np.zeros((0, 3)), np.zeros(0)
    got = solve_dense_qp(P, q, G, h, np.full(3, -0.2), np.full(3, 0.2), solver="osqp")
    np.testing.assert_allclose(got, [0.2, -0.2, 0.05], atol=1e-3)  # osqp eps_abs
