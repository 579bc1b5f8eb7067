"""Scenes beyond the bounds are bad input; padding never removes a pair; large scenes answer.

Work, not time, is asserted here (the same on a busy machine): a scene over the cap is refused
before any shape is built. How long loading and refusing take: scripts/bench_scene_size.py.

Issue 42: a box at xyz = 1e308 or a cylinder 1e308 m long was "IN COLLISION" with NaN points;
``--padding 1`` reported "collision-free, pairs checked: 0" (every self pair dropped as "always in
contact"); 10,000 scene boxes gave no answer after 200 s (Pinocchio's geometry model copies a
square matrix of its objects at each one added).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from kin import load_robot
from kin.collision import CollisionChecker, CollisionModelError, load_collision_model
from kin.collision.bounds import MAX_SHAPES


@pytest.fixture(scope="module")
def ur5():
    return load_robot("ur5")


@pytest.mark.parametrize(
    ("entry", "field"),
    [
        ("[[box]]\nsize = [0.1, 0.1, 0.1]\nxyz = [1e308, 0, 0]", "box[0].xyz[0]"),
        ("[[cylinder]]\nradius = 0.1\nlength = 1e308", "cylinder[0].length"),
        ("[[box]]\nsize = [0.1, 11.0, 0.1]", "box[0].size[1]"),
        ("[[sphere]]\nradius = 0.1\nxyz = [0, -1001, 0]", "sphere[0].xyz[1]"),
        ("[[sphere]]\nradius = 1e-400", "sphere[0].radius"),
    ],
)
def test_sizes_and_places_beyond_the_bounds_are_bad_input(ur5, tmp_path, entry, field):
    """One error naming the file and the field; no model, no NaN."""
    scene = tmp_path / "scene.toml"
    scene.write_text(entry + "\n", encoding="utf-8")
    with pytest.raises(CollisionModelError, match=re.escape(f"scene.toml: {field}: ")):
        load_collision_model(ur5, scene=scene)


def test_padding_beyond_the_bound_is_bad_input(ur5):
    with pytest.raises(CollisionModelError, match="padding"):
        load_collision_model(ur5, padding=1e308)


@pytest.mark.parametrize("padding", [0.2, 1.0])
def test_padding_never_removes_a_pair(ur5, padding):
    """ur5 with 1 m of padding: every pair checked without padding is checked, and collides."""
    plain = load_collision_model(ur5)
    padded = load_collision_model(ur5, padding=padding)
    assert padded.pairs == plain.pairs and len(plain.pairs) > 0
    assert padded.disabled == plain.disabled
    checker = CollisionChecker(padded)
    q = np.zeros(ur5.nq)
    if padding == 1.0:
        assert checker.in_collision(q) and len(checker.collisions(q)) == len(padded.pairs)


def _boxes(path, count: int) -> None:
    centres = np.random.default_rng(0).uniform(-20.0, 20.0, (count, 3)) + [0.0, 0.0, 30.0]
    path.write_text(
        "".join(
            f"[[box]]\nsize = [0.05, 0.05, 0.05]\nxyz = [{x}, {y}, {z}]\n" for x, y, z in centres
        ),
        encoding="utf-8",
    )


@pytest.fixture
def built_boxes(monkeypatch):
    """The coal boxes built while the test runs (a scene's boxes are made one by one)."""
    import coal

    made: list[object] = []
    real = coal.Box

    def counted(*args):
        made.append(args)
        return real(*args)

    monkeypatch.setattr(coal, "Box", counted)
    return made


def test_twenty_thousand_boxes_are_refused_at_once(ur5, tmp_path, built_boxes):
    """More than MAX_SHAPES shapes: one line naming the count and the cap, no shape built."""
    scene = tmp_path / "boxes.toml"
    _boxes(scene, 20_000)
    said = f"20000 shapes; a scene holds at most {MAX_SHAPES:,}"
    with pytest.raises(CollisionModelError, match=said):
        load_collision_model(ur5, scene=scene)
    assert built_boxes == []


@pytest.mark.slow
def test_a_hundred_thousand_boxes_are_refused_before_any_is_built(ur5, tmp_path, built_boxes):
    scene = tmp_path / "boxes.toml"
    _boxes(scene, 100_000)
    with pytest.raises(CollisionModelError, match="100000 shapes"):
        load_collision_model(ur5, scene=scene)
    assert built_boxes == []


def test_a_scene_at_the_cap_loads_and_answers(ur5, tmp_path, built_boxes):
    """MAX_SHAPES boxes: loaded (each built once), and every query answers, by the broad phase."""
    scene = tmp_path / "boxes.toml"
    _boxes(scene, MAX_SHAPES)
    checker = CollisionChecker(load_collision_model(ur5, scene=scene))
    q = np.zeros(ur5.nq)
    qs = np.random.default_rng(1).uniform(ur5.lower, ur5.upper, (50, ur5.nq))
    verdicts = checker.in_collision_batch(qs)
    assert checker.broad_phase
    assert [checker.in_collision(x) for x in qs] == verdicts.tolist()
    assert bool(checker.collisions(q)) == checker.in_collision(q)
    assert np.isfinite(checker.distance(q).distance)
    assert len(built_boxes) == MAX_SHAPES


@pytest.mark.parametrize(
    ("geometry", "origin", "field"),
    [
        ('<box size="0.1 20 0.1"/>', "0 0 0", "collision[0].size"),
        ('<cylinder radius="0.1" length="1e308"/>', "0 0 0", "collision[0].length"),
        ('<sphere radius="0.1"/>', "1e308 0 0", "collision[0].origin.xyz"),
    ],
)
def test_a_cell_urdf_beyond_the_bounds_is_bad_input(ur5, tmp_path, geometry, origin, field):
    """A URDF scene's shape obeys the bounds of a TOML scene's: one error naming the field."""
    cell = tmp_path / "cell.urdf"
    cell.write_text(
        '<robot name="cell"><link name="post"><collision>'
        f'<origin xyz="{origin}"/><geometry>{geometry}</geometry>'
        "</collision></link></robot>",
        encoding="utf-8",
    )
    with pytest.raises(CollisionModelError, match=re.escape(field)):
        load_collision_model(ur5, scene=cell)
