"""Angles of any size in tables and targets are reduced modulo a turn, exactly, before use."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from dh2urdf import get_robot
from dh2urdf.units import ANGLE_UNITS, angle_to_radians
from kin.commands import fk, ik

HUGE = 1e18
#: 1e18 deg reduced by hand, in degrees (exact: fmod on floats is exact).
REDUCED = math.fmod(HUGE, 360.0)


def _puma_with(tmp_path, name: str, angle: float):
    """PUMA 560's table (degrees) with joint 2's theta and alpha (0 there) set to ``angle`` [deg]."""
    text = get_robot("puma560").table_path.read_text(encoding="utf-8")
    parts = text.split("[[joints]]")  # the preamble, then one part per row
    assert "alpha = 0.0" in parts[2] and "theta = 0.0" in parts[2]
    parts[0] = parts[0].replace('name = "puma560"', f'name = "{name}"')
    parts[2] = parts[2].replace("alpha = 0.0", f"alpha = {angle!r}")
    parts[2] = parts[2].replace("theta = 0.0", f"theta = {angle!r}")
    path = tmp_path / f"{name}.toml"
    path.write_text("[[joints]]".join(parts), encoding="utf-8")
    return str(path)


def _json(capsys, main, argv: list[str], codes: tuple[int, ...] = (0,)) -> dict:
    assert main([*argv, "--json"]) in codes, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def test_angle_to_radians_reduces_before_converting():
    """1e18 deg is fmod(1e18, 360) = 280 deg; small angles are only converted."""
    deg = ANGLE_UNITS["deg"]
    assert REDUCED == 280.0
    assert angle_to_radians(HUGE, deg) == 280.0 * deg
    assert angle_to_radians(-HUGE, deg) == -280.0 * deg
    assert angle_to_radians(90.0, deg) == 90.0 * deg
    assert angle_to_radians(1.5, 1.0) == 1.5


def test_a_table_angle_of_1e18_deg_gives_the_reduced_tables_fk_and_ik(tmp_path, capsys):
    """theta and alpha of 1e18 deg: the same FK and IK answers as 280 deg written by hand."""
    huge = _puma_with(tmp_path, "puma_huge", HUGE)
    reduced = _puma_with(tmp_path, "puma_reduced", REDUCED)
    q = ["0.3", "-0.5", "0.4", "0.2", "0.6", "-0.1"]
    poses = [_json(capsys, fk.main, ["--robot", path, "--q", *q]) for path in (huge, reduced)]
    assert poses[0]["position_m"] == poses[1]["position_m"]
    assert poses[0]["rotation"] == poses[1]["rotation"]
    target = [str(v) for v in poses[1]["position_m"]]
    rpy = [str(v) for v in poses[1]["rpy"]]
    answers = [
        _json(capsys, ik.main, ["--robot", path, "--target", *target, "--rpy", *rpy])
        for path in (huge, reduced)
    ]
    assert answers[0]["status"] == answers[1]["status"] == "ok", answers[0]["message"]
    first, second = answers[0]["solutions"], answers[1]["solutions"]
    assert [s["q"] for s in first] == [s["q"] for s in second]
    assert any(np.allclose(s["q"], [float(v) for v in q], atol=1e-6) for s in first)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_a_target_rpy_of_1e18_deg_is_the_reduced_one(sign, capsys):
    """--rpy 1e18 ... --deg answers as --rpy 280 ... --deg."""
    argv = ["--robot", "puma560", "--target", "0.4", "0.1", "0.3", "--deg"]
    huge = _json(capsys, ik.main, [*argv, "--rpy", str(sign * HUGE), "20", "0"], (0, 1))
    reduced = _json(capsys, ik.main, [*argv, "--rpy", str(sign * REDUCED), "20", "0"], (0, 1))
    assert huge["status"] == reduced["status"]
    for key in ("solutions", "rejected"):
        assert [s["q"] for s in huge[key]] == [s["q"] for s in reduced[key]], f"{key=}"
    assert huge["solutions"] or huge["rejected"]
