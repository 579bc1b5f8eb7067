"""Starts and scans of a batched free-joint form (kin/ik/analytic/seven_r/free_value_scan.py).

A made-up form whose one branch at a free value ``v`` is ``(v, 3.0, 0, ..., 0)``, only where
``v >= 0.45``: the values a start or a scan must land on, and the batches it must ask, are known
by hand.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from kin.ik.analytic.seven_r.free_value_scan import (
    NEAR_VALUES,
    SCAN_STEP,
    first,
    first_each,
    nearest_inside,
    nearest_inside_each,
)
from kin.ik.limit_rule import nearest_copy

REACH = 0.45
TARGET = np.eye(4)


@dataclasses.dataclass
class StepForm:
    """One branch ``(v, 3.0, 0, ...)`` at each free value ``v >= REACH``, none below; records calls."""

    free: int = 0
    lower: np.ndarray = dataclasses.field(default_factory=lambda: np.full(7, -4.0))
    upper: np.ndarray = dataclasses.field(default_factory=lambda: np.full(7, 4.0))
    calls: list[int] = dataclasses.field(default_factory=list)

    def branches(self, targets: np.ndarray, values: np.ndarray, exact: bool = False) -> np.ndarray:
        assert targets.shape == (values.size, 4, 4)
        self.calls.append(values.size)
        out = np.full((values.size, 2, 7), np.nan)
        reached = values >= REACH
        out[reached, 0] = 0.0
        out[reached, 0, 0] = values[reached]
        out[reached, 0, 1] = 3.0
        return out


def starts_at(*values: float) -> np.ndarray:
    """Start joint vectors with free joint ``values``, joint 2 at -2.0 and the rest zero."""
    starts = np.zeros((len(values), 7))
    starts[:, 0] = values
    starts[:, 1] = -2.0
    return starts


def test_a_scan_takes_the_nearest_value_with_a_branch_in_batches():
    """From 0.0 by 0.1: 0.5 (0.45 lies between 0.4 and 0.5), found in the second batch (the 16
    nearest values after the start's own); joint 2's 3.0 moves to its copy nearest the start's -2.0."""
    form = StepForm()
    out = np.full(7, 7.0)
    assert first(form, TARGET, starts_at(0.0), out, 0.1) == 0
    assert out[0] == pytest.approx(0.5, abs=1e-12)
    assert out[1] == pytest.approx(3.0 - 2 * math.pi, abs=1e-12)
    assert form.calls == [1, NEAR_VALUES]


def test_a_start_not_finite_is_skipped_and_a_fine_step_scans_nothing():
    """A NaN start leaves the next one to answer; a step finer than SCAN_STEP asks nothing."""
    form = StepForm()
    out = np.full(7, 7.0)
    starts = np.vstack((np.full((1, 7), np.nan), starts_at(0.0)))
    assert first(form, TARGET, starts, out, 0.1) == 1
    form.calls.clear()
    untouched = np.full(7, 7.0)
    assert first(form, TARGET, starts_at(0.0), untouched, SCAN_STEP / 2) == -1
    assert form.calls == [] and np.all(untouched == 7.0)


def test_without_a_scan_every_start_is_solved_at_once():
    """Step 0: one call of the finite starts' values; the first start with a branch answers."""
    form = StepForm()
    out = np.full(7, 7.0)
    assert first(form, TARGET, starts_at(0.0, 0.6, 0.7), out, 0.0) == 1
    assert out[0] == 0.6 and form.calls == [3]
    assert first(form, TARGET, starts_at(0.0, -1.0), out, 0.0) == -1


def test_first_each_answers_each_target_at_its_start():
    """A start below the reach, one on it and a NaN start: NaN, its branch, NaN; one call of two."""
    form = StepForm()
    starts = np.vstack((starts_at(0.0, 0.6), np.full((1, 7), np.nan)))
    found = first_each(form, np.broadcast_to(TARGET, (3, 4, 4)), starts)
    assert np.isnan(found[[0, 2]]).all()
    assert found[1, 0] == 0.6 and found[1, 1] == pytest.approx(3.0 - 2 * math.pi, abs=1e-12)
    assert form.calls == [2]


def test_nearest_inside_keeps_the_limits():
    """The 2 pi copy nearest the start inside the limits; none inside: None."""
    branch = np.array([[0.0, 3.0, 0, 0, 0, 0, 0]])
    lower, upper = np.full(7, -3.1), np.full(7, 3.1)
    start = np.zeros(7)
    start[1] = -3.0
    assert nearest_inside(branch, start, lower, upper)[1] == 3.0  # 3.0 - 2 pi is below -3.1
    found = nearest_inside(branch, start, lower - 1.0, upper)
    assert found[1] == pytest.approx(3.0 - 2 * math.pi, abs=1e-12)
    assert nearest_inside(branch, start, lower, np.full(7, 2.0)) is None


def _one_by_one(branches, start, lower, upper):
    """The rule joint by joint with the scalar nearest_copy: the inside rows, the nearest first."""
    best, best_distance = None, math.inf
    for row in branches[~np.isnan(branches).any(axis=1)]:
        copies = [nearest_copy(v, s, lo, hi) for v, s, lo, hi in zip(row, start, lower, upper)]
        if all(inside for _, inside in copies):
            q = np.array([c for c, _ in copies])
            distance = float(((q - start) ** 2).sum())
            if distance < best_distance:
                best, best_distance = q, distance
    return best


def test_nearest_inside_each_is_the_scalar_rule_set_by_set():
    """Many branch sets in one pass give, set by set, the scalar rule's branch (or NaN: none)."""
    rng = np.random.default_rng(7)
    lower, upper = np.full(7, -2.5), np.full(7, 2.5)
    lower[3], upper[3] = -6.0, 0.5  # one joint over a whole turn, one lopsided
    branches = rng.uniform(-9.0, 9.0, (40, 6, 7))
    branches[rng.random((40, 6)) < 0.3] = np.nan  # NaN rows: no branch there
    branches[5] = np.nan  # a set with none at all
    starts = rng.uniform(-2.0, 2.0, (40, 7))
    for each_start in (starts, starts[0]):
        found = nearest_inside_each(branches, each_start, lower, upper)
        for k in range(40):
            start = each_start if each_start.ndim == 1 else each_start[k]
            expected = _one_by_one(branches[k], start, lower, upper)
            if expected is None:
                assert np.isnan(found[k]).all()
                assert nearest_inside(branches[k], start, lower, upper) is None
            else:
                np.testing.assert_allclose(found[k], expected, rtol=0, atol=1e-12)
                np.testing.assert_array_equal(
                    nearest_inside(branches[k], start, lower, upper), found[k]
                )
    assert np.isnan(found[5]).all()
    assert (~np.isnan(found[:, 0])).sum() >= 5  # the test sees sets with a branch inside
    assert nearest_inside_each(np.empty((3, 0, 7)), starts[:3], lower, upper).shape == (3, 7)
