"""Where the numeric search draws its starts: the joint limits, a long rail cut to the arm's size.

The seed table's samples (:mod:`.seed_table`), the random starts (:mod:`.restarts`, and
:mod:`.collision_bound`'s) and the reach's samples (:mod:`kin.ik.reach`, which then measures
distances across the rail) are drawn uniformly inside a box of joint values. A prismatic joint whose travel is far longer than the arm
(a mobile base's rail: the Robotics Toolbox's Frankie and Fetch declare +-999,999 m) would put
nearly every draw kilometres from any target: the seed table's nearest samples and the random
starts then never lead damped Newton to an answer, and every call falls through to the mink QP
runs (Frankie: 3.3 ms a call instead of 0.4 ms, and 15 of 200 reachable targets not found).

Such a joint is drawn within ``size`` of the value nearest zero inside its limits, ``size`` being
the arm's own size (the sum over rows of ``|a| + |d|`` plus the tool offset [m]: any tool motion
the other joints make is within it). Damped Newton moves a prismatic joint as far as it must from
there (its Jacobian column is constant). Every other joint keeps its limits, so the draws and the
answers of every other arm are unchanged; answers stay inside the true limits.
"""

from __future__ import annotations

import numpy as np

from dh2urdf import DHTable

#: A prismatic joint is drawn from a cut box when its travel is more than this many times the
#: arm's size (a linear axis of an arm, a gantry's rail of a few arm lengths, keeps its limits).
LONG_RAIL = 10.0


def arm_size(table: DHTable) -> float:
    """The arm's size [m]: the sum over rows of ``|a| + |d|`` plus the tool offset's length."""
    total = float(np.linalg.norm(np.asarray(table.T_last_tool, dtype=float)[:3, 3]))
    return total + sum(abs(row.a) + abs(row.d) for row in table.rows)


def sampling_limits(
    table: DHTable, lower: np.ndarray, upper: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The box the numeric search draws its starts from [rad, or m for a prismatic joint].

    ``lower`` and ``upper`` (the joint limits) themselves when no joint is a long rail (the
    caller's arrays, not copies); else copies with each long rail cut to ``arm_size`` either side
    of its value nearest zero inside its limits.
    """
    size = arm_size(table)
    rails = [
        i
        for i, row in enumerate(table.rows)
        if row.joint_type == "prismatic" and upper[i] - lower[i] > LONG_RAIL * size
    ]
    if not rails or size <= 0.0:
        return lower, upper
    low, high = lower.copy(), upper.copy()
    for i in rails:
        middle = min(max(0.0, float(lower[i])), float(upper[i]))
        low[i] = max(float(lower[i]), middle - size)
        high[i] = min(float(upper[i]), middle + size)
    return low, high
