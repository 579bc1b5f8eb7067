"""Collision check of joint paths (kin.path.check_path_collisions, ``kin path --scene/--srdf``).

Compared with a direct coal check built apart (tests/support/collision_reference.py): the verdict of every
sample, and the motion between samples sampled densely by the reference; a path the reference
finds colliding between free samples is never called free, and a path called free has no contact
deeper than 1e-6 m anywhere the reference looks.
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call
from support.collision_reference import CollisionReference
from support.urdf_reference import erd

from kin import load_robot
from kin.collision.requests import CONTACT_TOLERANCE
from kin.commands import path as path_command
from kin.path import check_path_collisions

CELL = Path(__file__).parents[1] / "data" / "collision" / "cell.toml"
CONTACT_TOL = 1e-6
#: Reference samples per segment when the motion between samples is checked densely.
DENSE = 100


@cache
def setup(name: str):
    """(robot, checker, reference, the pairs checked) of ``name`` in the cell."""
    from kin.collision import CollisionChecker, load_collision_model

    if name == "ur5-urdf":  # the maker's meshes (as hulls)
        robot = load_robot(erd("ur_description/urdf/ur5_robot.urdf"), None, "tool0")
        path, base, _ = robot.urdf_source
        text = Path(path).read_text(encoding="utf-8")
        reference = CollisionReference(text, Path(path), robot.joint_names, base, CELL)
    else:  # a DH table's link cylinders
        robot = load_robot(name)
        reference = CollisionReference(robot.urdf, None, robot.joint_names, None, CELL)
    model = load_collision_model(robot, scene=CELL)
    return robot, CollisionChecker(model), reference, [tuple(p) for p in model.pairs]


def deepest(name: str, q: np.ndarray) -> float:
    """The reference's smallest signed distance over the checked pairs at ``q`` [m]."""
    _, _, reference, pairs = setup(name)
    return min(d for d, _ in reference.signed_distances(q, pairs).values())


def random_segments(name: str, count: int, seed: int, length: float) -> np.ndarray:
    """``count`` two-sample joint paths, each a step of ``length`` [rad] in a random direction."""
    robot = setup(name)[0]
    rng = np.random.default_rng(seed)
    start = rng.uniform(robot.lower, robot.upper, (count, robot.nq))
    step = rng.normal(size=(count, robot.nq))
    step *= length / np.linalg.norm(step, axis=1, keepdims=True)
    return np.stack([start, start + step], axis=1)


@pytest.mark.parametrize("name", ["ur5-urdf", "humanoid7"])
def test_sample_verdicts_are_the_references(name):
    """Each sample of a joint path is judged colliding exactly when coal called directly says so."""
    robot, checker, _, _ = setup(name)
    rng = np.random.default_rng(3)
    a, b = rng.uniform(robot.lower, robot.upper, (2, robot.nq))
    q = a + np.linspace(0.0, 1.0, 40)[:, None] * (b - a)
    result = check_path_collisions(checker, q)
    expected = [deepest(name, row) for row in q]
    compared = 0
    for index, distance in enumerate(expected):
        if abs(distance) > CONTACT_TOL:
            assert result.sample_collisions[index] == (distance < 0), f"{name=} {index=}"
            compared += 1
    assert compared >= 38, f"{name=}"
    assert result.free == (min(expected) > 0 and result.first is None), f"{name=}"


@pytest.mark.parametrize("name", ["ur5-urdf", "humanoid7"])
def test_motion_between_free_samples_is_never_called_free_when_it_collides(name):
    """Two free samples with a collision between them (by the reference, densely): not free."""
    hidden = free = 0
    for q in random_segments(name, 120, seed=11, length=1.5):
        if deepest(name, q[0]) <= CONTACT_TOL or deepest(name, q[1]) <= CONTACT_TOL:
            continue
        t = np.linspace(0.0, 1.0, DENSE + 1)[1:-1]
        between = min(deepest(name, q[0] + s * (q[1] - q[0])) for s in t)
        result = check_path_collisions(setup(name)[1], q)
        if between < -CONTACT_TOL:
            hidden += 1
            assert not result.free, f"{name=} q={q.tolist()}: called free, reference {between}"
            first = result.first
            assert first is not None and not first.at_sample and first.segment == 0
            assert 0.0 < first.fraction < 1.0
            if first.proven:  # the reference sees the named pair in contact there (one verdict)
                distances = setup(name)[2].signed_distances(first.q, [(first.a, first.b)])
                assert distances[(first.a, first.b)][0] < CONTACT_TOLERANCE + CONTACT_TOL, (
                    f"{name=}"
                )
        if result.free:
            free += 1
            assert between > -CONTACT_TOL, f"{name=} q={q.tolist()}"
    assert hidden >= 1 and free >= 1, f"{name=}: {hidden=} {free=} (the test must see both)"


def test_a_ball_between_two_samples_is_named(tmp_path):
    """A ball on the tool's way between two far samples: segment 0, the tool's link and the ball."""
    from kin.batch_fk import batch_forward_kinematics
    from kin.collision import CollisionChecker, load_collision_model

    robot = load_robot("ur5")
    q = np.array([[0.5, -1.4, -2.0, -1.2, 1.57, -1.0], [-0.5, -1.4, -2.0, -1.2, 1.57, -1.0]])
    middle = batch_forward_kinematics(robot.table, q.mean(axis=0)[None])[0, :3, 3]  # the tool
    scene = tmp_path / "ball.toml"
    scene.write_text(
        f"[[sphere]]\nname = 'ball'\nradius = 0.03\nxyz = {middle.tolist()}\n", encoding="utf-8"
    )
    checker = CollisionChecker(load_collision_model(robot, scene=scene))
    result = check_path_collisions(checker, q)
    assert not result.sample_collisions.any()
    first = result.first
    assert first is not None and first.proven and not first.at_sample
    assert first.segment == 0 and first.b == "ball" and first.kind == "scene"
    assert 0.0 < first.fraction < 0.5
    assert "between samples 0 and 1" in first.describe()


#: In the maker's base frame (the shipped ur5 since issue 43): in front of the base, tool down.
UR5_LINE = ["--robot", "ur5", "--steps", "20", "--from", "-0.4", "-0.1", "0.3", "--rpy", "3.14159", "0", "3.14159", "--to", "-0.4", "0.3", "0.3", "--rpy", "3.14159", "0", "3.14159"]  # fmt: skip


def test_kin_path_with_a_far_scene_is_free(tmp_path, capsys):
    """Exit 0, the JSON says free and states the rule."""
    scene = tmp_path / "far.toml"
    scene.write_text("[[sphere]]\nradius = 0.05\nxyz = [1.0, 1.0, 1.0]\n", encoding="utf-8")
    code = call(path_command.main, UR5_LINE + ["--scene", str(scene), "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    record = json.loads(out)["collisions"]
    assert record["free"] is True and record["first"] is None and "d0 + d1" in record["rule"]


def test_kin_path_through_a_ball_exits_1_with_one_line(tmp_path, capsys):
    """A ball on the line: exit 1, one stderr line naming the sample and the pair."""
    scene = tmp_path / "ball.toml"
    scene.write_text("[[sphere]]\nradius = 0.03\nxyz = [-0.4, 0.1, 0.3]\n", encoding="utf-8")
    code = call(path_command.main, UR5_LINE + ["--scene", str(scene)])
    out, err = capsys.readouterr()
    assert code == 1
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "the path collides:" in lines[0] and "/ sphere" in lines[0]
    assert "collisions: IN COLLISION" in out


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--scene", "/nonexistent/cell.toml"], "cell.toml"),
        (["--padding", "0.01"], "--padding needs --scene or --srdf"),
    ],
)
def test_bad_collision_input_exits_2(capsys, extra, needle):
    """A missing scene, or --padding alone: one line, exit 2."""
    code = call(path_command.main, UR5_LINE + extra)
    assert_one_line_error(code, capsys.readouterr().err, needle)
