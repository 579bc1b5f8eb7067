"""A DH table's meshes (``[[joints.mesh]]``, ``[[base_mesh]]``): the URDF carries them, kin checks
them as a hand-written URDF with the same mesh checked by Pinocchio + coal does, and bad input is
one line naming the table, the row and the key (exit 2, nothing written)."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import coal
import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import assert_one_line_error
from support.urdf_reference import erd

from dh2urdf import load_table
from dh2urdf.command import main as dh2urdf_main
from dh2urdf.exceptions import TableError
from dh2urdf.table_writer import table_text
from dh2urdf.urdf_writer import urdf_string, write_urdf
from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model

#: The maker's UR5 forearm and upper arm (example-robot-data), STL, meters.
FOREARM = erd("ur_description/meshes/ur5/collision/forearm.stl")
UPPERARM = erd("ur_description/meshes/ur5/collision/upperarm.stl")

#: Two revolute joints that meet (no segment drawn), a mesh on each moving body, in mm / deg.
TABLE = f"""
name = "meshed"
convention = "standard"
length_unit = "mm"
angle_unit = "deg"

[[joints]]
type = "revolute"
a = 0.0
alpha = 90.0
d = 0.0
theta = 0.0
limits = [-180.0, 180.0]
[[joints.mesh]]
file = "{UPPERARM}"
xyz = [0.0, 50.0, 0.0]
rpy = [0.0, -90.0, 0.0]

[[joints]]
type = "revolute"
a = 0.0
alpha = 0.0
d = 0.0
theta = 0.0
limits = [-180.0, 180.0]
[[joints.mesh]]
file = "{FOREARM}"
xyz = [100.0, 0.0, 20.0]
rpy = [10.0, 90.0, 30.0]
scale = [1.0, 1.5, 1.0]
"""

#: The same arm written by hand: DH frame 1 = Rz(q1) Rx(90 deg), frame 2 = frame 1 Rz(q2).
HAND_URDF = f"""<robot name="hand">
  <link name="base"/>
  <link name="turning"/>
  <link name="frame1">
    <collision><geometry><mesh filename="{UPPERARM}"/></geometry>
      <origin xyz="0 0.05 0" rpy="0 {-math.pi / 2!r} 0"/></collision>
  </link>
  <link name="frame2">
    <collision><geometry><mesh filename="{FOREARM}" scale="1 1.5 1"/></geometry>
      <origin xyz="0.1 0 0.02" rpy="{math.radians(10)!r} {math.pi / 2!r} {math.radians(30)!r}"/>
    </collision>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="turning"/>
    <axis xyz="0 0 1"/><limit lower="-3.2" upper="3.2" effort="1" velocity="1"/></joint>
  <joint name="twist" type="fixed"><parent link="turning"/><child link="frame1"/>
    <origin rpy="{math.pi / 2!r} 0 0"/></joint>
  <joint name="j2" type="revolute"><parent link="frame1"/><child link="frame2"/>
    <axis xyz="0 0 1"/><limit lower="-3.2" upper="3.2" effort="1" velocity="1"/></joint>
</robot>
"""

SCENE = """
[[box]]
name = "wall"
size = [0.05, 1.0, 1.0]
xyz = [0.3, 0.0, 0.0]
rpy = [0.0, 0.0, 0.4]

[[sphere]]
name = "ball"
radius = 0.08
xyz = [-0.1, 0.25, 0.2]
"""


def _hand_reference(q: np.ndarray) -> float:
    """Smallest signed distance [m] of the hand-written URDF's meshes (convex hulls) to the scene."""
    model = pin.buildModelFromXML(HAND_URDF)
    geometry = pin.buildGeomFromUrdfString(model, HAND_URDF, pin.GeometryType.COLLISION)
    data = model.createData()
    pin.forwardKinematics(model, data, q)
    pin.updateGeometryPlacements(model, data, geometry, geometry.createData())
    wall = (
        coal.Box(0.05, 1.0, 1.0),
        pin.SE3(pin.rpy.rpyToMatrix(0, 0, 0.4), np.array([0.3, 0, 0])),
    )
    ball = (coal.Sphere(0.08), pin.SE3(np.eye(3), np.array([-0.1, 0.25, 0.2])))
    best = math.inf
    for obj in geometry.geometryObjects:
        obj.geometry.buildConvexHull(True, "Qt")  # qhull: the hull itself, as kin takes a mesh
        hull = obj.geometry.convex
        placement = data.oMi[obj.parentJoint] * obj.placement
        for shape, where in (wall, ball):
            result = coal.DistanceResult()
            coal.distance(hull, placement, shape, where, coal.DistanceRequest(), result)
            best = min(best, result.min_distance)
    return best


def test_kin_checks_a_table_mesh_as_pinocchio_and_coal_check_a_hand_written_urdf(tmp_path):
    """Over 60 random q the closest distance to a wall and a ball equals the reference's to 1e-6 m
    (GJK's tolerance), and the verdicts agree; both free and colliding postures are sampled."""
    table_path = tmp_path / "meshed.toml"
    table_path.write_text(TABLE)
    scene = tmp_path / "cell.toml"
    scene.write_text(SCENE)
    checker = CollisionChecker(load_collision_model(load_robot(table_path), scene=scene))
    rng = np.random.default_rng(3)
    verdicts = set()
    for q in rng.uniform(-math.pi, math.pi, size=(60, 2)):
        expected = _hand_reference(q)
        closest = checker.distance(q)
        assert closest.b in ("wall", "ball"), closest
        if expected > 1e-4:
            assert abs(closest.distance - expected) < 1e-6, (q, closest.distance, expected)
        verdicts.add(expected < 0.0)
        assert checker.in_collision(q) == (expected < 0.0), (q, expected)
    assert verdicts == {False, True}


def test_the_urdf_carries_the_mesh_in_visual_and_collision_and_drops_the_bodys_sticks(tmp_path):
    """Row 2 (a = 400 mm) with a mesh: link2's <collision> holds the mesh, not the 1 cm stick
    along a2 (still drawn); row 1 keeps its stick; a visual-only base mesh is drawn, not checked;
    a URDF written into a folder names the mesh relative to it."""
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "forearm.stl").write_bytes(FOREARM.read_bytes())
    table_path = tmp_path / "arm.toml"
    table_path.write_text(
        TABLE.replace(f'[[joints.mesh]]\nfile = "{UPPERARM}"\n', "[row1]\n")
        .replace("[row1]\nxyz = [0.0, 50.0, 0.0]\nrpy = [0.0, -90.0, 0.0]\n", "")
        .replace(f'"{FOREARM}"', '"meshes/forearm.stl"')
        .replace("a = 0.0\nalpha = 0.0", "a = 400.0\nalpha = 0.0")
        .replace("a = 0.0\nalpha = 90.0", "a = 300.0\nalpha = 90.0")
        + '\n[[base_mesh]]\nfile = "meshes/forearm.stl"\nuse = "visual"\n'
    )
    table = load_table(table_path)
    root = ET.fromstring(urdf_string(table))
    links = {link.get("name"): link for link in root.iter("link")}

    def names(link: str, kind: str) -> list[str]:
        return [element.get("name", "") for element in links[link].findall(kind)]

    assert "a2" in names("link2", "visual") and "a2_collision" not in names("link2", "collision")
    assert names("link2", "collision") == ["mesh2_0_collision"]
    assert "a1_collision" in names("link1", "collision")
    assert "mesh0_0" in names("frame0", "visual") and not any(
        "mesh" in n for n in names("frame0", "collision")
    )
    mesh = links["link2"].find("collision/geometry/mesh")
    assert mesh is not None and mesh.get("filename") == str(tmp_path / "meshes" / "forearm.stl")
    assert mesh.get("scale") == "1.0 1.5 1.0"
    out = tmp_path / "out" / "arm.urdf"
    out.parent.mkdir()
    write_urdf(table, out)
    assert 'filename="../meshes/forearm.stl"' in out.read_text()
    # the command names them the same way (it named them by absolute paths)
    by_command = tmp_path / "out" / "by_command.urdf"
    assert dh2urdf_main([str(table_path), "-o", str(by_command)]) == 0
    assert by_command.read_text() == out.read_text()
    # the table written back names the same files and gives the same URDF
    again = tmp_path / "again.toml"
    again.write_text(table_text(table, mesh_folder=tmp_path))
    assert 'file = "meshes/forearm.stl"' in again.read_text()
    assert (
        urdf_string(load_table(again)).split("-->", 1)[1] == urdf_string(table).split("-->", 1)[1]
    )


def test_the_preview_draws_the_table_meshes(tmp_path):
    """kin preview's viewer (Pinocchio on the table's URDF, no meshcat server) draws both meshes."""
    from kin.viewer.robot_viewer import RobotViewer

    table_path = tmp_path / "meshed.toml"
    table_path.write_text(TABLE)
    viewer = RobotViewer(load_robot(table_path))
    paths = [obj.meshPath for obj in viewer.visual_model.geometryObjects]
    assert str(FOREARM) in paths and str(UPPERARM) in paths


@pytest.mark.parametrize(
    ("mesh", "field", "needle"),
    [
        ('file = "missing.stl"', "mesh[0].file", "mesh not found"),
        ('file = "notes.stl"', "mesh[0].file", "is not an STL mesh"),
        ('file = "notes.txt"', "mesh[0].file", "is not a mesh file"),
        ('file = "fake.dae"', "mesh[0].file", "is not a COLLADA mesh"),
        ('file = "forearm.stl"\nscale = nan', "mesh[0].scale", "positive finite scale"),
        ('file = "forearm.stl"\nscale = [1.0, inf, 1.0]', "mesh[0].scale", "positive finite"),
        ('file = "forearm.stl"\nscale = 0.0', "mesh[0].scale", "positive finite"),
        ('file = "forearm.stl"\nuse = "drawn"', "mesh[0].use", "both, collision, visual"),
        ('file = "forearm.stl"\nxyz = [1.0, 2.0]', "mesh[0].xyz", "expected [x, y, z]"),
        ('file = "forearm.stl"\ncolour = "red"', "mesh[0]", "expected a table of file"),
    ],
)
def test_bad_mesh_is_one_line_naming_the_table_row_and_key(mesh, field, needle, tmp_path, capsys):
    """dh2urdf and kin: exit 2, one line 'TABLE, joint row 2, field KEY: ...', nothing written."""
    (tmp_path / "notes.stl").write_text("these are not triangles\n")
    (tmp_path / "notes.txt").write_text("v 0 0 0\n")
    (tmp_path / "fake.dae").write_text("<xml/>")
    (tmp_path / "forearm.stl").write_bytes(FOREARM.read_bytes())
    table_path = tmp_path / "arm.toml"
    row2 = f'file = "{FOREARM}"\nxyz = [100.0, 0.0, 20.0]\nrpy = [10.0, 90.0, 30.0]\n'
    text = TABLE.replace(row2 + "scale = [1.0, 1.5, 1.0]\n", mesh + "\n")
    assert text != TABLE
    table_path.write_text(text)
    with pytest.raises(TableError) as caught:
        load_table(table_path)
    assert (caught.value.row, caught.value.field) == (2, field)
    out = tmp_path / "arm.urdf"
    code = dh2urdf_main([str(table_path), "-o", str(out)])
    assert_one_line_error(code, capsys.readouterr().err, f"arm.toml, joint row 2, field '{field}'")
    assert needle in str(caught.value) and not out.exists()
    from kin.commands.check import main as kin_check

    code = kin_check(["--robot", str(table_path), "--q", "0", "0"])
    assert_one_line_error(code, capsys.readouterr().err, f"joint row 2, field '{field}'")


def test_a_base_mesh_error_names_the_key_without_a_row(tmp_path):
    table_path = tmp_path / "arm.toml"
    table_path.write_text(TABLE + '\n[[base_mesh]]\nfile = "none.obj"\n')
    with pytest.raises(TableError, match=r"field 'base_mesh\[0\].file': mesh not found") as caught:
        load_table(table_path)
    assert caught.value.row is None


def test_the_urdf_text_with_meshes_equals_yourdfpys(tmp_path):
    """urdf_string of a table with meshes: the bytes yourdfpy's writer and lxml give."""
    from support.urdf_text import body, yourdfpy_text

    table_path = tmp_path / "meshed.toml"
    table_path.write_text(TABLE + f'\n[[base_mesh]]\nfile = "{FOREARM}"\nuse = "visual"\n')
    table = load_table(table_path)
    assert body(urdf_string(table)) == yourdfpy_text(table)
