"""MoveIt's setup-assistant rules in ``generate_disabled_pairs``, on tiny URDFs made to show each.

The expected pairs are read off the drawings (which links touch where), not computed: the rules
are those of ``compute_default_collisions.cpp`` (cited in kin/collision/srdf_generator.py).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from kin import load_robot
from kin.collision import CollisionModelError, load_collision_model
from kin.collision.srdf_generator import (
    ALWAYS_BATCH,
    ALWAYS_FRACTION,
    default_state,
    generate_disabled_pairs,
    srdf_text,
)

#: base holds a box over x in [0.03, 1.10] m; slider's 1 cm sphere slides along x in [0, 1] m
#: (prismatic ``slide``), so base and slider touch for x >= 0.02 m: in 98 % of uniform states,
#: not at x = 0 (the default state). ``mid`` (a far sphere) sits between them, so they are not
#: adjacent. ``cap`` and ``clamp`` ride rigidly on ``mid``, not adjacent to ``base``: cap's
#: sphere is 3 m away, clamp's box overlaps base's box.
SLIDE = """<robot name="slide">
  <link name="base"><collision><origin xyz="0.565 0 0"/>
    <geometry><box size="1.07 0.2 0.2"/></geometry></collision></link>
  <link name="mid"><collision><origin xyz="0 0 -3"/>
    <geometry><sphere radius="0.01"/></geometry></collision></link>
  <link name="cap"><collision><origin xyz="0 0 3"/>
    <geometry><sphere radius="0.01"/></geometry></collision></link>
  <link name="clamp"><collision><origin xyz="0.5 0 0.1"/>
    <geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="slider"><collision><geometry><sphere radius="0.01"/></geometry></collision></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="mid"/></joint>
  <joint name="fix_cap" type="fixed"><parent link="mid"/><child link="cap"/></joint>
  <joint name="fix_clamp" type="fixed"><parent link="mid"/><child link="clamp"/></joint>
  <joint name="slide" type="prismatic"><parent link="mid"/><child link="slider"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""

#: ``hub`` (no geometry) joins base, side and arm; ``x1`` and ``x2`` (no geometry) join arm and
#: ball. Nothing touches: arm's sphere is 0.5 m out, ball 1.5 m, side 1 m below. ``turn`` may
#: move from 0.5 to 1.5 rad only (0 is outside). A transmission names ``turn`` too.
TREE = """<robot name="tree">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="hub"/>
  <link name="side"><collision><origin xyz="0 0 -1"/>
    <geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="arm"><collision><origin xyz="0.5 0 0"/>
    <geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="x1"/>
  <link name="x2"/>
  <link name="ball"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="to_hub" type="fixed"><parent link="base"/><child link="hub"/></joint>
  <joint name="to_side" type="fixed"><parent link="hub"/><child link="side"/></joint>
  <joint name="turn" type="revolute"><parent link="hub"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="0.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="to_x1" type="fixed"><parent link="arm"/><child link="x1"/>
    <origin xyz="0.5 0 0"/></joint>
  <joint name="to_x2" type="fixed"><parent link="x1"/><child link="x2"/>
    <origin xyz="0.5 0 0"/></joint>
  <joint name="to_ball" type="fixed"><parent link="x2"/><child link="ball"/></joint>
  <transmission name="t"><joint name="turn"/></transmission>
</robot>
"""


def _model(tmp_path: Path, text: str, tip: str):
    path = tmp_path / "arm.urdf"
    path.write_text(text)
    return load_collision_model(load_robot(path, None, tip))


@pytest.fixture
def slide(tmp_path):
    return _model(tmp_path, SLIDE, "slider")


def test_a_pair_touching_in_98_percent_of_states_is_always(slide):
    """MoveIt disables a pair in contact in more than 190 of 200 states; it was kept before."""
    assert (ALWAYS_BATCH, ALWAYS_FRACTION) == (200, 0.95)
    assert generate_disabled_pairs(slide, samples=50)[("base", "slider")] == "Always"


def test_the_fraction_is_an_argument(slide):
    """At a fraction of 0.995 (more than 199 of 200) the 98 % pair stays checked; the batch too."""
    disabled = generate_disabled_pairs(slide, samples=50, always_fraction=0.995)
    assert ("base", "slider") not in disabled
    again = generate_disabled_pairs(slide, samples=50, always_fraction=0.9, always_batch=100)
    assert again[("base", "slider")] == "Always"  # more than 90 of 100


def test_rigid_pairs_are_judged_by_contact_not_called_adjacent(slide):
    """Links riding on one joint but not joined by one: Default when touching, else Never."""
    disabled = generate_disabled_pairs(slide, samples=50)
    assert {p: r for p, r in disabled.items() if r != "Always"} == {
        ("base", "mid"): "Adjacent",
        ("cap", "mid"): "Adjacent",
        ("clamp", "mid"): "Adjacent",
        ("mid", "slider"): "Adjacent",
        ("base", "clamp"): "Default",
        ("base", "cap"): "Never",
        ("cap", "clamp"): "Never",
        ("cap", "slider"): "Never",
        ("clamp", "slider"): "Never",
    }


def test_adjacent_through_links_without_geometry(tmp_path):
    """A link without shapes joins all its neighbours, also in series and across branches."""
    model = _model(tmp_path, TREE, "ball")
    disabled = generate_disabled_pairs(model, samples=50)
    assert disabled == {
        ("arm", "ball"): "Adjacent",  # through x1 and x2
        ("arm", "base"): "Adjacent",  # through hub
        ("arm", "side"): "Adjacent",  # through hub, across its branches
        ("base", "side"): "Adjacent",
        ("ball", "base"): "Never",
        ("ball", "side"): "Never",
    }


def test_default_state_is_zero_or_mid_limits(tmp_path, slide):
    """0 where the limits hold it, else the middle of the limits (0.5..1.5 rad -> 1.0 rad)."""
    tree = _model(tmp_path, TREE, "ball")
    assert default_state(tree.robot).tolist() == [1.0]
    assert default_state(slide.robot).tolist() == [0.0]


def test_same_seed_same_bytes_and_the_rules_stated(slide):
    """The SRDF is reproducible and its comment states the fraction, batch, count and seed."""
    texts = [srdf_text("slide", generate_disabled_pairs(slide, 30, 7), 30, 7) for _ in range(2)]
    assert texts[0] == texts[1]
    assert "more than 190 of 200 states of a batch (fraction 0.95)" in texts[0]
    assert "none of the batches' states and 30 more" in texts[0]
    assert "default_rng(7)" in texts[0]
    other = srdf_text("slide", {}, 30, 7, always_fraction=0.9, always_batch=100)
    assert "more than 90 of 100 states of a batch (fraction 0.9)" in other


@pytest.mark.parametrize(
    ("arguments", "words"),
    [
        ({"samples": 0}, "samples must be at least 1"),
        ({"random_seed": -1}, "random_seed must be at least 0"),
        ({"always_fraction": 0.0}, "always_fraction must be in (0, 1]"),
        ({"always_fraction": float("nan")}, "always_fraction must be in (0, 1]"),
        ({"always_batch": 0}, "always_batch must be at least 1"),
    ],
)
def test_bad_arguments_one_error_naming_them(slide, arguments, words):
    """An argument out of range raises CollisionModelError naming it."""
    with pytest.raises(CollisionModelError, match=words.replace("(", r"\(").replace("]", r"\]")):
        generate_disabled_pairs(slide, **arguments)
