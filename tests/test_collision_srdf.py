"""``kin collisions --write-srdf``: the disabled pairs as MoveIt's setup assistant finds them.

Compared with the maker's SRDF of Panda (example-robot-data's ``panda.srdf``, written by MoveIt's
assistant) on the chain ``panda_link0`` .. ``panda_hand`` at 10,000 samples, seed 0:

* pairs ours disables that the maker's keeps: none;
* pairs the maker's disables that ours keeps: none either;
* pairs the maker's disables that ours does not know: the nine with ``panda_leftfinger`` or
  ``panda_rightfinger``. The fingers hang off ``panda_hand`` by prismatic joints, beside the
  chain from base to tip, and a kin collision model holds the chain's links only; the maker's
  assistant saw the whole tree (fingers adjacent to the hand, touching each other at the default
  opening, never reaching links 3, 4, 6, 7).

On the 24 pairs both know, the reasons agree too (``panda_hand``/``panda_link5`` and
``panda_link5``/``panda_link7`` "Default": touching with every joint at 0).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from functools import cache
from pathlib import Path

import pytest
from urdf_reference import erd

from kin import load_robot
from kin.commands import main as kin_main

PANDA = "panda_description/urdf/panda.urdf"
FINGER_PAIRS = {
    ("panda_hand", "panda_leftfinger"),
    ("panda_hand", "panda_rightfinger"),
    ("panda_leftfinger", "panda_link3"),
    ("panda_leftfinger", "panda_link4"),
    ("panda_leftfinger", "panda_link6"),
    ("panda_leftfinger", "panda_link7"),
    ("panda_leftfinger", "panda_rightfinger"),
    ("panda_link3", "panda_rightfinger"),
    ("panda_link4", "panda_rightfinger"),
    ("panda_link6", "panda_rightfinger"),
    ("panda_link7", "panda_rightfinger"),
}


def srdf_pairs(path: Path) -> dict[tuple[str, str], str]:
    """``(link1, link2)`` (sorted) -> reason of an SRDF's ``disable_collisions``."""
    root = ET.parse(path).getroot()
    return {
        tuple(sorted((e.get("link1"), e.get("link2")))): e.get("reason")
        for e in root.iter("disable_collisions")
    }


@cache
def panda_generated(tmp: Path) -> Path:
    """The SRDF ``kin collisions`` writes for Panda's chain to ``panda_hand`` (10,000 samples)."""
    out = tmp / "panda.srdf"
    argv = ["--robot", str(erd(PANDA)), "--tip", "panda_hand", "--write-srdf", str(out)]
    assert kin_main(["collisions", *argv, "--samples", "10000", "--random-seed", "0"]) == 0
    return out


@pytest.fixture(scope="module")
def generated(tmp_path_factory) -> Path:
    return panda_generated(tmp_path_factory.mktemp("srdf"))


def test_panda_against_the_makers_srdf(generated):
    """Ours disables what the maker's does on the chain, with the same reasons; fingers apart."""
    ours = srdf_pairs(generated)
    maker = srdf_pairs(erd("panda_description/srdf/panda.srdf"))
    assert sorted(set(ours) - set(maker)) == []
    assert set(maker) - set(ours) == FINGER_PAIRS
    assert {p: maker[p] for p in ours} == ours
    assert len(ours) == 24


def test_the_written_srdf_leaves_the_kept_pairs(generated):
    """Loaded back, the SRDF leaves the 36 - 24 = 12 pairs the samples saw touching."""
    from kin.collision import load_collision_model

    robot = load_robot(erd(PANDA), None, "panda_hand")
    everything = load_collision_model(robot)
    reduced = load_collision_model(robot, srdf=generated)
    assert len(everything.pairs) + sum(r == "adjacent" for r in everything.disabled.values()) == 36
    assert len(reduced.pairs) == 12
    assert {tuple(sorted(p)) for p in reduced.pairs}.isdisjoint(srdf_pairs(generated))


def test_same_samples_and_seed_same_bytes(tmp_path, generated):
    """The output is reproducible; its comment states the sample count and the seed."""
    again = tmp_path / "again.srdf"
    argv = ["--robot", str(erd(PANDA)), "--tip", "panda_hand", "--write-srdf", str(again)]
    assert kin_main(["collisions", *argv, "--samples", "10000"]) == 0
    assert again.read_bytes() == generated.read_bytes()
    text = again.read_text()
    assert "10000 configurations uniform within the joint limits" in text
    assert "default_rng(0)" in text


def test_humanoid7_reasons(tmp_path):
    """The DH cylinders of humanoid7: three adjacent pairs, three never touching."""
    out = tmp_path / "h.xml"
    argv = ["--robot", "humanoid7", "--write-srdf", str(out), "--samples", "2000"]
    assert kin_main(["collisions", *argv]) == 0
    assert srdf_pairs(out) == {
        ("frame2", "frame4"): "Adjacent",
        ("frame2", "link1"): "Adjacent",
        ("frame4", "link7"): "Adjacent",
        ("frame2", "link7"): "Never",
        ("frame4", "link1"): "Never",
        ("link1", "link7"): "Never",
    }


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        (["--samples", "0"], "--samples"),
        (["--random-seed", "-1"], "--random-seed"),
        (["--write-srdf", "/dev/full"], "character device"),
        (["--write-srdf", "{tmp}/missing/x.srdf"], "does not exist"),
        (["--write-srdf", "{tmp}/x.txt"], "unknown file type"),
        (["--robot", "no_such_robot"], "no_such_robot"),
    ],
)
def test_bad_input_one_line_exit_2_nothing_written(tmp_path, capsys, extra, words):
    """Bad options: exit 2, one line naming the option, no file."""
    argv = ["--robot", "humanoid7", "--write-srdf", str(tmp_path / "out.srdf"), "--samples", "5"]
    argv += [a.replace("{tmp}", str(tmp_path)) for a in extra]
    try:
        code = kin_main(["collisions", *argv])
    except SystemExit as exit_:  # argparse's own errors
        code = exit_.code
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and words in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == []
