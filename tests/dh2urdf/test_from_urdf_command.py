"""`dh2urdf from-urdf`: a table file whose FK is the URDF's; the URDF written back from it is
kinematically the input; bad input is one line, exit 2, nothing written."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import assert_one_line_error
from support.urdf_reference import ARMS, UrdfReference, erd

from dh2urdf import load_table
from dh2urdf.command import main
from dh2urdf.urdf_chain import read_chain


@pytest.mark.parametrize("arm", ["ur5", "panda", "kinova", "tiago", "double_pendulum"])
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_table_file_and_the_urdf_written_back_match_the_input(arm, convention, tmp_path, capsys):
    """The written table (read back by load_table) and the URDF dh2urdf writes from it give the
    original URDF's FK over 300 random q (judged by Pinocchio on each file): to 1e-11, since a
    URDF writes rotations as roll-pitch-yaw, which loses digits near pitch +-90 deg (TIAGo's
    tool: 4.5e-12); the table itself is exact to 1e-12 (test_urdf_to_dh.py)."""
    relative, base, tip = ARMS[arm]
    urdf = erd(relative)
    table_path = tmp_path / f"{arm}.toml"
    argv = ["from-urdf", str(urdf), "-o", str(table_path), "--convention", convention]
    argv += [] if base is None else ["--base", base]
    argv += [] if tip is None else ["--tip", tip]
    assert main(argv) == 0
    assert capsys.readouterr().out.startswith(f"wrote {table_path}")
    table = load_table(table_path)
    chain = read_chain(urdf, base, tip)
    original = UrdfReference(urdf, chain.base, chain.tip, table.joint_names)
    back = tmp_path / f"{arm}.urdf"
    assert main([str(table_path), "-o", str(back)]) == 0
    written = pin.buildModelFromUrdf(str(back))
    data = written.createData()
    tool = written.getFrameId("tool")
    rng = np.random.default_rng(4)
    lower, upper = np.maximum(table.lower, -math.pi), np.minimum(table.upper, math.pi)
    for q in rng.uniform(lower, upper, size=(300, table.dof)):
        pin.framesForwardKinematics(written, data, q)
        error = np.abs(data.oMf[tool].homogeneous - original.pose(q)).max()
        assert error < 1e-11, f"{arm=} {convention=} {error=}"


@pytest.mark.parametrize(
    ("content", "extra", "needle"),
    [
        ("not xml", [], "not XML"),
        ("<robot name='x'><link name='a'/></robot>", [], "could be the tip; give --tip LINK"),
        (None, ["--tip", "nope"], "no link 'nope' for the tip; links:"),
        (None, [], "several links could be the tip: ee_link, tool0"),
    ],
)
def test_bad_input_is_one_line_and_writes_nothing(content, extra, needle, tmp_path, capsys):
    """Not XML, no joint, an unknown tip, an ambiguous tip: exit 2, one line, no file."""
    if content is None:
        urdf = erd(ARMS["ur5"][0])
    else:
        urdf = tmp_path / "bad.urdf"
        urdf.write_text(content)
    out = tmp_path / "out.toml"
    code = main(["from-urdf", str(urdf), "-o", str(out), *extra])
    assert_one_line_error(code, capsys.readouterr().err, needle)
    assert not out.exists()


def test_table_to_stdout(capsys):
    """-o - prints the table (TOML) and nothing else."""
    assert main(["from-urdf", str(erd(ARMS["ur5"][0])), "--tip", "tool0", "-o", "-"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("# Read from ur5_robot.urdf") and 'name = "shoulder_pan_joint"' in out
