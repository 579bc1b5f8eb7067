"""No command writes over one of its inputs: an output that is an input file (its path, a
symbolic link to it, a hard link to it) is one line and exit 2 before any work, the input
untouched (issue 42: `kin collisions --robot arm.urdf --write-srdf arm.urdf` replaced the URDF
by its SRDF; `dh2urdf cobra.toml -o cobra.toml` overwrote the only table with XML)."""

from __future__ import annotations

import argparse
import os
import shutil
from pathlib import Path

import pytest
from support.cli_helper import assert_one_line_error

import dh2urdf
import dh2urdf.command
import dh2urdf.from_urdf_command
from dh2urdf.output_file import output_problem, same_file_problem
from kin.commands import collisions, path, preview, reach, workspace

ROOT = Path(__file__).resolve().parents[2]
#: The shipped UR5 table, where the package is installed (a wheel's tests run from a tree
#: without the package sources).
SHIPPED_UR5 = Path(dh2urdf.__file__).resolve().parent / "tables" / "ur5.toml"
PATH_POINTS = ["--from", "0.4", "0", "0.3", "--to", "0.4", "0.2", "0.3", "--steps", "10"]

#: What each input file holds: a real file of its kind (the command would read it).
CONTENTS = {
    "table.toml": (SHIPPED_UR5).read_bytes(),
    "arm.urdf": (ROOT / "urdf" / "ur5.urdf").read_bytes(),
    "cell.toml": (ROOT / "tests" / "data" / "collision" / "cell.toml").read_bytes(),
    "arm.srdf": b'<?xml version="1.0"?>\n<robot name="ur5"/>\n',
    "motion.json": b'{"robot": "ur5", "q": [[0, 0, 0, 0, 0, 0]]}\n',
    "map.npz": b"PK\x03\x04 a reach map\n",
}

#: (command's main, its argv with {input} and {output}, the input's option, the input file,
#: the output's option). Every command with an output file, against every file it reads.
CASES = [
    (dh2urdf.command.main, ["{input}", "-o", "{output}"], "the table", "table.toml", "-o"),
    (
        dh2urdf.from_urdf_command.main,
        ["{input}", "-o", "{output}"],
        "the URDF",
        "arm.urdf",
        "-o",
    ),
    *[
        (
            collisions.main,
            ["--robot", "{input}", "--write-srdf", "{output}"],
            "--robot",
            name,
            "--write-srdf",
        )
        for name in ("arm.urdf", "table.toml")
    ],
    *[
        (
            workspace.main,
            ["--robot", "{input}", "--n", "1000", "-o", "{output}"],
            "--robot",
            name,
            "-o",
        )
        for name in ("arm.urdf", "table.toml")
    ],
    *[
        (reach.main, ["--robot", "ur5", *given, "-o", "{output}"], option, name, "-o")
        for option, name, given in (
            ("--scene", "cell.toml", ["--scene", "{input}"]),
            ("--srdf", "arm.srdf", ["--srdf", "{input}"]),
        )
    ],
    (reach.main, ["--robot", "{input}", "-o", "{output}"], "--robot", "arm.urdf", "-o"),
    (
        reach.main,
        ["--robot", "ur5", "--scene", "{input}", "-o", "{tmp}/m.npz", "--png", "{output}"],
        "--scene",
        "cell.toml",
        "--png",
    ),
    *[
        (path.main, [*robot, *PATH_POINTS, *given, "--csv", "{output}"], option, name, "--csv")
        for option, name, robot, given in (
            ("--robot", "table.toml", ["--robot", "{input}"], []),
            ("--scene", "cell.toml", ["--robot", "ur5"], ["--scene", "{input}"]),
            ("--srdf", "arm.srdf", ["--robot", "ur5"], ["--srdf", "{input}"]),
        )
    ],
    *[
        (preview.main, [*robot, *given, "--html", "{output}"], option, name, "--html")
        for option, name, robot, given in (
            ("--robot", "arm.urdf", ["--robot", "{input}"], []),
            ("--scene", "cell.toml", ["--robot", "ur5"], ["--scene", "{input}"]),
            ("--srdf", "arm.srdf", ["--robot", "ur5"], ["--srdf", "{input}"]),
            ("--path", "motion.json", ["--robot", "ur5"], ["--path", "{input}"]),
            ("--reach", "map.npz", ["--robot", "ur5"], ["--reach", "{input}"]),
        )
    ],
]


def _output_of(kind: str, source: Path) -> Path:
    """The output path of a case: the input itself, a symbolic link to it, or a hard link."""
    if kind == "same path":
        return source
    other = source.with_name(f"{kind.replace(' ', '_')}_{source.name}")
    if kind == "symbolic link":
        other.symlink_to(source.name)
    else:
        os.link(source, other)
    return other


@pytest.mark.parametrize("kind", ["same path", "symbolic link", "hard link"])
@pytest.mark.parametrize(
    ("main", "argv", "option", "name", "output_option"),
    CASES,
    ids=[f"{case[0].__module__}:{case[4]}-over-{case[2]}" for case in CASES],
)
def test_an_output_over_an_input_is_refused(
    main, argv, option, name, output_option, kind, tmp_path, capsys, monkeypatch
):
    """Exit 2, one line naming the output's option and the input's, the input's bytes unchanged."""
    monkeypatch.chdir(tmp_path)
    source = tmp_path / name
    source.write_bytes(CONTENTS[name])
    output = _output_of(kind, source)
    given = {"input": str(source), "output": str(output), "tmp": str(tmp_path)}
    code = main([word.format(**given) for word in argv])
    err = capsys.readouterr().err
    assert_one_line_error(code, err, f"{output_option} {output}: is the same file as {option}")
    assert source.read_bytes() == CONTENTS[name], f"{kind=}: the input was written"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted({name, output.name}), (
        "a file was left behind"
    )


def test_the_issue_reproducers_keep_their_input(tmp_path, capsys):
    """`kin collisions --robot arm.urdf --write-srdf arm.urdf` and `dh2urdf cobra.toml -o
    link-to-cobra.toml`: refused, the URDF and the table as they were."""
    urdf = tmp_path / "arm.urdf"
    shutil.copy(ROOT / "urdf" / "ur5.urdf", urdf)
    before = urdf.read_bytes()
    assert collisions.main(["--robot", str(urdf), "--write-srdf", str(urdf)]) == 2
    assert urdf.read_bytes() == before
    table = tmp_path / "cobra.toml"
    shutil.copy(SHIPPED_UR5, table)
    (tmp_path / "link.toml").symlink_to(table)
    assert dh2urdf.command.main([str(table), "-o", str(tmp_path / "link.toml")]) == 2
    assert table.read_bytes() == (SHIPPED_UR5).read_bytes()
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and "same file as --robot" in err[0] and "the table" in err[1], err


def test_a_shipped_robot_name_stands_for_its_table_file():
    """`--robot ur5`: the output may not be the shipped table that the name reads."""
    from kin.commands.output_file import input_files

    args = argparse.Namespace(robot="ur5", scene=None, srdf="cell.srdf")
    found = input_files(args, "--robot", "--scene", "--srdf")
    table = str(SHIPPED_UR5)
    assert [option for option, _ in found] == ["--robot", "--robot", "--srdf"]
    assert os.path.samefile(found[1][1], table)
    assert "same file as --robot" in (output_problem(table, None, found) or "")


def test_a_new_path_or_another_file_is_no_input(tmp_path):
    """Other files, a new path, standard input ('-') and options not given are not inputs."""
    first, second = tmp_path / "a.toml", tmp_path / "b.toml"
    first.write_text("x")
    second.write_text("x")  # the same bytes, another file
    inputs = [("--robot", str(first)), ("--scene", None), ("--srdf", "-")]
    assert same_file_problem(second, inputs) is None
    assert same_file_problem(tmp_path / "new.toml", inputs) is None
    assert output_problem(second, None, inputs) is None
    assert "same file as --robot" in (same_file_problem(tmp_path / "." / "a.toml", inputs) or "")
