"""The audit of a robot given as a URDF (issue #17): its chain read as the table under audit."""

from __future__ import annotations

import json

from support.cli_helper import call
from support.urdf_reference import ARMS, erd

from kin.commands.audit import main


def test_a_urdf_audited_against_itself_is_reproduced_as_written(capsys):
    """UR5's URDF as TABLE (chain to tool0) against the same URDF: the extracted table as written
    reproduces it (1e-6 m and rad), so --check exits 0."""
    urdf = str(erd(ARMS["ur5"][0]))
    argv = [urdf, "--tip", "tool0", "--urdf", urdf, "--frame", "tool0", "--count", "20"]
    assert call(main, [*argv, "--json", "--check", "--singles"]) == 0
    report = json.loads(capsys.readouterr().out)
    best = report["readings"][0]
    assert best["changes"] == [] and best["reproduced"]


def test_base_and_tip_need_a_urdf_table(capsys):
    """--tip with a .toml table: exit 2, one line saying what it goes with."""
    urdf = str(erd(ARMS["ur5"][0]))
    assert call(main, ["ur5", "--tip", "tool0", "--urdf", urdf, "--frame", "tool0"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--base and --tip go with a URDF TABLE" in err
