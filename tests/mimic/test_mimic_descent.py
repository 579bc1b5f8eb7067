"""kin/mimic/descent.py: a joint the step pushes past its limit is held, the others take its share.

Judged apart from the descent: every answer by Pinocchio's own mimic model of the file (the
tool pose reached) and by the URDF's limits of every joint, mimic ones included; the work by the
steps the search reports (a count, not a time).
"""

from __future__ import annotations

import numpy as np
from support.mimic_reference import _in_limits, _pinocchio_mimic_fk, _urdf

import kin

#: Damped least-squares steps a solved target may take on average [count]: with the limits held
#: it is 20 here; clipping every step at the limits took 100 (a descent pressed against a limit
#: crept, up to its 200 steps on a quarter of the starts of the corpus' PR2 finger chain).
STEP_BUDGET = 40


def test_targets_with_joints_at_their_limits_are_reached_in_few_steps(tmp_path):
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(0.5), encoding="utf-8")
    arm = kin.load_arm(path)
    rng = np.random.default_rng(21)
    steps, targets = [], 0
    while targets < 40:
        q = rng.uniform(arm.lower, arm.upper)
        pinned = rng.choice(arm.nq, size=2, replace=False)  # two joints on a limit
        q[pinned] = np.where(rng.random(2) < 0.5, arm.lower[pinned], arm.upper[pinned])
        if not _in_limits(q, 0.5):  # the mimic joint's own limits
            continue
        targets += 1
        goal = _pinocchio_mimic_fk(path, q)
        start = np.where(rng.random(arm.nq) < 0.5, arm.lower, arm.upper)  # pressed on limits
        found = arm.search(goal[:3, 3], None, start, restarts=0)  # a position: redundant
        if found.answer is None:
            continue  # one start may meet a local minimum: counted below
        reached = _pinocchio_mimic_fk(path, found.answer.q)
        np.testing.assert_allclose(reached[:3, 3], goal[:3, 3], atol=1e-5)
        assert _in_limits(found.answer.q, 0.5)
        steps.append(found.iterations)
    assert len(steps) >= 15, len(steps)  # one start each: a local minimum may stop one
    assert np.mean(steps) <= STEP_BUDGET, steps
