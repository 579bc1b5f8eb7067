"""``kin check``: the verdict, the exit codes (0 free, 1 in collision, 2 bad input), JSON in SI."""

from __future__ import annotations

import json
import math

from support.cli_helper import assert_one_line_error, call
from support.stick_arms import stick_table_file

from kin.commands import check

FOLDED = ["0", "-1.5", "3.1", "0", "0", "0"]  # UR5's forearm back onto its upper arm


def test_free_configuration_exits_0(capsys):
    """UR5 at zero is free: exit 0, the closest pair printed."""
    assert call(check.main, ["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("ur5: collision-free") and "closest:" in out and "\ncontact" not in out


def test_folded_configuration_exits_1_with_the_pair(capsys):
    """The folded UR5 collides (upper arm / forearm cylinders): exit 1, the pair and its depth."""
    assert call(check.main, ["--robot", "ur5", "--q", *FOLDED]) == 1
    out = capsys.readouterr().out
    assert "IN COLLISION" in out and "contact (self): link2 / frame3" in out


def test_degrees_and_json_scene(capsys, tmp_path):
    """--deg reads degrees; --json is SI; a ball 0.04 m from the base cylinder (hand-computed)."""
    scene = tmp_path / "cell.toml"
    scene.write_text('[[sphere]]\nname = "ball"\nradius = 0.1\nxyz = [0, 0.15, 0.03]\n')
    sticks = str(stick_table_file("ur5", tmp_path))  # the base: a 1 cm cylinder on z
    argv = ["--robot", sticks, "--q", "0", "0", "0", "0", "0", "0", "--deg", "--json"]
    assert call(check.main, [*argv, "--scene", str(scene)]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["in_collision"] is False and record["contacts"] == []
    assert (record["closest"]["a"], record["closest"]["b"]) == ("frame0", "ball")
    assert math.isclose(record["closest"]["distance_m"], 0.04, abs_tol=1e-9)
    folded = [str(math.degrees(float(v))) for v in FOLDED]
    argv = ["--robot", sticks, "--q", *folded, "--deg", "--json", "--padding", "50", "--unit", "mm"]
    assert call(check.main, [*argv, "--scene", str(scene)]) == 1
    record = json.loads(capsys.readouterr().out)
    assert record["in_collision"] and math.isclose(record["q"][2], 3.1)
    assert "padding 0.05 m" in record["shapes"]


def test_bad_input_is_one_line_exit_2(capsys, tmp_path):
    """A NaN size, a missing scene, a wrong joint count: one line on stderr, exit 2."""
    scene = tmp_path / "bad.toml"
    scene.write_text("[[box]]\nsize = [0.1, nan, 0.1]\n")
    cases = [
        (["--scene", str(scene)], "box[0].size[1]"),
        (["--scene", str(tmp_path / "none.toml")], "none.toml"),
        (["--srdf", str(scene)], "not XML"),
        (["--padding", "-1"], "padding"),
    ]
    for extra, needle in cases:
        code = call(check.main, ["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0", *extra])
        assert_one_line_error(code, capsys.readouterr().err, needle)
    code = call(check.main, ["--robot", "ur5", "--q", "0", "0"])
    assert_one_line_error(code, capsys.readouterr().err, "--q needs 6 values")
