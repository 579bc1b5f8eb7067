"""scripts/bench_plan.py --quick: the tables' columns, and every path kin returns certified
(with and without the goal's whole-turn copies).

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
        assert {"kin", "kin+turns", "ompl+coal"} <= set(rows), body
        for name in ("kin", "kin+turns"):
            kin = rows[name].split()
            if kin[1] == "100%":  # kin returned a path: the reference must find it free
                solved += name == "kin"
                assert kin[6] == "100%", rows[name]
                assert float(kin[7]) > 0.0, rows[name]  # the smallest distance seen [mm]
            else:
                assert kin[1] == "0%" and kin[6] == "-", rows[name]
    assert solved >= 6, out  # a hard problem may meet the 5 s cap on a loaded machine
