"""A 7R arm with an end joint held (kin/ik/analytic/seven_r/held_end.py).

The target the 6R arm left must reach, for a 7R target at the held joint's value, is the 6R arm's
own tool pose (the plain NumPy DH product of ``tests/support/dh_reference.py`` on the table's rows without
the held one), joint 1 or joint 7 held, both conventions, random base and tool.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from support.dh_reference import ReferenceTable, fk_frames
from support.general_arms import random_7r_arm as random_arm

from kin.ik.analytic.seven_r.held_end import dh_transforms, held_end, six_r_table


def left_arm(reference: ReferenceTable, free: int) -> ReferenceTable:
    """The reference arrays of the 6R arm left: the rows but ``free``, its end frame the identity."""
    keep = [i for i in range(7) if i != free]
    return dataclasses.replace(
        reference,
        names=tuple(reference.names[i] for i in keep),
        prismatic=reference.prismatic[keep],
        a=reference.a[keep],
        alpha=reference.alpha[keep],
        d=reference.d[keep],
        theta=reference.theta[keep],
        lower=reference.lower[keep],
        upper=reference.upper[keep],
        T_world_base=reference.T_world_base if free == 6 else np.eye(4),
        T_last_tool=reference.T_last_tool if free == 0 else np.eye(4),
    )


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("free", [0, 6])
def test_the_held_arms_target_is_the_6r_arms_own_pose(convention, free):
    """end.targets(T(q), q_free) = FK of the 6R arm left at the other joints (NumPy DH), and
    end.joint_vectors puts the six joints and the held value back in q's places."""
    for seed in range(4):
        table, reference = random_arm(seed, convention)
        end = held_end(table, free, None, None)  # type: ignore[arg-type]  # no 6R solve
        q = np.random.default_rng(50 + seed).uniform(-np.pi, np.pi, (20, 7))
        poses = fk_frames(reference, q)[:, -1]
        sub = end.targets(poses, q[:, free])
        expected = fk_frames(left_arm(reference, free), q[:, end.others])[:, -1]
        assert np.abs(sub - expected).max() < 1e-12, f"{table.name} {free=}"
        assert six_r_table(table, free).dof == 6
        back = end.joint_vectors(q[:, None, end.others], q[:, free])
        np.testing.assert_array_equal(back[:, 0], q)


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_transforms_are_the_rows_own(convention):
    """One row's transforms at many values: the reference's DH matrix of that row."""
    table, reference = random_arm(9, convention)
    values = np.linspace(-3.0, 3.0, 7)
    for row in range(7):
        q = np.zeros((values.size, 7))
        q[:, row] = values
        frames = fk_frames(reference, q)
        link = np.linalg.inv(frames[:, row]) @ frames[:, row + 1]
        assert np.abs(dh_transforms(table, row, values) - link).max() < 1e-12, f"{row=}"
