"""The sub-problems the seven-joint closed forms share, scalar and batched, and their scan.

``p cos t + q sin t = k`` (:func:`harmonic_roots`), ``Rz(ta) Rx(alpha) Rz(tb) v = d`` (a
Paden-Kahan sub-problem 2 about two axes a twist apart, :func:`rotation_pair`), their NumPy twins
over N equations and the outward scan of a free joint (:func:`scan`). Angles in radians, lengths
in meters. The compiled twins' support the 6R forms share (the packing of a form's parameters,
the threads of a batch) is :mod:`kin.ik.analytic.twin_support`; its names stay importable here.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence

import numpy as np

from ...angles import clip_unit
from ..twin_support import (  # noqa: F401  (their home before; importable from here still)
    PARALLEL_ROWS,
    ScanJob,
    batch_threads,
    call_first_many,
    chain_fields,
    pack_params,
    thread_pool,
)
from ..twin_support import thread_pool as _pool  # noqa: F401  (its former private name)

#: Slack on ``|cos| <= 1`` of the elbow and pair angles (rounding at the edge of the workspace).
COS_SLACK = 1e-12


def harmonic_roots(p: float, q: float, k: float) -> tuple[float, ...]:
    """Angles ``t`` [rad] with ``p cos t + q sin t = k``: two, one (a double root) or none.

    ``|k| / hypot(p, q)`` up to :data:`COS_SLACK` above 1 counts as 1 (rounding at the edge).
    """
    rho = math.hypot(p, q)
    if rho < 1e-15:
        return ()
    c = clip_unit(k / rho, COS_SLACK)
    if c is None:
        return ()
    phi, delta = math.atan2(q, p), math.acos(c)
    return (phi + delta, phi - delta) if delta > 0.0 else (phi,)


def fold_distance(p: float, q: float, k: float) -> float:
    """How far ``p cos t + q sin t = k`` is from a double root: ``| 1 - |k| / hypot(p, q) |``.

    0 for an equation too weak to solve (``hypot(p, q) < 1e-15``, as :func:`harmonic_roots`).
    Near 0 its two roots are near each other (or nearly exist): a small change of the arm
    adds or removes both.
    """
    rho = math.hypot(p, q)
    return abs(1.0 - abs(k) / rho) if rho >= 1e-15 else 0.0


def rotation_pair(
    sa: float, ca: float, vx: float, vy: float, vz: float, dx: float, dy: float, dz: float
) -> list[tuple[float, float]]:
    """Angles ``(ta, tb)`` with ``Rz(ta) Rx(alpha) Rz(tb) v = d`` (``|v| = |d|``), up to two pairs.

    The z row gives ``sa (vx sin tb + vy cos tb) + ca vz = dz`` (two ``tb``); ``ta`` then turns
    ``Rx(alpha) Rz(tb) v`` about z onto ``d``. ``sa, ca`` are ``sin alpha, cos alpha``.
    """
    heading = math.atan2(dy, dx)
    pairs = []
    for tb in harmonic_roots(sa * vy, sa * vx, dz - ca * vz):
        cb, sb = math.cos(tb), math.sin(tb)
        mx = vx * cb - vy * sb
        my = ca * (vx * sb + vy * cb) - sa * vz
        pairs.append((heading - math.atan2(my, mx), tb))
    return pairs


def scan(value: float, step: float, low: float, high: float) -> Iterator[float]:
    """``value``, then ``value + j step`` and ``value - j step`` for j = 1, 2, ... inside ``[low, high]``.

    The free joint's values [rad] outward from a start's: the first that gives a branch inside the
    limits is the nearest to the start's at that resolution. ``step <= 0``: ``value`` alone.
    """
    yield value
    if not step > 0.0:
        return
    j = 1
    while True:
        up, down = value + j * step, value - j * step
        if up > high and down < low:
            return
        if low <= up <= high:
            yield up
        if low <= down <= high:
            yield down
        j += 1


def limit_arcs(
    lower: Sequence[float], upper: Sequence[float], offsets: Sequence[float], joints: Sequence[int]
) -> tuple[float, ...]:
    """The joints' limits as arcs of their angle ``t = q + offset``, as the twins read them.

    Per joint: ``cos, sin`` of the middle of the limits, ``cos`` of half their span, then 1
    when the span is a whole turn or more (or not finite: every ``t``), else 0 (``arc`` in
    ``_closed7.c`` and ``_shoulder7.c``). The Python modules do not use them: the twins skip,
    without solving, the free-joint values where no branch, followed as directions, has every
    joint in its arc (``arc_admits`` in ``_twin.h``).
    """
    values: list[float] = []
    for j in joints:
        middle = 0.5 * (lower[j] + upper[j]) + offsets[j]
        half = 0.5 * (upper[j] - lower[j])
        if not half < math.pi:
            values += (1.0, 0.0, -1.0, 1.0)
        else:
            values += (math.cos(middle), math.sin(middle), math.cos(half), 0.0)
    return tuple(values)


def harmonic_roots_array(p: np.ndarray, q: np.ndarray, k: np.ndarray) -> np.ndarray:
    """:func:`harmonic_roots` of N equations: (N, 2), NaN where a root is missing.

    A double root fills column 0 only (as the scalar returns one angle).
    """
    rho = np.hypot(p, q)
    with np.errstate(divide="ignore", invalid="ignore"):
        cosine = k / rho
    ok = (rho >= 1e-15) & (np.abs(cosine) <= 1.0 + COS_SLACK)
    phi = np.arctan2(q, p)
    delta = np.arccos(np.clip(cosine, -1.0, 1.0))
    out = np.stack((phi + delta, np.where(delta > 0.0, phi - delta, np.nan)), 1)
    out[~ok] = np.nan
    return out


def rotation_pair_array(sa: float, ca: float, v: np.ndarray, d: np.ndarray) -> np.ndarray:
    """:func:`rotation_pair` of N vector pairs (N, 3): ``(ta, tb)`` as (N, 2, 2)."""
    vx, vy, vz = v[:, 0], v[:, 1], v[:, 2]
    heading = np.arctan2(d[:, 1], d[:, 0])
    tb = harmonic_roots_array(sa * vy, sa * vx, d[:, 2] - ca * vz)
    out = np.empty((v.shape[0], 2, 2))
    for i in range(2):
        cb, sb = np.cos(tb[:, i]), np.sin(tb[:, i])
        mx = vx * cb - vy * sb
        my = ca * (vx * sb + vy * cb) - sa * vz
        out[:, i, 0] = heading - np.arctan2(my, mx)
        out[:, i, 1] = tb[:, i]
    return out
