"""The collision checker's joint-vector handling: the fast path for a finite float64 vector still
turns every bad ``q`` into one JointVectorError, other array-likes give the float64 answers, and
the verdicts equal a bare ``pin.computeCollisions`` on the same GeometryModel, in any thread."""

from __future__ import annotations

import threading
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import kin
from kin.collision import CollisionChecker, load_collision_model

CELL = Path(__file__).parents[1] / "data" / "collision" / "cell.toml"


@pytest.fixture(scope="module")
def checker() -> CollisionChecker:
    return CollisionChecker(load_collision_model(kin.load_robot("humanoid7"), scene=CELL))


@pytest.fixture(scope="module")
def qs(checker) -> np.ndarray:
    robot = checker.model.robot
    return np.random.default_rng(3).uniform(robot.lower, robot.upper, (300, robot.nq))


BAD = {
    "nan": lambda n: np.r_[np.zeros(n - 1), np.nan],
    "inf": lambda n: np.r_[np.inf, np.zeros(n - 1)],
    "-inf": lambda n: np.r_[np.zeros(n - 1), -np.inf],
    "inf-inf": lambda n: np.r_[np.inf, -np.inf, np.zeros(n - 2)],
    "column": lambda n: np.zeros((n, 1)),
    "row": lambda n: np.zeros((1, n)),
    "short": lambda n: np.zeros(n - 1),
    "long": lambda n: np.zeros(n + 1),
    "scalar": lambda n: np.float64(0.0),
    "text": lambda n: "0 0 0",
    "nan list": lambda n: [0.0] * (n - 1) + [float("nan")],
}


@pytest.mark.parametrize("kind", sorted(BAD))
@pytest.mark.parametrize("query", ["in_collision", "collisions", "distance"])
def test_bad_joint_vector_is_one_error(checker, kind, query):
    """NaN, infinities, wrong shapes and non-numbers raise JointVectorError naming the problem."""
    q = BAD[kind](checker.model.robot.nq)
    with pytest.raises(kin.JointVectorError) as info:
        getattr(checker, query)(q)
    assert "\n" not in str(info.value), f"{kind=}"
    assert any(word in str(info.value) for word in ("finite", "flat vector", "joint", "numbers"))


def test_bad_row_in_batch_is_one_error(checker, qs):
    """A NaN in one row of a batch raises JointVectorError, nothing computed."""
    bad = qs[:10].copy()
    bad[4, 2] = np.nan
    with pytest.raises(kin.JointVectorError, match="finite"):
        checker.in_collision_batch(bad)


def test_verdicts_equal_bare_pinocchio(checker, qs):
    """in_collision equals pin.computeCollisions on a fresh GeometryData; both kinds occur."""
    model, geometry = checker.model.robot.model, checker.model.geometry_model
    data, geometry_data = model.createData(), pin.GeometryData(geometry)
    reference = [pin.computeCollisions(model, data, geometry, geometry_data, q, True) for q in qs]
    ours = [checker.in_collision(q) for q in qs]
    assert ours == reference
    assert 0 < sum(ours) < len(qs)
    assert all(type(v) is bool for v in ours)
    # the contact-computing queries agree with the verdict-only one
    assert [bool(checker.collisions(q)) for q in qs[:100]] == reference[:100]


def test_array_likes_give_the_float64_answer(checker, qs):
    """Lists, float32, int and strided views of q give the verdict of the float64 vector."""
    for q in qs[:50]:
        expected = checker.in_collision(q)
        assert checker.in_collision(q.tolist()) == expected
        assert checker.in_collision(tuple(q)) == expected
        assert checker.in_collision(np.repeat(q, 2)[::2]) == expected
    zeros = np.zeros(checker.model.robot.nq)
    expected = checker.in_collision(zeros)
    assert checker.in_collision(zeros.astype(np.float32)) == expected
    assert checker.in_collision(zeros.astype(int)) == expected


def test_threads_get_their_own_data(checker, qs):
    """Two threads checking at once give the single-thread verdicts."""
    expected = [checker.in_collision(q) for q in qs]
    results: dict[int, list[bool]] = {}

    def work(index: int) -> None:
        results[index] = [checker.in_collision(q) for q in qs]

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert results == {0: expected, 1: expected}
