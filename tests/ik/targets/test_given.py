"""kin.ik.targets.given: a target from a user's values in a unit, checked against Pinocchio's
rotations and plain unit arithmetic (not against the target classes' own conversions)."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kin.ik.exceptions import TargetError
from kin.ik.targets.given import target_from_values
from kin.ik.targets.target import AxisTarget, PitchTarget, PoseTarget, PositionTarget

_ANGLE = st.floats(-720.0, 720.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.tuples(_ANGLE, _ANGLE, _ANGLE))
def test_rpy_in_degrees_is_pinocchios_rotation(rpy_deg):
    """rpy [deg] and a position [mm]: Pinocchio's rpyToMatrix of the radians, the meters."""
    target = target_from_values([100.0, -20.0, 5.0], rpy=rpy_deg, length=1e-3, angle=math.pi / 180)
    assert isinstance(target, PoseTarget)
    expected = pin.rpy.rpyToMatrix(*np.radians(rpy_deg))
    np.testing.assert_allclose(target.rotation, expected, atol=1e-12)
    np.testing.assert_allclose(target.position, [0.1, -0.02, 0.005], rtol=1e-15)


@settings(max_examples=60, deadline=None)
@given(st.tuples(*(st.floats(-10, 10, allow_nan=False) for _ in range(4))))
def test_quaternion_is_pinocchios_rotation(wxyz):
    """Any non-zero quaternion (not normalised): Pinocchio's rotation of it normalised."""
    w, x, y, z = wxyz
    if math.hypot(w, x, y, z) < 1e-3:
        return
    target = target_from_values([0.0, 0.0, 0.0], quaternion=wxyz)
    expected = pin.Quaternion(w, x, y, z).normalized().toRotationMatrix()
    np.testing.assert_allclose(target.rotation, expected, atol=1e-12)


def test_kinds_chosen_by_the_values_given():
    """No orientation: a position; axis, pitch (with roll) and a masked pose as given."""
    assert isinstance(target_from_values([1, 2, 3]), PositionTarget)
    axis = target_from_values([0, 0, 1], axis=[0, 0, -1], tool_axis="x")
    assert isinstance(axis, AxisTarget) and axis.tool_axis == "x"
    pitch = target_from_values([0.3, 0, 0.1], pitch=90.0, roll=-45.0, angle=math.pi / 180)
    assert isinstance(pitch, PitchTarget)
    assert pitch.pitch == pytest.approx(math.pi / 2) and pitch.roll == pytest.approx(-math.pi / 4)
    masked = target_from_values([0, 0, 0], rpy=[0, 0, 0], mask=[1, 1, 1, 0, 0, 1])
    assert masked.free == ("rx", "ry")


def test_a_huge_angle_keeps_its_digits():
    """1e18 deg is fmod(1e18, 360) deg (reduced before the conversion, not after)."""
    target = target_from_values([0, 0, 0], rpy=[0.0, 0.0, 1e18], angle=math.pi / 180)
    yaw = math.radians(math.fmod(1e18, 360.0))
    np.testing.assert_allclose(target.rotation, pin.rpy.rpyToMatrix(0, 0, yaw), atol=1e-12)


@pytest.mark.parametrize(
    ("values", "words"),
    [
        ({"rpy": [0, 0, 0], "pitch": 0.1}, "give one orientation"),
        ({"roll": 0.1}, "roll needs pitch"),
        ({"mask": [1, 1, 1, 0, 0, 0], "axis": [0, 0, 1]}, "mask needs rpy or quaternion"),
        ({"quaternion": [0, 0, 0, 0]}, "quaternion must not be zero"),
        ({"rpy": [0, float("nan"), 0]}, "rpy"),
        ({"pitch": "steep"}, "pitch"),
    ],
)
def test_malformed_values_are_target_errors(values, words):
    """Each refusal is a TargetError naming the value."""
    with pytest.raises(TargetError, match=words):
        target_from_values([0.1, 0.0, 0.2], **values)


def test_position_not_three_numbers():
    with pytest.raises(TargetError, match="position"):
        target_from_values([0.1, 0.2])
