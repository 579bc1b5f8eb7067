"""Configuration input handling: any array-like joint vector, shapes refused with JointVectorError."""

import numpy as np
import pytest

from kin import Configuration, JointVectorError, load_robot


def test_fk_accepts_lists_and_integer_arrays():
    """fk() gives the same pose for a list, an int array and a float array."""
    configuration = Configuration(load_robot("planar2"))
    expected = configuration.fk(np.array([0.0, 0.0])).translation
    for q in ([0, 0], np.array([0, 0]), (0.0, 0.0)):
        np.testing.assert_allclose(configuration.fk(q).translation, expected, atol=0)
    np.testing.assert_allclose(expected, [0.5, 0.0, 0.0], atol=1e-12)


@pytest.mark.parametrize("q", [[[0.0], [0.0]], np.zeros((1, 2)), [0.0, float("inf")], [0.0]])
def test_fk_and_update_refuse_bad_shapes_and_values(q):
    """A 2-D, non-finite or short joint vector raises JointVectorError in fk() and update()."""
    configuration = Configuration(load_robot("planar2"))
    with pytest.raises(JointVectorError):
        configuration.fk(q)
    with pytest.raises(JointVectorError):
        configuration.update(q)
