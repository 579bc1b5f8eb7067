"""A batched collision check gives each configuration's own verdict, whatever ran before it.

Seen on Panda (maker's URDF to panda_link8, tests/data/collision/cell.toml): a pool of geometry data
reused across batches called a configuration free whose links 5 and 7 overlap by 2.9 cm, after
other batches had run on it; the single call and a fresh pool called it colliding (GJK then
started from the previous call's answer: kin/collision/requests.py). The checker now keeps its
pool from batch to batch, so this runs batches after batches on one. The verdicts here are
compared with single calls, which tests/collision/test_collision_engines.py compares with coal called
directly.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from support.urdf_reference import ARMS, erd

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model

CELL = Path(__file__).parents[1] / "data" / "collision" / "cell.toml"


def test_batches_after_batches_agree_with_single_calls():
    relative, base, _ = ARMS["panda"]
    robot = load_robot(erd(relative), base, "panda_link8")
    checker = CollisionChecker(load_collision_model(robot, scene=CELL))
    qs = np.random.default_rng(0).uniform(robot.lower, robot.upper, (2000, robot.nq))
    single = np.array([checker.in_collision(q) for q in qs])
    for _ in range(2):
        np.testing.assert_array_equal(checker.in_collision_batch(qs), single)
    for chunk, expected in zip(np.array_split(qs, 4), np.array_split(single, 4)):
        np.testing.assert_array_equal(checker.in_collision_batch(chunk), expected)
    assert 0 < single.sum() < len(single)
