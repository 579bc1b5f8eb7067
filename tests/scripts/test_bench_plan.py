"""scripts/bench_plan.py --quick: the tables' columns, and every path kin returns certified.

The certification is the script's own reference (Pinocchio + coal built apart from kin, every
0.005 rad of joint motion), so this test fails when kin returns a path that touches the cell
between its joint vectors. Times are printed, never judged.
"""

from __future__ import annotations

import re

import pytest
from support.scripts_helper import SCRIPTS, load_script

HEADER = [
    "planner",
    "solved",
    "median [ms]",
    "p95 [ms]",
    "length [rad]",
    "/straight",
    "certified",
    "closest [mm]",
]


@pytest.mark.slow
def test_quick_bench_certifies_every_kin_path(capsys, monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPTS))  # the script's own modules (plan_problems...)
    assert load_script("bench_plan").main(["--quick", "--no-mplib"]) == 0
    out = capsys.readouterr().out
    tables = re.findall(r"\n(panda|ur5) / (\w+): 1 problems\n(.*)\n((?:.+\n?)+)", out)
    assert len(tables) == 8, out  # two arms, four scenes, one problem each
    solved = 0
    for _, _, header, body in tables:
        assert header.split()[0] == "planner" and all(c in header for c in HEADER), header
        rows = {line.split()[0]: line for line in body.strip().splitlines()}
        assert {"kin", "ompl+coal"} <= set(rows), body
        kin = rows["kin"].split()
        if kin[1] == "100%":  # kin returned a path: the reference must find it free
            solved += 1
            assert kin[6] == "100%", rows["kin"]
            assert float(kin[7]) > 0.0, rows["kin"]  # the smallest distance seen [mm]
        else:
            assert kin[1] == "0%" and kin[6] == "-", rows["kin"]
    assert solved >= 6, out  # a hard problem may meet the 5 s cap on a loaded machine
