"""Text output is one line per record whatever the names read from files; --json is strict JSON.

A scene object (or a link, a joint) named ``"a\\nkin check: ..."`` forged an output line; a box at
1e308 m put ``NaN`` in ``kin check --json``; an SRDF of another robot gave two stderr lines.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from dh2urdf.output_text import counted, shown_name
from kin.commands import check, collisions, fk, ik, path, preview

ZEROS = ["0", "0", "0", "0", "0", "0"]
#: A box on ur5's link3 at zero joint values (the arm lies along -x at 0.09 m height).
ON_LINK3 = "size = [0.1, 0.1, 0.1]\nxyz = [0.6, 0.0, 0.09]\n"

#: Characters that end, hide or reorder a terminal line, and ordinary ones.
HOSTILE = st.sampled_from(list("\n\r\t\x00\x1b\x7f\x85\u2028\u2029\u202e\u200b\ufeff"))
ORDINARY = st.characters(blacklist_categories=("Cs",), blacklist_characters="\"\\'")
NAMES = st.lists(st.one_of(HOSTILE, ORDINARY), min_size=1, max_size=12).map("".join)


def _toml_string(text: str) -> str:
    """``text`` as a TOML basic string: every control character escaped."""
    body = "".join(
        f"\\u{ord(c):04x}" if ord(c) < 0x20 or ord(c) == 0x7F or c in '"\\' else c for c in text
    )
    return f'"{body}"'


def _run(main, argv: list[str]) -> tuple[int, str, str]:  # noqa: ANN001
    """``main(argv)``: exit code, stdout and stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = int(exc.code)
    return code, out.getvalue(), err.getvalue()


def _printable_lines(text: str) -> list[str]:
    """The lines of ``text`` (newline only), each asserted printable."""
    lines = text.split("\n")
    assert lines[-1] == "", text
    for line in lines[:-1]:
        assert line.isprintable(), repr(line)
    return lines[:-1]


def test_shown_name_escapes_what_would_forge_or_hide_a_line():
    """Printable names stay; a newline, an escape, a bidi override or a leading quote: repr."""
    assert shown_name("link3") == "link3" and shown_name("ščéna ü") == "ščéna ü"
    assert shown_name("a\nkin check: free") == "'a\\nkin check: free'"
    assert shown_name("\x1b[2K") == "'\\x1b[2K'" and shown_name("a\u202eb") == "'a\\u202eb'"
    assert shown_name("'x'") == "\"'x'\""
    assert counted(1, "scene object") == "1 scene object" and counted(0, "pair") == "0 pairs"
    assert counted(2, "entry", "entries") == "2 entries"


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(name=NAMES)
def test_kin_check_prints_one_line_per_record_whatever_the_object_name(name, tmp_path):
    """A box named anything, touching link3: five lines (verdict, pairs, shapes, contact,
    closest), each printable, the contact and closest lines naming it as shown_name does."""
    scene = tmp_path / "cell.toml"
    scene.write_text(f"[[box]]\nname = {_toml_string(name)}\n{ON_LINK3}", encoding="utf-8")
    code, out, err = _run(check.main, ["--robot", "ur5", "--q", *ZEROS, "--scene", str(scene)])
    assert code == 1, err
    lines = _printable_lines(out)
    prefixes = [
        "ur5: IN COLLISION",
        "pairs checked: ",
        "shapes: ",
        "contact (scene): ",
        "closest: ",
    ]
    assert [p for line, p in zip(lines, prefixes) if line.startswith(p)] == prefixes, out
    assert len(lines) == 5, out
    assert f"link3 / {shown_name(name)}  " in lines[3] and f" / {shown_name(name)}  " in lines[4]
    assert "1 scene object;" in lines[1]


def _hostile_urdf(folder: Path) -> Path:
    """A 2R arm whose first link and first joint have a newline and a forged line in their name."""
    link, joint = "l1&#10;closest: forged", "j1&#10;position [m]: 9 9 9"
    box = '<collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.05 0.05"/></geometry></collision>'  # noqa: E501
    limit = '<limit lower="-3" upper="3" effort="1" velocity="1"/>'
    text = f"""<robot name="two">
  <link name="base_link"/><link name="{link}">{box}</link><link name="l2">{box}</link>
  <link name="tool"/>
  <joint name="{joint}" type="revolute"><parent link="base_link"/><child link="{link}"/>
    <axis xyz="0 0 1"/>{limit}</joint>
  <joint name="j2" type="revolute"><parent link="{link}"/><child link="l2"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 0 1"/>{limit}</joint>
  <joint name="jt" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.5 0 0"/></joint>
</robot>"""
    path = folder / "two.urdf"
    path.write_text(text, encoding="utf-8")
    return path


def test_link_and_joint_names_of_a_urdf_are_escaped_in_every_command(tmp_path):
    """A URDF's link 'l1\\nclosest: forged' and joint 'j1\\nposition [m]: 9 9 9': kin check,
    fk, ik, path and collisions print printable lines only, the names escaped."""
    urdf = str(_hostile_urdf(tmp_path))
    scene = tmp_path / "cell.toml"
    scene.write_text('[[sphere]]\nname = "ball"\nradius = 0.1\nxyz = [0.25, 0.0, 0.0]\n')
    line = ["--from", "0.5", "0.5", "0", "--to", "0.6", "0.5", "0", "--steps", "2"]
    runs = [
        (check, ["--robot", urdf, "--q", "0", "0", "--scene", str(scene)]),
        (fk, ["--robot", urdf, "--q", "9", "0"]),
        (ik, ["--robot", urdf, "--target", "0.5", "0.5", "0"]),
        (ik, ["--robot", urdf, "--target", "0.5", "0.5", "0", "--scene", str(scene), "--all"]),
        (path, ["--robot", urdf, *line]),
        (collisions, ["--robot", urdf, "--samples", "10", "--write-srdf", str(tmp_path / "a.srdf")]),
    ]  # fmt: skip
    escaped = {shown_name("l1\nclosest: forged"), shown_name("j1\nposition [m]: 9 9 9")}
    for command, argv in runs:
        code, out, err = _run(command.main, argv)
        assert code in (0, 1), (argv, err)
        lines = _printable_lines(out) + _printable_lines(err)
        assert not any(line.startswith(("closest: forged", "position [m]: 9")) for line in lines)
        if command is not collisions:  # its summary names no link
            assert any(name in out + err for name in escaped), (argv, out, err)


@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # pyzmq's, shown under pytest only
def test_preview_names_the_pair_escaped(tmp_path):
    """kin preview --scene: the verdict and closest lines name the object escaped."""
    scene = tmp_path / "cell.toml"
    scene.write_text(f'[[box]]\nname = "a\\nur5: collision-free"\n{ON_LINK3}', encoding="utf-8")
    argv = ["--robot", "ur5", "--scene", str(scene), "--html", str(tmp_path / "p.html")]
    code, out, err = _run(preview.main, argv)
    assert code == 0, err
    lines = _printable_lines(out)
    assert lines[0] == "ur5: IN COLLISION (link3 / 'a\\nur5: collision-free')", out
    assert len(lines) == 3 and lines[1].startswith("closest: link3 / 'a\\nur5"), out


def _strict(text: str) -> object:
    """``text`` parsed as strict JSON: NaN and Infinity refused."""

    def refuse(constant: str) -> float:
        raise AssertionError(f"not JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def _far_scene(folder: Path) -> Path:
    """A box 1e308 m out: coal's witness points overflow to NaN."""
    scene = folder / "far.toml"
    scene.write_text('[[box]]\nname = "far"\nsize = [0.1, 0.1, 0.1]\nxyz = [1e308, 0, 0]\n')
    return scene


def test_check_json_writes_null_for_a_non_finite_number_and_says_so(tmp_path):
    """kin check --json with a box at 1e308 m printed NaN: now strict JSON, each non-finite
    number null, and one warning line naming the fields. (If the box is refused as bad input,
    that is one line and exit 2, and nothing is printed: strict too.)"""
    argv = ["--robot", "ur5", "--q", *ZEROS, "--scene", str(_far_scene(tmp_path)), "--json"]
    code, out, err = _run(check.main, argv)
    if code == 2:  # refused as bad input
        assert out == "" and len(err.splitlines()) == 1
        return
    record = _strict(out)
    assert "NaN" not in out and "Infinity" not in out
    numbers = [record["closest"]["distance_m"]] if record["closest"] else []
    for contact in record["contacts"]:
        numbers += [contact["depth_m"], *contact["point_a_m"], *contact["point_b_m"]]
    assert all(v is None or math.isfinite(v) for v in numbers)
    if None in numbers:
        lines = err.splitlines()
        assert len(lines) == 1 and "non-finite number" in lines[0] and "written as null" in lines[0]


@settings(max_examples=60, deadline=None)
@given(
    st.recursive(
        st.one_of(st.floats(), st.integers(), st.text(max_size=3), st.none(), st.booleans()),
        lambda inner: st.one_of(
            st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=3), inner, max_size=4)
        ),
        max_leaves=20,
    )
)
@example({"NaN": None, "Infinity": ["NaN", "-Infinity", 1.5]})  # text named like the constants
@example({"NaN": float("nan"), "x": [float("-inf"), "NaN"]})
def test_json_output_is_strict_for_any_record(record):
    """dumps: any tree of numbers is strict JSON; finite numbers kept, the others null.

    The expected record is Python's own lenient JSON of ``record`` read back with each bare
    ``NaN``/``Infinity`` token as null (``parse_constant``): a key or a string ``"NaN"`` is text,
    which strict JSON holds as it is (replacing the word in the text changed such keys too).
    """
    import warnings

    from kin.commands.json_output import NonFiniteWarning, dumps

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        text = dumps(record)
    back = _strict(text)
    expected = json.loads(json.dumps(record, allow_nan=True), parse_constant=lambda _: None)
    assert back == expected
    assert bool(caught) == (text != json.dumps(record, allow_nan=True)), caught
    assert all(issubclass(w.category, NonFiniteWarning) for w in caught)


def test_an_srdf_of_another_robot_is_one_error_line(tmp_path):
    """An SRDF written for 'other' naming links ur5 lacks: one line (the error, naming the SRDF's
    robot), not a warning line and an error line."""
    srdf = tmp_path / "other.srdf"
    srdf.write_text(
        '<robot name="other"><disable_collisions link1="foo" link2="bar" reason="Never"/></robot>'
    )  # noqa: E501
    done = _subprocess(["check", "--robot", "ur5", "--q", *ZEROS, "--srdf", str(srdf)])
    assert done.returncode == 2 and len(done.stderr.splitlines()) == 1, done.stderr
    assert "no link 'foo'" in done.stderr and "written for the robot 'other'" in done.stderr


def test_an_srdf_of_another_name_with_known_links_warns_once(tmp_path):
    """An SRDF named for 'scorbot' whose links ur5's DH model has too: used, one warning line."""
    srdf = tmp_path / "s.srdf"
    srdf.write_text(
        '<robot name="scorbot"><disable_collisions link1="frame1" link2="frame3" reason="Never"/></robot>'
    )  # noqa: E501
    done = _subprocess(["check", "--robot", "ur5", "--q", *ZEROS, "--srdf", str(srdf)])
    assert done.returncode == 0, done.stderr
    assert len(done.stderr.splitlines()) == 1 and "written for the robot 'scorbot'" in done.stderr


def _subprocess(argv: list[str]):  # noqa: ANN202
    from support.cli_helper import run

    return run(argv)


def test_counts_of_one_are_singular(tmp_path, capsys):
    """'1 scene objects', '1 samples', '1 joints' were printed: the singular now."""
    from dh2urdf import command as dh2urdf_command

    argv = ["--robot", "planar2", "--samples", "1", "--write-srdf", str(tmp_path / "p.srdf")]
    assert collisions.main(argv) == 0
    assert "of 1 link pair disabled (1 Adjacent); 1 sample, seed 0" in capsys.readouterr().err
    table = tmp_path / "one.toml"
    table.write_text(
        'name = "one"\nconvention = "standard"\nlength_unit = "m"\nangle_unit = "deg"\n'
        '[[joints]]\ntype = "revolute"\na = 0.3\nalpha = 0.0\nd = 0.1\ntheta = 0.0\n'
        "limits = [-90.0, 90.0]\n"
    )
    assert dh2urdf_command.main([str(table), "-o", str(tmp_path / "one.urdf")]) == 0
    assert "(URDF, one, 1 joint, meters/radians)" in capsys.readouterr().out
