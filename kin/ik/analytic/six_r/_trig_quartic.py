"""Real roots of ``E(t) = h0 + hc cos t + hs sin t + hc2 cos 2t + hs2 sin 2t``, the quartic of the 6R closed forms.

:mod:`.pieper` (joint 3 of a general 3R arm) and :mod:`.three_parallel` (joint 1 of an arm with
three parallel axes) both end in this equation. With ``x = tan((t - tau) / 2)`` it is a quartic
in ``x`` whose leading coefficient is ``E(tau + pi)``; the shift ``tau`` (``tau + pi`` a multiple
of 45 deg) is chosen where ``|E(tau + pi)|`` is the largest of the eight, so no root runs off to
infinity. The real eigenvalues of the quartic's companion matrix give the candidate angles; the
callers polish them by safeguarded Newton steps (:func:`polish_batch`) on their
own, unexpanded ``E`` and keep those that reach it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

#: Companion eigenvalues ``x`` with ``|Im x| <= IMAG_TOL (1 + Re x^2)`` are taken as real roots
#: (a double root splits into a complex pair of about ``sqrt(eps)`` under rounding).
IMAG_TOL = 1e-6
#: Safeguarded Newton steps of the callers' polishing: a step is taken only when it lowers
#: ``|E|`` (else halved for the next try); one longer than ``MAX_STEP`` [rad] is not tried (the
#: root is double, or there is no real root near); one shorter than ``CONVERGED`` [rad] is not
#: needed.
NEWTON_STEPS = 3
MAX_STEP = 0.1
CONVERGED = 1e-15
#: Machine epsilon, for the callers' rounding bounds on ``E``.
EPS = 2.0**-52

#: The shifts tried: ``tau + pi`` in multiples of 45 deg, with their cos, sin, cos 2, sin 2.
_SHIFTS = tuple(k * math.pi / 4 for k in range(8))
_SHIFT_TRIG = tuple((math.cos(a), math.sin(a), math.cos(2 * a), math.sin(2 * a)) for a in _SHIFTS)
_SHIFT_ARRAY = np.array(_SHIFT_TRIG)


def _first_row(h0, hc, hs, hc2, hs2, lead):  # type: ignore[no-untyped-def]
    """The companion matrix's first row of the shifted quartic (floats or arrays)."""
    return (
        -(2.0 * hs - 4.0 * hs2) / lead,
        -(2.0 * h0 - 6.0 * hc2) / lead,
        -(2.0 * hs + 4.0 * hs2) / lead,
        -(h0 + hc + hc2) / lead,
    )


def candidates_batch(
    h0: npt.ArrayLike, hc: npt.ArrayLike, hs: npt.ArrayLike, hc2: npt.ArrayLike, hs2: npt.ArrayLike
) -> np.ndarray:
    """Candidate roots ``t`` of N equations (coefficients broadcast to (N,)): (N, 4) [rad].

    Not polished; NaN where an eigenvalue is not real or the equation has no finite quartic
    (``E = 0`` for every ``t``, or a coefficient not finite).
    """
    e0, ec, es, ec2, es2 = np.broadcast_arrays(
        *(np.asarray(h, dtype=float) for h in (h0, hc, hs, hc2, hs2))
    )
    c, s, c2, s2 = _SHIFT_ARRAY.T
    values = np.abs(e0[:, None] + ec[:, None] * c + es[:, None] * s + ec2[:, None] * c2
                    + es2[:, None] * s2)  # fmt: skip
    best = np.argmax(values, axis=1)
    usable = values[np.arange(len(best)), best] > 0.0
    ct, st = -_SHIFT_ARRAY[best, 0], -_SHIFT_ARRAY[best, 1]
    c2t, s2t = _SHIFT_ARRAY[best, 2], _SHIFT_ARRAY[best, 3]
    tau = np.array(_SHIFTS)[best] + math.pi
    ec, es = ec * ct + es * st, es * ct - ec * st
    ec2, es2 = ec2 * c2t + es2 * s2t, es2 * c2t - ec2 * s2t
    lead = np.where(usable, e0 - ec + ec2, 1.0)
    companion = np.zeros((len(best), 4, 4))
    for column, value in enumerate(_first_row(e0, ec, es, ec2, es2, lead)):
        companion[:, 0, column] = value
    companion[:, 1, 0] = companion[:, 2, 1] = companion[:, 3, 2] = 1.0
    finite = usable & np.isfinite(companion).all(axis=(1, 2))
    companion[~finite] = 0.0
    x = np.linalg.eigvals(companion)
    real = (np.abs(x.imag) <= IMAG_TOL * (1.0 + x.real * x.real)) & finite[:, None]
    return np.where(real, tau[:, None] + 2.0 * np.arctan(x.real), np.nan)


def polish_batch(
    residual: Callable[[np.ndarray], tuple[Any, ...]], t: np.ndarray
) -> tuple[np.ndarray, list[np.ndarray], np.ndarray]:
    """Safeguarded Newton steps on ``E`` from an array of starts [rad], at most :data:`NEWTON_STEPS`.

    Per start, a step is taken only when it lowers ``|E|`` (else halved for the next try) and
    not when longer than :data:`MAX_STEP`; NaN starts stay NaN.

    Args:
        residual: ``t -> (E, dE/dt, bound, *extra)``: the caller's unexpanded ``E``, its
            derivative, the largest ``|E|`` of a root (rounding included) and values it needs
            at the root, for an array of angles.
        t: The starts (:func:`candidates_batch` angles) [rad].

    Returns:
        The polished angles, the extras at them, and where ``|E|`` is within its bound.
    """
    e, de, bound, *extra = residual(t)
    damping = np.ones_like(t)
    for _ in range(NEWTON_STEPS):
        step = np.where(de != 0.0, e / de, 0.0)
        step = np.where(np.abs(step) > MAX_STEP, 0.0, step)
        if not (np.abs(step) > CONVERGED).any():
            break
        trial = t - damping * step
        e2, de2, bound2, *extra2 = residual(trial)
        better = np.abs(e2) < np.abs(e)
        t, e = np.where(better, trial, t), np.where(better, e2, e)
        de, bound = np.where(better, de2, de), np.where(better, bound2, bound)
        extra = [np.where(better, b, a) for a, b in zip(extra, extra2)]
        damping = np.where(better, 1.0, 0.5 * damping)
    return t, extra, np.abs(e) <= bound
