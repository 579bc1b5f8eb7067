"""``kin collisions --write-srdf``: the disabled pairs as MoveIt's setup assistant finds them.

The command on Panda's URDF (tip ``panda_hand``, fingers held closed) at 1,000 samples, seed 0:
the file, its comment, its bytes, and what it leaves checked. The comparison with the makers'
SRDFs is tests/collision/test_collision_srdf_makers.py; the rules on tiny URDFs
tests/collision/test_collision_srdf_rules.py.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from functools import cache
from pathlib import Path

import pytest
from support.urdf_reference import erd

from kin import load_robot
from kin.commands import main as kin_main

PANDA = "panda_description/urdf/panda.urdf"


def srdf_pairs(path: Path) -> dict[tuple[str, str], str]:
    """``(link1, link2)`` (sorted) -> reason of an SRDF's ``disable_collisions``."""
    root = ET.parse(path).getroot()
    return {
        tuple(sorted((e.get("link1"), e.get("link2")))): e.get("reason")
        for e in root.iter("disable_collisions")
    }


@cache
def panda_generated(tmp: Path) -> Path:
    """The SRDF ``kin collisions`` writes for Panda to ``panda_hand`` (1,000 samples)."""
    out = tmp / "panda.srdf"
    argv = ["--robot", str(erd(PANDA)), "--tip", "panda_hand", "--write-srdf", str(out)]
    assert kin_main(["collisions", *argv, "--samples", "1000", "--random-seed", "0"]) == 0
    return out


@pytest.fixture(scope="module")
def generated(tmp_path_factory) -> Path:
    return panda_generated(tmp_path_factory.mktemp("srdf"))


def test_the_written_srdf_leaves_the_kept_pairs(generated):
    """Loaded back, the SRDF leaves the 55 - 37 = 18 pairs the samples saw touching."""
    from kin.collision import load_collision_model

    robot = load_robot(erd(PANDA), None, "panda_hand")
    everything = load_collision_model(robot)
    reduced = load_collision_model(robot, srdf=generated)
    assert len(everything.links) == 11
    assert len(srdf_pairs(generated)) == 37
    assert len(reduced.pairs) == 18
    assert {tuple(sorted(p)) for p in reduced.pairs}.isdisjoint(srdf_pairs(generated))


def test_same_samples_and_seed_same_bytes(tmp_path, generated):
    """The output is reproducible; its comment states the rules, count, seed and held joints."""
    again = tmp_path / "again.srdf"
    argv = ["--robot", str(erd(PANDA)), "--tip", "panda_hand", "--write-srdf", str(again)]
    assert kin_main(["collisions", *argv, "--samples", "1000"]) == 0
    assert again.read_bytes() == generated.read_bytes()
    text = again.read_text()
    assert "more than 190 of 200 states of a batch (fraction 0.95)" in text
    assert "none of the batches' states and 1000 more" in text
    assert "default_rng(0)" in text
    assert "held still, not sampled: panda_finger_joint1 = 0 m" in text


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
