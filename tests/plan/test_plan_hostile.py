"""``kin plan --stdin`` under hostile lines (hypothesis): exactly one JSON answer per input line,
in order, whatever each holds (non-finite and extreme joint values, wrong lengths, wrong types,
unknown keys, named states, broken JSON); never an internal error, stderr empty.
"""

from __future__ import annotations

import io
import json
import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support.cli_helper import call

from kin.commands import plan as plan_command

#: Joint values a hostile client may send (JSON allows NaN and Infinity as Python writes them).
VALUE = st.one_of(
    st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 1.5, -1.5, 3.2, 1e200, -1e308, 1e308]),
    st.sampled_from([math.nan, math.inf, -math.inf]),
    st.floats(min_value=-3.2, max_value=3.2),
    st.booleans(),
    st.text(max_size=4),
    st.none(),
)
JOINTS = st.one_of(
    st.lists(VALUE, min_size=2, max_size=2),
    st.lists(VALUE, max_size=4),
    st.sampled_from(["home", "nowhere", "", 5, None, {}]),
)
KEYS = st.sampled_from(
    ["planner", "seed", "time_limit", "max_checks", "deg", "time", "rpy", "speed", "target"]
)
ODD = st.one_of(VALUE, st.sampled_from(["RRT", "RRTx", -1, 0, 2**70, [0, 0, 0], "PRM"]))


@st.composite
def lines(draw: st.DrawFn) -> str:
    """One request line: a start, a goal or target, a few other keys; or broken text."""
    if draw(st.integers(0, 9)) == 0:
        return draw(st.sampled_from(["not json", "[1, 2]", "{", '"x"', "null", "{}" * 3]))
    record: dict = {"start": draw(JOINTS)}
    if draw(st.booleans()):
        record["goal"] = draw(JOINTS)
    else:
        record["target"] = draw(st.lists(VALUE, min_size=0, max_size=4))
    for _ in range(draw(st.integers(0, 2))):
        record[draw(KEYS)] = draw(ODD)
    record.setdefault("max_checks", 300)  # a bounded plan per line (the default is 200,000)
    return json.dumps(record)


@settings(
    max_examples=15,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(requests=st.lists(lines(), min_size=1, max_size=5))
def test_every_hostile_line_gets_one_answer_in_order(requests, monkeypatch, capsys):
    monkeypatch.setattr("sys.stdin", io.StringIO("\n".join(requests) + "\n"))
    code = call(plan_command.main, ["--robot", "planar2", "--stdin", "--time-limit", "60"])
    captured = capsys.readouterr()
    answers = [json.loads(line) for line in captured.out.splitlines()]
    assert [answer["line"] for answer in answers] == list(range(1, len(requests) + 1))
    assert captured.err == ""
    failed = any("error" in a or a.get("status") != "ok" for a in answers)
    assert code == (1 if failed else 0)
    internal = [a for a in answers if "internal error" in a.get("error", "")]
    assert not internal, internal
    for answer in answers:
        assert len(answer.get("error", "")) < 600, answer["error"][:700]
