"""The compiled pose check (``kin/_native/ik/targets/_pose_check.c``) gives the Python check's verdict.

A :class:`~kin.ik.PoseTarget` built from a float64 (3,) position and (3, 3) rotation takes the
short way: the compiled twin says whether the copies are finite with ``max |R^T R - I| <= 1e-12``
and ``det R > 0``; anything else goes the long way (:func:`kin.ik.targets.target._rotation`). Both are
held here to :func:`kin.ik.targets.target.orthonormality` (plain Python floats) and to NumPy's
``R.T @ R`` and ``det``, over rotations, near-rotations, reflections, extreme and non-finite
values, other dtypes, shapes and memory orders; the target built either way is the same.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from kin.ik import PoseTarget, TargetError
from kin.ik.targets import target as target_module

try:
    from kin.ik.targets._pose_check import exact_pose as _exact_pose
except ImportError:  # not built: the tests of the twin skip
    _exact_pose = None
TOL = target_module._ROTATION_EXACT

needs_twin = pytest.mark.skipif(_exact_pose is None, reason="kin/ik/targets/_pose_check not built")
#: The library took the twin (not with DH_KINEMATICS_PURE_PYTHON=1): its packed targets are tested.
needs_loaded_twin = pytest.mark.skipif(
    target_module._exact_pack is None, reason="kin.ik.targets.target runs without its twin"
)


def _rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def _python_verdict(position: np.ndarray, rotation: np.ndarray) -> bool:
    values = position.tolist() + rotation.ravel().tolist()
    if not all(map(math.isfinite, values)):
        return False
    deviation, determinant = target_module.orthonormality(*rotation.ravel().tolist())
    return deviation <= TOL and determinant > 0.0


def _numpy_deviation(rotation: np.ndarray) -> float:
    with np.errstate(all="ignore"):
        return float(np.abs(rotation.T @ rotation - np.eye(3)).max())


def _cases() -> list[tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(7)
    cases = []
    for _ in range(300):
        r = _rotation(rng)
        p = rng.normal(size=3)
        cases.append((p, r))
        cases.append((p, -r))  # a reflection: det -1
        for scale in (1e-14, 1e-13, 5e-12, 1e-9, 1e-4, 1e-2):
            cases.append((p, r + scale * rng.normal(size=(3, 3))))
    r = np.eye(3)
    for bad in (np.nan, np.inf, -np.inf, 1e200, 1e308, -1e-320):
        for k in range(9):
            m = r.copy()
            m.flat[k] = bad
            cases.append((np.zeros(3), m))
        cases.append((np.array([bad, 0.0, 0.0]), r))
    return cases


@needs_twin
def test_twin_gives_the_python_verdict():
    """Same verdict as plain Python floats, away from the 1e-12 threshold (rounding order)."""
    checked = 0
    for p, r in _cases():
        deviation = _numpy_deviation(r)
        if math.isfinite(deviation) and abs(deviation - TOL) < 1e-15:
            continue  # on the threshold: a fused multiply-add may round it either way
        assert _exact_pose(p, r, TOL) == _python_verdict(p, r), (p, r)
        checked += 1
    assert checked > 2000


@needs_twin
def test_twin_agrees_with_numpy():
    """A finite matrix passes iff NumPy's ``max |R^T R - I|`` is below the tolerance, det > 0."""
    for p, r in _cases():
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(p))):
            assert not _exact_pose(p, r, TOL)
            continue
        deviation = _numpy_deviation(r)
        if abs(deviation - TOL) < 1e-15:
            continue
        expected = deviation <= TOL and np.linalg.det(r) > 0
        assert _exact_pose(p, r, TOL) == expected


@needs_twin
@pytest.mark.parametrize(
    "position, rotation",
    [
        (np.zeros(3), np.eye(3, dtype=np.float32)),  # another dtype
        (np.zeros(3, dtype=np.float32), np.eye(3)),
        (np.zeros(3), np.eye(3).reshape(9)),  # another shape
        (np.zeros((3, 1)), np.eye(3)),
        (np.zeros(4), np.eye(3)),
        (np.zeros(3), np.eye(4)),
        (np.zeros(3), np.eye(3)[:, :2]),
        (np.zeros(3), np.eye(3)[::2]),  # not C-contiguous
        (np.zeros(3), np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]])),  # integers
        ([0.0, 0.0, 0.0], np.eye(3)),  # not an array
        (np.zeros(3), "eye"),
    ],
)
def test_twin_declines_other_arrays(position, rotation):
    """Anything but C-contiguous float64 (3,) and (3, 3) is declined, never an error."""
    assert _exact_pose(position, rotation, TOL) is False


@given(
    arrays(np.float64, 3, elements=st.floats(allow_nan=True, allow_infinity=True)),
    arrays(np.float64, (3, 3), elements=st.floats(allow_nan=True, allow_infinity=True)),
)
@settings(max_examples=300, deadline=None)
def test_short_and_long_way_build_the_same_target(position, rotation):
    """From hostile arrays: the same target (or the same TargetError) with or without the twin."""
    saved = target_module._exact_pack
    try:
        results = []
        for twin in (saved, None):
            target_module._exact_pack = twin
            try:
                built = PoseTarget(position, rotation)
                results.append((built.position.tolist(), built.rotation.tolist()))
                assert not built.position.flags.writeable
                assert not built.rotation.flags.writeable
                assert built.position is not position and built.rotation is not rotation
                assert built.finite
            except TargetError as err:
                results.append(str(err))
    finally:
        target_module._exact_pack = saved
    assert results[0] == results[1]


@needs_loaded_twin
@given(
    arrays(np.float64, 3, elements=st.floats(allow_nan=True, allow_infinity=True)),
    arrays(np.float64, (3, 3), elements=st.floats(allow_nan=True, allow_infinity=True)),
    st.sampled_from(["C", "F", "strided"]),
)
@settings(max_examples=300, deadline=None)
def test_exact_pack_holds_the_checked_values(position, rotation, order):
    """``exact_pack``: the 12 values (position, rotation row-major) exactly when ``exact_pose``
    passes them, else None, whatever the strides; the caller's arrays untouched and writeable."""
    if order == "strided":  # views of a larger array, as T[:3, 3] and T[:3, :3] are
        pose = np.zeros((4, 4))
        pose[:3, :3], pose[:3, 3] = rotation, position
        position, rotation = pose[:3, 3], pose[:3, :3]
    else:
        rotation = np.asarray(rotation, order=order)
    before = (position.copy(), rotation.copy())
    packed = target_module._exact_pack(position, rotation, TOL)
    verdict = _exact_pose(np.ascontiguousarray(position), np.ascontiguousarray(rotation), TOL)
    assert (packed is not None) == verdict
    if packed is not None:
        values = np.frombuffer(packed)
        np.testing.assert_array_equal(values[:3], position)
        np.testing.assert_array_equal(values[3:].reshape(3, 3), rotation)
    assert position.flags.writeable and rotation.flags.writeable
    np.testing.assert_array_equal(position, before[0])
    np.testing.assert_array_equal(rotation, before[1])


@needs_loaded_twin
def test_exact_pack_declines_what_is_not_an_ndarray():
    """Lists, subclasses, other dtypes and shapes: None (the long way), never an error."""
    short = target_module._exact_pack
    assert short([0.0, 0.0, 0.0], np.eye(3), TOL) is None
    assert short(np.zeros(3), np.eye(3).tolist(), TOL) is None
    assert short(np.zeros(3).view(np.recarray), np.eye(3), TOL) is None
    assert short(np.zeros(3, dtype=np.float32), np.eye(3), TOL) is None
    assert short(np.zeros(4), np.eye(3), TOL) is None
    assert short(np.zeros(3), np.eye(3), TOL) is not None
    with pytest.raises(TypeError):
        short(np.zeros(3), np.eye(3))


@needs_loaded_twin
def test_packed_target_arrays_are_read_only_for_good_and_pickle():
    """A packed target's arrays are views of immutable bytes (no flag makes them writeable); a
    pickled or copied target is the same target."""
    import copy
    import pickle

    target = PoseTarget(np.array([0.1, 0.2, 0.3]), np.eye(3))
    assert target._packed is not None and target.finite
    with pytest.raises(ValueError):
        target.position.flags.writeable = True
    with pytest.raises(ValueError):
        target.rotation[0, 0] = 2.0
    for twin in (pickle.loads(pickle.dumps(target)), copy.copy(target), copy.deepcopy(target)):
        assert twin._packed == target._packed and twin.finite
        np.testing.assert_array_equal(twin.position, target.position)
        np.testing.assert_array_equal(twin.rotation, target.rotation)
        assert not twin.position.flags.writeable


def test_target_is_a_checked_copy():
    """The caller's arrays may change after: the target keeps what was checked."""
    rng = np.random.default_rng(3)
    p, r = rng.normal(size=3), _rotation(rng)
    target = PoseTarget(p, r)
    p[0], r[0, 0] = np.nan, 5.0
    assert math.isfinite(target.position[0]) and abs(target.rotation[0, 0]) <= 1.0
    assert target.finite
    with pytest.raises(ValueError):
        target.rotation[0, 0] = 1.0
