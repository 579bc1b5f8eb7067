"""Hostile tables, URDFs and input lines: one line and exit 2, never a traceback.

Each finding of issue 33 through the commands (``kin fk``, ``kin ik``, ``dh2urdf from-urdf``,
table loading), then random malformed files (hypothesis) through the same commands.
"""

from __future__ import annotations

import io
import json
import math
import subprocess
import sys
import tempfile
import warnings
from datetime import timedelta
from pathlib import Path
from xml.sax.saxutils import quoteattr

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from support.scripts_helper import load_script

from dh2urdf import command as dh2urdf_command
from dh2urdf import from_urdf_command, load_table
from dh2urdf.exceptions import TableError
from dh2urdf.joint_cap import MAX_JOINTS
from kin.commands import fk, ik

ROOT = Path(__file__).resolve().parents[2]


def chain_urdf(n: int, lower: str = "-3", upper: str = "3", kind: str = "revolute") -> str:
    """A URDF chain of ``n`` joints of ``kind`` (alternately tilted), all with these limits."""
    parts = ['<robot name="chain">', '<link name="l0"/>']
    for i in range(1, n + 1):
        tilt = 0.3 if i % 2 else 0.0
        parts.append(
            f'<link name="l{i}"/><joint name="j{i}" type="{kind}"><parent link="l{i - 1}"/>'
            f'<child link="l{i}"/><origin xyz="0 0 0.1" rpy="0 {tilt} 0"/><axis xyz="0 0 1"/>'
            f'<limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/></joint>'
        )
    return "\n".join([*parts, "</robot>"])


def chain_table(n: int, limits: str = "[-3.0, 3.0]") -> str:
    """A DH table of ``n`` revolute rows in m and rad, all with these limits."""
    lines = ['convention = "standard"', 'length_unit = "m"', 'angle_unit = "rad"']
    for i in range(n):
        alpha = 0.5 if i % 2 else -0.5
        lines.append(
            f'[[joints]]\ntype = "revolute"\na = 0.1\nalpha = {alpha}\nd = 0.05\ntheta = 0.0\n'
            f"limits = {limits}"
        )
    return "\n".join(lines) + "\n"


def zeros(n: int) -> list[str]:
    """``n`` joint values of 0, as command-line words."""
    return ["0"] * n


#: The commands a robot file goes through: name -> (main, arguments after the file).
COMMANDS = {
    "kin fk": (fk.main, lambda path, n: ["--robot", path, "--q", *zeros(max(n, 1))]),
    "kin ik": (ik.main, lambda path, n: ["--robot", path, "--target", "0.1", "0.1", "0.3"]),
    "dh2urdf from-urdf": (from_urdf_command.main, lambda path, n: [path, "-o", "-"]),
    "dh2urdf": (dh2urdf_command.main, lambda path, n: [path, "-o", "-"]),
}


def run(name: str, path: Path, n: int, capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    """Exit code and stderr of command ``name`` on the robot file ``path`` of ``n`` joints."""
    main, argv = COMMANDS[name]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the commands print warnings as lines of their own
        code = main(argv(str(path), n))
    return code, capsys.readouterr().err


def assert_one_error_line(code: int, err: str, *needles: str) -> None:
    """Exit 2, one ``error:`` line holding every needle, no traceback."""
    errors = [line for line in err.splitlines() if "error:" in line]
    assert code == 2 and len(errors) == 1, (code, err[-2000:])
    assert "Traceback" not in err and len(errors[0]) < 1000, errors[0][:2000]
    assert all(needle in errors[0] for needle in needles), errors[0]


@pytest.mark.parametrize("name", ["kin fk", "kin ik", "dh2urdf from-urdf"])
def test_reversed_urdf_limits_name_the_joint_and_the_field(name, tmp_path, capsys):
    """<limit lower="3" upper="-3">: one line naming joint j1 and the limit, exit 2."""
    path = tmp_path / "reversed.urdf"
    path.write_text(chain_urdf(6, "3", "-3"), encoding="utf-8")
    code, err = run(name, path, 6, capsys)
    assert_one_error_line(code, err, "'j1'", "limit lower 3 is above upper -3")


@pytest.mark.parametrize("name", ["kin fk", "kin ik", "dh2urdf from-urdf"])
def test_huge_revolute_urdf_limits_are_unlimited(name, tmp_path, capsys):
    """Revolute limits of +-1e308 rad mean "no limits": read as continuous, no OverflowError."""
    path = tmp_path / "huge.urdf"
    path.write_text(chain_urdf(6, "-1e308", "1e308"), encoding="utf-8")
    code, err = run(name, path, 6, capsys)
    assert code in (0, 1) and "Traceback" not in err and "error" not in err, err


def test_huge_revolute_urdf_limits_give_a_continuous_table(tmp_path, capsys):
    """from-urdf writes the +-1e308 rad joints as continuous with limits [-pi, pi]."""
    path = tmp_path / "huge.urdf"
    path.write_text(chain_urdf(2, "-1e308", "1e308"), encoding="utf-8")
    table = tmp_path / "huge.toml"
    assert from_urdf_command.main([str(path), "-o", str(table)]) == 0
    rows = load_table(table).rows
    assert [(row.continuous, row.lower, row.upper) for row in rows] == [
        (True, -math.pi, math.pi)
    ] * 2


@pytest.mark.parametrize("name", ["kin fk", "kin ik", "dh2urdf from-urdf"])
def test_huge_prismatic_urdf_limits_are_refused(name, tmp_path, capsys):
    """A prismatic travel of 1e308 m: one line naming the joint and the 1e6 m bound."""
    path = tmp_path / "slide.urdf"
    path.write_text(chain_urdf(3, "-1e308", "1e308", "prismatic"), encoding="utf-8")
    code, err = run(name, path, 3, capsys)
    assert_one_error_line(code, err, "'j1'", "1e+06 m")


@pytest.mark.parametrize("value", ["inf", "nan", "1e999"])
def test_non_finite_urdf_limits_are_refused(value, tmp_path, capsys):
    """inf, nan or 1e999 in a URDF limit: the URDF parser's complaint, one line."""
    path = tmp_path / "inf.urdf"
    path.write_text(chain_urdf(6, f"-{value}", value), encoding="utf-8")
    code, err = run("kin fk", path, 6, capsys)
    assert_one_error_line(code, err, "j1")


@pytest.mark.parametrize("name", ["kin fk", "kin ik", "dh2urdf"])
def test_huge_table_limits_are_refused(name, tmp_path, capsys):
    """Revolute limits of +-1e308 rad in a table: one line naming the row, the field, the fix."""
    path = tmp_path / "huge.toml"
    path.write_text(chain_table(6, "[-1e308, 1e308]"), encoding="utf-8")
    code, err = run(name, path, 6, capsys)
    assert_one_error_line(code, err, "joint row 1, field 'limits'", "continuous = true")


@pytest.mark.parametrize(
    "document",
    ["a = " + "[" * 5000 + "]" * 5000, "a = " + "{x = " * 5000 + "1" + "}" * 5000],
    ids=["arrays", "inline-tables"],
)
def test_deeply_nested_toml_is_one_line(document, tmp_path, capsys):
    """5000 nested arrays or inline tables: a TableError, and one line from the commands."""
    path = tmp_path / "deep.toml"
    path.write_text(document, encoding="utf-8")
    with pytest.raises(TableError, match="nested too deep"):
        load_table(path)
    code, err = run("kin fk", path, 6, capsys)
    assert_one_error_line(code, err, "nested too deep")


def test_table_joint_cap(tmp_path, capsys):
    """64 rows load and give FK; 65 are refused in one line before any row is read."""
    path = tmp_path / "cap.toml"
    path.write_text(chain_table(MAX_JOINTS), encoding="utf-8")
    code, err = run("kin fk", path, MAX_JOINTS, capsys)
    assert code == 0 and "error" not in err, err
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # 64 links of 0.15 m: "millimeters?"
        assert load_table(path).dof == MAX_JOINTS
    path.write_text(chain_table(MAX_JOINTS + 1), encoding="utf-8")
    for name in ("kin fk", "kin ik", "dh2urdf"):
        code, err = run(name, path, MAX_JOINTS + 1, capsys)
        assert_one_error_line(code, err, "65 [[joints]] rows", f"at most {MAX_JOINTS}")


def test_urdf_joint_cap_is_checked_before_pinocchio(tmp_path, capsys, monkeypatch):
    """A 65-joint chain is refused from its XML: Pinocchio is never asked to parse it."""
    import dh2urdf.urdf_chain

    def no_pinocchio(*args: object, **kwargs: object) -> None:
        raise AssertionError("Pinocchio parsed a URDF beyond the cap")

    path = tmp_path / "cap.urdf"
    path.write_text(chain_urdf(MAX_JOINTS + 1), encoding="utf-8")
    monkeypatch.setattr(dh2urdf.urdf_chain, "build_pinocchio_model", no_pinocchio)
    for name in ("kin fk", "kin ik", "dh2urdf from-urdf"):
        code, err = run(name, path, MAX_JOINTS + 1, capsys)
        assert_one_error_line(code, err, "65 moving joints", f"at most {MAX_JOINTS}")
    monkeypatch.undo()
    path.write_text(chain_urdf(MAX_JOINTS), encoding="utf-8")
    code, err = run("kin fk", path, MAX_JOINTS, capsys)
    assert code == 0 and "error" not in err, err


def test_urdf_tip_choice_counts_the_chain_only(tmp_path, capsys):
    """A 70-joint URDF whose chain to --tip l10 has 10 joints loads; to l70 it is refused."""
    path = tmp_path / "long.urdf"
    path.write_text(chain_urdf(70), encoding="utf-8")
    assert fk.main(["--robot", str(path), "--tip", "l10", "--q", *zeros(10)]) == 0
    assert fk.main(["--robot", str(path), "--tip", "l70", "--q", *zeros(70)]) == 2
    assert_one_error_line(2, capsys.readouterr().err, "'l70' has 70 moving joints")


def test_urdf_of_5000_joints_is_one_line_not_a_crash(tmp_path):
    """5,000 joints crashed Pinocchio's parser (segfault): now one line, exit 2 (subprocess)."""
    path = tmp_path / "5000.urdf"
    path.write_text(chain_urdf(5000), encoding="utf-8")
    done = subprocess.run(
        [sys.executable, "-m", "kin", "fk", "--robot", str(path), "--q", "0"],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=ROOT,
    )
    assert_one_error_line(done.returncode, done.stderr, "5000 joints", "at most 1024")


def test_stdin_line_of_a_million_numbers_is_not_repeated(monkeypatch, capsys):
    """A stdin target of 1.5 million numbers: the error quotes its start, not 7.5 MB."""
    lines = [
        json.dumps({"target": [0.1] * 1_500_000}),
        json.dumps({"target": [0.3, 0.1, 0.4], "seed_q": "x" * 1_000_000}),
        json.dumps({"target": [0.3, 0.1, 0.4], "x" * 1_000_000: 1}),
        "[" * 100_000 + "]" * 100_000,
    ]
    monkeypatch.setattr(sys, "stdin", io.StringIO("\n".join(lines) + "\n"))
    assert ik.main(["--robot", "ur5", "--stdin"]) == 1
    answers = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [answer["line"] for answer in answers] == [1, 2, 3, 4]
    for answer in answers:
        assert len(answer["error"]) < 300, answer["error"][:400]
    assert answers[0]["error"].startswith("the target position must be 3 number(s), got [0.1,")
    assert answers[3]["error"].startswith("not JSON")


# Random malformed files (hypothesis): one line and exit 2, or exit 0 when the file happens to be
# valid; never a traceback, within a deadline per example.

#: Numbers and near-numbers a hostile file may hold.
HOSTILE_NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -1.0, 1e308, -1e308, 1e6, 1e7, 25.2, -400.0]),
    st.integers(-(10**30), 10**30),
)
#: Any value a TOML field may hold instead of the right one.
HOSTILE_VALUES = st.one_of(
    HOSTILE_NUMBERS,
    st.booleans(),
    st.text(max_size=12),
    st.just("x" * 100_000),
    st.lists(HOSTILE_NUMBERS, max_size=5),
    st.just([0.1] * 10_000),
    st.integers(1, 400).map(lambda depth: _nested(depth)),
    st.dictionaries(st.text(max_size=5), HOSTILE_NUMBERS, max_size=3),
)
#: Joint counts around the cap (0 and 65 are refused).
SIZES = st.sampled_from([0, 1, 2, 6, MAX_JOINTS, MAX_JOINTS + 1])
#: Attribute text of a URDF number.
HOSTILE_TEXT = st.one_of(
    HOSTILE_NUMBERS.map(str),
    st.sampled_from(["", "abc", "1 2", "0x10", "1e999", "-inf", "nan", "x" * 100_000]),
)


def _nested(depth: int) -> list:
    """A list nested ``depth`` deep."""
    value: list = [1.0]
    for _ in range(depth):
        value = [value]
    return value


def toml_value(value: object) -> str:
    """``value`` as TOML text (a small writer: numbers, strings, lists, inline tables)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, int | float):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(v)}" for k, v in value.items()) + "}"
    items: list[str] = []
    stack: list = [(iter(value), items)]  # iterative: lists nested hundreds deep
    while stack:
        iterator, out = stack[-1]
        item = next(iterator, StopIteration)
        if item is StopIteration:
            stack.pop()
            if stack:
                stack[-1][1].append("[" + ", ".join(out) + "]")
            continue
        if isinstance(item, list):
            stack.append((iter(item), []))
        else:
            out.append(toml_value(item))
    return "[" + ", ".join(items) + "]"


@st.composite
def hostile_tables(draw: st.DrawFn) -> tuple[str, int]:
    """TOML text of a table with hostile fields, rows or structure, and its number of rows."""
    rows = draw(SIZES)
    document: dict = {"convention": "standard", "length_unit": "m", "angle_unit": "rad"}
    row = {"type": "revolute", "a": 0.1, "alpha": 0.5, "d": 0.05, "theta": 0.0, "limits": [-3, 3]}
    joints = [dict(row, name=f"j{i}") for i in range(rows)]
    for _ in range(draw(st.integers(0, 3))):
        key = draw(
            st.sampled_from(
                [
                    *row,
                    "name",
                    "velocity",
                    "mass",
                    "direction",
                    "bogus",
                    "beta",
                    "radius",
                    "radius_a",
                    "mesh",
                    "housing",
                    "allow_contact",
                ]
            )
        )
        value = draw(HOSTILE_VALUES)
        if joints and draw(st.booleans()):
            joints[draw(st.integers(0, rows - 1))][key] = value
        elif key in ("type", "a", "alpha", "bogus") or not joints:
            document[
                draw(
                    st.sampled_from(
                        ["convention", "angle_unit", "name", "base", "x", "states", "base_mesh"]
                    )
                )
            ] = value
    lines = [f"{json.dumps(k)} = {toml_value(v)}" for k, v in document.items()]
    for joint in joints:
        lines.append("[[joints]]")
        lines += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in joint.items()]
    text = "\n".join(lines) + "\n"
    if draw(st.integers(0, 9)) == 0:
        text = text[: draw(st.integers(0, len(text)))]  # cut anywhere
    return text, rows


@st.composite
def hostile_urdfs(draw: st.DrawFn) -> tuple[str, int]:
    """URDF text with hostile joints, limits, names or structure, and its number of joints."""
    n = draw(SIZES)
    joints = []
    for i in range(1, n + 1):
        fields = {
            "type": "revolute",
            "lower": "-3",
            "upper": "3",
            "xyz": "0 0 0.1",
            "axis": "0 0 1",
            "parent": f"l{i - 1}",
            "name": f"j{i}",
        }
        joints.append(fields)
    for _ in range(draw(st.integers(0, 3))):
        if not joints:
            break
        fields = joints[draw(st.integers(0, n - 1))]
        key = draw(st.sampled_from([*fields, "drop-limit"]))
        if key == "type":
            fields[key] = draw(
                st.sampled_from(["continuous", "prismatic", "fixed", "floating", "planar", "x"])
            )
        elif key == "parent":
            fields[key] = draw(st.sampled_from(["l0", f"l{n}", "nowhere", "x" * 100_000]))
        elif key == "drop-limit":
            fields["lower"] = None
        elif key in ("xyz", "axis"):
            fields[key] = " ".join(draw(st.lists(HOSTILE_TEXT, min_size=0, max_size=4)))
        else:
            fields[key] = draw(HOSTILE_TEXT)
    parts = ['<robot name="hostile">', '<link name="l0"/>']
    for i, fields in enumerate(joints, start=1):
        limit = (
            f"<limit lower={quoteattr(fields['lower'])} upper={quoteattr(fields['upper'])} "
            'effort="1" velocity="1"/>'
            if fields["lower"] is not None
            else ""
        )
        parts.append(
            f'<link name="l{i}"/><joint name={quoteattr(fields["name"])} '
            f"type={quoteattr(fields['type'])}><parent link={quoteattr(fields['parent'])}/>"
            f'<child link="l{i}"/><origin xyz={quoteattr(fields["xyz"])}/>'
            f"<axis xyz={quoteattr(fields['axis'])}/>{limit}</joint>"
        )
    if draw(st.integers(0, 9)) == 0:
        depth = draw(st.integers(1, 100_000))
        parts.append("<gazebo>" * depth + "</gazebo>" * depth)
    text = "\n".join([*parts, "</robot>"])
    if draw(st.integers(0, 9)) == 0:
        text = text[: draw(st.integers(0, len(text)))]  # cut anywhere
    return text, n


def assert_exit_0_or_one_line(code: int, err: str, path: Path) -> None:
    """Exit 0, or exit 2 with one error line naming the file (or --q); never a traceback."""
    assert "Traceback" not in err, err[-3000:]
    assert code in (0, 2), (code, err[-3000:])
    event(f"exit {code}")
    if code == 2:
        errors = [line for line in err.splitlines() if ": error: " in line]
        assert len(errors) == 1, err[-3000:]
        assert str(path) in errors[0] or "--q needs" in errors[0], errors[0][:3000]
        assert len(errors[0]) < 2100, errors[0][:300]


HOSTILE_SETTINGS = settings(
    max_examples=200,
    deadline=timedelta(seconds=20),  # a hang fails; a loaded machine does not
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


@pytest.mark.parametrize("name", ["kin fk", "dh2urdf"])
@HOSTILE_SETTINGS
@given(case=hostile_tables())
def test_hostile_tables_give_one_line(name, case, tmp_path, capsys):
    """A table with NaN, inf, 1e308, huge strings, deep lists, 0 or 65 rows: exit 0 or 2."""
    text, rows = case
    path = Path(tempfile.mkdtemp(dir=tmp_path)) / "hostile.toml"
    path.write_text(text, encoding="utf-8")
    capsys.readouterr()
    code, err = run(name, path, rows, capsys)
    assert_exit_0_or_one_line(code, err, path)


@pytest.mark.parametrize("name", ["kin fk", "dh2urdf from-urdf"])
@HOSTILE_SETTINGS
@given(case=hostile_urdfs())
def test_hostile_urdfs_give_one_line(name, case, tmp_path, capsys):
    """A URDF with hostile limits, axes, types, links, names, nesting, 0 or 65 joints: 0 or 2."""
    text, joints = case
    path = Path(tempfile.mkdtemp(dir=tmp_path)) / "hostile.urdf"
    path.write_text(text, encoding="utf-8")
    capsys.readouterr()
    code, err = run(name, path, joints, capsys)
    assert_exit_0_or_one_line(code, err, path)


def test_bench_joint_cap_measures_below_and_refuses_above_the_cap(capsys):
    """bench_joint_cap.py: a 4-joint table and URDF solve (rows with peak MiB), 65 are refused."""
    assert load_script("bench_joint_cap").main(["--joints", "4", "65", "--timeout", "0.5"]) == 0
    rows = [line.split() for line in capsys.readouterr().out.splitlines()[2:]]
    assert [row[:2] for row in rows] == [
        ["table", "4"],
        ["URDF", "4"],
        ["table", "65"],
        ["URDF", "65"],
    ]
    assert all(float(row[2]) > 10.0 for row in rows)  # peak memory of a Python child [MiB]
    assert [row[3] == "refused:" for row in rows] == [False, False, True, True], rows
