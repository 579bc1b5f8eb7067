"""A target outside the seed table's grid (kin/ik/numeric/seed_cells.py): the same k nearest
samples as ranking every sample, and the distances of the plain pose embedding.

The cells' boxes only prune which samples are ranked; the answer is held to a brute-force
ranking of all of them (NumPy's stable argsort of every distance) and to the distance
``|p - p_i|^2 + w^2 |R - R_i|_F^2`` computed directly (not through the lifted rows).
"""

from __future__ import annotations

import functools

import numpy as np
import pinocchio as pin
from hypothesis import given, settings
from hypothesis import strategies as st

from kin import load_robot
from kin.ik.numeric.seed_table import SeedTable, build_seed_table


@functools.cache
def _table(robot: str) -> SeedTable:
    return build_seed_table(load_robot(robot), size=3000, cache=False)


def _brute(table: SeedTable, position: np.ndarray, rotation: np.ndarray | None, k: int):
    """Every sample ranked: the indices, and the plain embedding distances of the ``k``."""
    lifted = table._lifted
    assert lifted is not None
    order = np.argsort(lifted @ table._query(position, rotation), kind="stable")[:k]
    gap = table.positions[order] - position
    plain = np.einsum("ij,ij->i", gap, gap)
    if rotation is not None:
        turn = table.rotations[order] - rotation.reshape(-1)
        plain = plain + table.rotation_weight**2 * np.einsum("ij,ij->i", turn, turn)
    return order, plain


@settings(max_examples=120, deadline=None)
@given(
    robot=st.sampled_from(["ur5", "lab5", "humanoid7"]),
    direction=st.tuples(*(st.floats(-1.0, 1.0) for _ in range(3))).filter(
        lambda v: sum(x * x for x in v) > 1e-3
    ),
    distance=st.floats(0.05, 1e4),
    turn=st.tuples(*(st.floats(-3.0, 3.0) for _ in range(3))),
    with_rotation=st.booleans(),
    k=st.integers(1, 40),
)
def test_far_targets_get_the_nearest_of_every_sample(
    robot, direction, distance, turn, with_rotation, k
):
    """A point beyond the sampled box along any direction, a pose or a position: same k."""
    table = _table(robot)
    low, high = table.positions.min(axis=0), table.positions.max(axis=0)
    centre, reach = (low + high) / 2, float(np.linalg.norm(high - low))  # beyond the grid's box
    unit = np.array(direction) / np.linalg.norm(direction)
    position = centre + unit * (reach + distance)
    assert table._cell_key(position) is None  # outside the grid: the far search
    rotation = pin.exp3(np.array(turn)) if with_rotation else None
    found = table.nearest(position, rotation, k)
    expected, plain = _brute(table, position, rotation, k)
    np.testing.assert_array_equal(found, expected)
    # the ranking's distances are the embedding's (the lifted rows round them only)
    gap = table.positions[found] - position
    direct = np.einsum("ij,ij->i", gap, gap)
    if rotation is not None:
        spin = table.rotations[found] - rotation.reshape(-1)
        direct = direct + table.rotation_weight**2 * np.einsum("ij,ij->i", spin, spin)
    np.testing.assert_allclose(direct, plain, rtol=1e-9, atol=1e-9)
    assert np.all(np.diff(direct) >= -1e-9 * (1.0 + direct[:-1]))


def test_the_boxes_hold_their_samples():
    """Every sample lies in its box (bounds tight on it), and the boxes hold every sample once."""
    table = _table("ur5")
    boxes, owners = table._boxes, table._owners
    assert boxes is not None and owners is not None
    assert boxes.box_of.shape == owners.shape == (len(table),)
    placed = table.positions[owners]
    assert np.all(placed >= boxes.lower[boxes.box_of]) and np.all(
        placed <= boxes.upper[boxes.box_of]
    )
    for row in range(len(boxes.lower)):  # tight: a sample on each face
        mine = placed[boxes.box_of == row]
        np.testing.assert_array_equal(mine.min(axis=0), boxes.lower[row])
        np.testing.assert_array_equal(mine.max(axis=0), boxes.upper[row])
    assert np.array_equal(np.sort(owners), np.arange(len(table)))
    # grouped by box: each box's slice holds its entries, ascending, and nothing else
    assert boxes.starts[0] == 0 and boxes.starts[-1] == len(table)
    for row in range(len(boxes.lower)):
        mine = boxes.by_box[boxes.starts[row] : boxes.starts[row + 1]]
        np.testing.assert_array_equal(mine, np.flatnonzero(boxes.box_of == row))
    some = np.array([3, 0, len(boxes.lower) - 1])
    np.testing.assert_array_equal(
        np.sort(boxes.members(some)), np.flatnonzero(np.isin(boxes.box_of, some))
    )


def test_a_huge_or_non_finite_position_ranks_every_sample():
    """Beyond the cells' bound (1e300 m, inf): the full ranking's answer, no overflow error."""
    table = _table("ur5")
    for value in (1e300, np.inf):
        position = np.array([value, 0.0, 0.5])
        with np.errstate(over="ignore", invalid="ignore"):
            found = table.nearest(position, None, 3)
            expected = np.argsort(table._lifted @ table._query(position, None), kind="stable")
        np.testing.assert_array_equal(found, expected[:3])


@settings(max_examples=40, deadline=None)
@given(sample=st.integers(0, 2999), k=st.integers(100, 400), with_rotation=st.booleans())
def test_more_than_a_neighbourhood_holds_is_the_nearest_of_every_sample(sample, k, with_rotation):
    """Inside the grid with k beyond the 27 cells' samples: the cells' search, same k."""
    table = _table("humanoid7")
    position = table.positions[sample] + 0.01
    rotation = table.rotations[sample].reshape(3, 3) if with_rotation else None
    expected, _ = _brute(table, position, rotation, k)
    np.testing.assert_array_equal(table.nearest(position, rotation, k), expected)
