"""URDFs other readers read, we read: undeclared prefixes in extension blocks, a URDF known by its
content whatever its suffix, and the parser's own stderr lines folded into the one error line."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import assert_one_line_error, call, kin_command

from dh2urdf.command import main as dh2urdf_main
from dh2urdf.exceptions import UrdfChainError
from dh2urdf.urdf_parse import declare_prefixes, is_urdf_file
from kin import Configuration, load_robot

#: A 3R arm with what Gazebo files carry: a <gazebo> block and a <transmission> using prefixes
#: never declared (urdfdom ignores them; xml.etree calls them "unbound").
GAZEBO_ARM = """<?xml version="1.0"?>
<!-- a comment <before> the root -->
<robot name="gazebo_arm">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="tip"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/><origin xyz="0 0 0.3" rpy="0 0 0.2"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="10" velocity="2"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/><origin xyz="0.05 0.02 0.1" rpy="0.3 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <joint name="j3" type="revolute">
    <parent link="l2"/><child link="tip"/><origin xyz="0.4 0 0.01" rpy="0 0.1 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="2"/>
  </joint>
  <gazebo reference="tip">
    <sensor:camera name="c"><sensor:image format="R8G8B8"/></sensor:camera>
    <controller:plugin controller:name="p"/>
  </gazebo>
  <transmission name="t1"><hardwareInterface:effort/></transmission>
</robot>
"""

MJCF = '<mujoco model="arm"><worldbody><body name="b"/></worldbody></mujoco>\n'


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_undeclared_prefixes_are_declared_on_the_root():
    """Every prefix used but not declared gets a declaration on <robot>; none other does."""
    mended = declare_prefixes(GAZEBO_ARM)
    assert '<robot xmlns:controller="urn:undeclared:controller"' in mended
    for prefix in ("sensor", "hardwareInterface"):
        assert f'xmlns:{prefix}="urn:undeclared:{prefix}"' in mended
    assert mended.count("xmlns:") == 3
    assert declare_prefixes(mended) == mended
    assert declare_prefixes("<robot name='r'/>") == "<robot name='r'/>"


@pytest.mark.parametrize("name", ["arm.urdf", "arm.xml", "arm.URDF", "arm"])
def test_fk_of_a_gazebo_urdf_equals_pinocchio_on_the_same_file(name, tmp_path):
    """Unbound prefixes in <gazebo> and <transmission> are ignored, whatever the file's suffix:
    the tool pose equals Pinocchio's FK of the file itself over 50 random q, to 1e-12."""
    path = _write(tmp_path, name, GAZEBO_ARM)
    robot = load_robot(path)
    assert robot.nq == 3
    reference = pin.buildModelFromUrdf(str(path))
    data = reference.createData()
    tip = reference.getFrameId("tip")
    configuration = Configuration(robot)
    rng = np.random.default_rng(11)
    for q in rng.uniform(-1.5, 1.5, size=(50, 3)):
        pin.framesForwardKinematics(reference, data, q)
        error = np.abs(configuration.fk(q).homogeneous - data.oMf[tip].homogeneous).max()
        assert error < 1e-12, f"{name=} {q=} {error=}"


def test_kin_fk_reads_a_urdf_saved_as_xml(tmp_path, capsys):
    """`kin fk --robot FILE.xml` prints the pose Pinocchio gives on that file."""
    from kin.commands import main

    path = _write(tmp_path, "arm.xml", GAZEBO_ARM)
    q = [0.3, -0.4, 0.5]
    assert call(main, ["fk", "--robot", str(path), "--q", *map(str, q), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    reference = pin.buildModelFromUrdf(str(path))
    data = reference.createData()
    pin.framesForwardKinematics(reference, data, np.array(q))
    expected = data.oMf[reference.getFrameId("tip")].translation
    assert np.allclose(printed["position_m"], expected, atol=1e-9, rtol=0), printed


def test_from_urdf_reads_a_urdf_saved_as_xml(tmp_path, capsys):
    """`dh2urdf from-urdf FILE.xml` writes the table (3 revolute joints)."""
    path = _write(tmp_path, "arm.xml", GAZEBO_ARM)
    out = tmp_path / "arm.toml"
    assert dh2urdf_main(["from-urdf", str(path), "-o", str(out)]) == 0
    assert "3 joints RRR" in capsys.readouterr().out
    assert out.is_file()


@pytest.mark.parametrize("name", ["model.xml", "model.urdf", "model"])
def test_an_mjcf_file_is_one_clear_line(name, tmp_path, capsys):
    """An MJCF file (<mujoco>), whatever its name, is refused in one line that says what it is,
    by `kin fk` and by `dh2urdf from-urdf` (which writes nothing)."""
    from kin.commands import main

    path = _write(tmp_path, name, MJCF)
    code = call(main, ["fk", "--robot", str(path), "--q", "0"])
    assert_one_line_error(code, capsys.readouterr().err, "an MJCF (MuJoCo) model")
    out = tmp_path / "t.toml"
    code = call(dh2urdf_main, ["from-urdf", str(path), "-o", str(out)])
    assert_one_line_error(code, capsys.readouterr().err, "not a URDF: an MJCF (MuJoCo) model")
    assert not out.exists()


def test_the_kind_of_a_file_comes_from_its_content(tmp_path):
    """.xml/.URDF/no suffix with <robot> are URDFs; a table is not; other XML raises."""
    assert is_urdf_file(_write(tmp_path, "a.xml", GAZEBO_ARM))
    assert is_urdf_file(_write(tmp_path, "b", "\ufeff  " + GAZEBO_ARM))
    assert not is_urdf_file(_write(tmp_path, "c.toml", "<robot/>"))
    assert not is_urdf_file(_write(tmp_path, "d", 'name = "x"\n'))
    assert not is_urdf_file(tmp_path / "missing")
    with pytest.raises(UrdfChainError, match="root element <sdf>"):
        is_urdf_file(_write(tmp_path, "e.xml", "<sdf version='1.6'/>"))


def test_a_missing_xml_file_says_it_cannot_be_read(tmp_path, capsys):
    """A .xml path that does not exist is not an "unknown robot": the file cannot be read."""
    from kin.commands import main

    code = call(main, ["fk", "--robot", str(tmp_path / "arm.xml"), "--q", "0"])
    assert_one_line_error(code, capsys.readouterr().err, "cannot read the file")


def test_the_parsers_own_lines_go_into_the_one_error_line(tmp_path):
    """A joint whose child link is missing: urdfdom's multi-line complaint on the C stderr is
    folded into the error line; the process writes exactly one line (subprocess, fd 2)."""
    broken = GAZEBO_ARM.replace('<link name="tip"/>', "")
    path = _write(tmp_path, "broken.urdf", broken)
    argv = [*kin_command(), "fk", "--robot", str(path), "--q", "0", "0", "0"]
    done = subprocess.run(argv, capture_output=True, text=True, timeout=120)
    assert_one_line_error(done.returncode, done.stderr, "child link [tip] of joint [j3] not found")
    assert "model.cpp" not in done.stderr


def test_a_parse_error_from_the_library_names_the_parser_text(tmp_path):
    """The library's exception carries urdfdom's words, and fd 2 is restored afterwards."""
    from dh2urdf.urdf_parse import build_pinocchio_model

    broken = GAZEBO_ARM.replace('<link name="tip"/>', "")
    before = os.fstat(2)
    with pytest.raises(UrdfChainError, match=r"broken.urdf: Pinocchio cannot load .*\[tip\]"):
        build_pinocchio_model(broken, "broken.urdf")
    after = os.fstat(2)
    assert (after.st_dev, after.st_ino) == (before.st_dev, before.st_ino)
