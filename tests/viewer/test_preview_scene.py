"""``kin preview``'s camera frames the arm, the maker's meshes included; the cell's overlays.

The reference is built apart from the viewer: each <visual> mesh of Panda's URDF read with coal's
own loader from the file the URDF names (ElementTree, package:// resolved by the collision
reference), placed by Pinocchio's forward kinematics of the original URDF, seen through a pinhole
camera written here. Every vertex must be in the picture and their box cover a third of it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest
from support.collision_reference import resolve_mesh
from support.urdf_reference import erd

from kin import load_robot

viewer_module = pytest.importorskip("kin.viewer")


def reference_vertices(urdf: Path, base: str, q: dict[str, float]) -> np.ndarray:
    """Every <visual> mesh's vertices (N, 3), in ``base``'s frame [m]."""
    text = urdf.read_text(encoding="utf-8")
    model = pin.buildModelFromXML(text)
    data = model.createData()
    full = pin.neutral(model)
    for name, value in q.items():
        full[model.joints[model.getJointId(name)].idx_q] = value
    pin.forwardKinematics(model, data, full)
    pin.updateFramePlacements(model, data)
    base_inv = data.oMf[model.getFrameId(base)].inverse()
    points = []
    for link in ET.fromstring(text).findall("link"):
        for visual in link.findall("visual"):
            mesh = visual.find("geometry/mesh")
            if mesh is None:
                continue
            origin = visual.find("origin")
            xyz = (
                [0.0] * 3
                if origin is None
                else [float(v) for v in origin.get("xyz", "0 0 0").split()]
            )
            rpy = (
                [0.0] * 3
                if origin is None
                else [float(v) for v in origin.get("rpy", "0 0 0").split()]
            )
            local = pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz))
            bvh = coal.MeshLoader().load(str(resolve_mesh(mesh.get("filename"), urdf)))
            vertices = np.asarray(bvh.vertices())
            T = (base_inv * data.oMf[model.getFrameId(link.get("name"))] * local).homogeneous
            points.append(vertices @ T[:3, :3].T + T[:3, 3])
    return np.vstack(points)


def pinhole_box(points: np.ndarray, target, position, zoom: float) -> tuple[float, ...]:
    """(left, right, bottom, top) of ``points`` in a look-at pinhole view, edges at -1 and 1.

    Built here, apart from the viewer: three.js's camera with z up, meshcat's 75 deg vertical
    field narrowed by ``zoom`` (tan(fov / 2) / zoom), on a 4:3 picture.
    """
    forward = np.asarray(target, dtype=float) - np.asarray(position, dtype=float)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    relative = points - position
    depth = relative @ forward
    assert np.all(depth > 0), "a point behind the camera"
    tan_half = np.tan(np.radians(37.5)) / zoom
    x = relative @ right / depth / (4 / 3 * tan_half)
    y = relative @ up / depth / tan_half
    return float(x.min()), float(x.max()), float(y.min()), float(y.max())


def test_panda_camera_frames_its_meshes_large():
    """Panda with the maker's meshes (to panda_hand): every vertex of every <visual> mesh is in
    the picture, and their projected box covers more than a third of it (it was 15 %)."""
    urdf = erd("panda_description/urdf/panda.urdf")
    robot = load_robot(urdf, None, "panda_hand")
    q = [0.3, -0.6, 0.2, -2.0, 0.1, 1.6, 0.7]
    viewer = viewer_module.RobotViewer(robot)
    assert viewer.meshes is not None
    viewer.display(q)
    view = viewer.fit_camera()
    path, base, _ = robot.urdf_source
    vertices = reference_vertices(
        Path(path), base or "panda_link0", dict(zip(robot.joint_names, q))
    )
    left, right, bottom, top = pinhole_box(vertices, view.target, view.position, view.zoom)
    assert -1 < left and right < 1 and -1 < bottom and top < 1, (left, right, bottom, top)
    assert (right - left) * (top - bottom) / 4 > 1 / 3, (left, right, bottom, top)
    assert vertices[:, 0].min() < -0.15  # the base mesh reaches 0.15 m behind the base


# --- the scene, the links in collision and the closest pair (issue 36 item 5) ---------------

CELL = Path(__file__).resolve().parents[2] / "examples" / "cell.toml"
#: UR5 [rad] (the maker's base frame: q1 = 0 reaches +x, towards the wall): the forearm (link3)
#: through the wall; and a posture away from it, free.
UR5_IN_WALL = [0.785, -0.6, 0.3, 0.0, 0.0, 0.0]
UR5_FREE = [3.1416, -1.2, 0.5, 0.0, 0.0, 0.0]


def _rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll), written out apart from the code."""
    cr, sr, cp, sp, cy, sy = (f(a) for a in (roll, pitch, yaw) for f in (np.cos, np.sin))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _shown(robot_name: str, q: list[float], *extra: str):
    """A recorded viewer of the arm at ``q`` after the command's collision step, and its title."""
    from kin.commands import preview
    from kin.commands.preview_collisions import load_model, show_collisions

    robot = load_robot(robot_name)
    viewer = viewer_module.RobotViewer(robot)
    viewer.display(q)
    args = preview.get_argument_parser().parse_args(["--robot", robot_name, *extra])
    return viewer, show_collisions(viewer, load_model(robot, args), args)


def _node(viewer, *path: str) -> tuple[dict, np.ndarray | None]:
    """The recorded object (unpacked) and transform (4, 4) of a meshcat node."""
    import umsgpack
    from meshcat.servers.tree import find_node

    node = find_node(viewer.viewer.window.tree, ["meshcat", *path])
    assert node.object is not None, path
    matrix = None
    if node.transform is not None:
        flat = umsgpack.unpackb(node.transform)["matrix"]
        matrix = np.array(flat, dtype=float).reshape(4, 4).T  # three.js: column-major
    return umsgpack.unpackb(node.object)["object"], matrix


def test_scene_objects_are_drawn_with_the_sizes_and_placements_of_the_file():
    """Every object of cell.toml (read here with tomllib) is drawn grey at its size and pose."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib

    viewer, _ = _shown("ur5", UR5_FREE, "--scene", str(CELL))
    document = tomllib.loads(CELL.read_text(encoding="utf-8"))
    count = 0
    for kind, entries in document.items():
        for entry in entries:
            drawn, T = _node(viewer, "scene", "cell", entry["name"])
            geometry = drawn["geometries"][0]
            if kind == "box":
                assert geometry["type"] == "BoxGeometry"
                size = [geometry["width"], geometry["height"], geometry["depth"]]
                np.testing.assert_allclose(size, entry["size"], atol=1e-12)
            else:
                assert kind == "sphere" and geometry["type"] == "SphereGeometry"
                assert abs(geometry["radius"] - entry["radius"]) < 1e-12
            np.testing.assert_allclose(T[:3, 3], entry["xyz"], atol=1e-12)
            rpy = entry.get("rpy", [0.0, 0.0, 0.0])
            np.testing.assert_allclose(T[:3, :3], _rpy_matrix(*rpy), atol=1e-12)
            material = drawn["materials"][0]
            red, green, blue = (
                material["color"] >> 16,
                material["color"] >> 8 & 255,
                material["color"] & 255,
            )
            assert red == green == blue, f"{entry['name']}: not grey"
            count += 1
    assert count == 3


@pytest.mark.parametrize("q", [UR5_IN_WALL, UR5_FREE])
def test_red_links_are_exactly_the_colliding_ones(q):
    """The red material is on every visual of the links collisions(q) names, and on no other."""
    from kin.collision import CollisionChecker, load_collision_model

    robot = load_robot("ur5")
    checker = CollisionChecker(load_collision_model(robot, scene=str(CELL)))
    named = {n for c in checker.collisions(q) for n in (c.a, c.b)} - {"table", "wall", "ball"}
    viewer, title = _shown("ur5", q, "--scene", str(CELL))
    model = viewer.robot.model
    red_links = set()
    for node, obj in zip(viewer.geometry_nodes, viewer.visual_model.geometryObjects):
        drawn, _ = _node(viewer, *node.split("/"))
        if drawn["materials"][0]["color"] == 0xFF0000:
            red_links.add(model.frames[obj.parentFrame].name)
    assert red_links == named, (red_links, named)
    assert (q == UR5_IN_WALL) == bool(named) == ("IN COLLISION" in title)


def test_the_closest_pair_rod_joins_the_witness_points():
    """The rod runs from distance(q)'s point_a to point_b (meshcat's cylinder lies along its y
    axis, centred), a ball sits on each point, both drawn over the arm; the title names the pair."""
    from kin.collision import CollisionChecker, load_collision_model

    robot = load_robot("ur5")
    closest = CollisionChecker(load_collision_model(robot, scene=str(CELL))).distance(UR5_FREE)
    viewer, title = _shown("ur5", UR5_FREE, "--scene", str(CELL))
    rod, T = _node(viewer, "scene", "markers", "closest", "rod")
    geometry = rod["geometries"][0]
    assert geometry["type"] == "CylinderGeometry"
    a, b = np.asarray(closest.point_a), np.asarray(closest.point_b)
    np.testing.assert_allclose(T[:3, 3], (a + b) / 2, atol=1e-6)
    np.testing.assert_allclose(abs(T[:3, 1] @ (b - a)), np.linalg.norm(b - a), atol=1e-6)
    assert abs(geometry["height"] - np.linalg.norm(b - a)) < 1e-6
    assert geometry["radiusTop"] >= 0.005 * viewer.arm_length  # thick enough to see
    assert rod["materials"][0]["depthTest"] is False
    for name, point in (("a", a), ("b", b)):
        _, T = _node(viewer, "scene", "markers", "closest", name)
        np.testing.assert_allclose(T[:3, 3], point, atol=1e-6)
    assert f"closest: {closest.a} / {closest.b} {closest.distance:.4f} m" in title


def test_colliding_scene_objects_are_red_and_the_others_grey():
    """The objects collisions(q) names (the wall) turn red; the table and the ball stay grey."""
    from kin.collision import CollisionChecker, load_collision_model

    checker = CollisionChecker(load_collision_model(load_robot("ur5"), scene=str(CELL)))
    hit = {c.b for c in checker.collisions(UR5_IN_WALL)} & {"table", "wall", "ball"}
    assert "wall" in hit
    viewer, _ = _shown("ur5", UR5_IN_WALL, "--scene", str(CELL))
    for name in ("table", "wall", "ball"):
        drawn, _ = _node(viewer, "scene", "cell", name)
        color = drawn["materials"][0]["color"]
        assert (color == 0xFF0000) == (name in hit), (name, hex(color))


def test_the_camera_frames_the_arm_not_the_whole_cell():
    """With --scene the camera frames the arm (it stands nearer than the 1.6 m table would
    need) and sees every frame origin of the arm past the wall, the ball and the table."""
    viewer, _ = _shown("ur5", UR5_FREE, "--scene", str(CELL))
    view = viewer.fit_camera()
    # the table's corners (x, y = +-0.8) would need the camera 1.2 m or more away at zoom 1
    table = np.array([[x, y, -0.02] for x in (-0.8, 0.8) for y in (-0.8, 0.8)])
    left, right, bottom, top = pinhole_box(table, view.target, view.position, view.zoom)
    assert min(left, bottom) < -1 or max(right, top) > 1, "the whole table is in the picture"
    data = viewer.robot.model.createData()
    pin.framesForwardKinematics(viewer.robot.model, data, np.asarray(UR5_FREE))
    for frame in data.oMf:  # sample each sight line; no sample inside a scene object
        line = view.position + np.linspace(0, 0.97, 400)[:, None] * (
            frame.translation - view.position
        )
        assert not np.any(_inside_cell(line)), frame.name


def _inside_cell(points: np.ndarray) -> np.ndarray:
    """Points inside one of cell.toml's objects (written out here from the file's numbers)."""
    table = np.all(np.abs(points - [0.0, 0.0, -0.045]) <= [0.8, 0.8, 0.025], axis=1)
    R = _rpy_matrix(0.0, 0.0, 0.3)
    local = (points - [0.55, 0.0, 0.6]) @ R
    wall = np.all(np.abs(local) <= [0.025, 0.8, 0.6], axis=1)
    ball = np.linalg.norm(points - [0.0, 0.45, 0.5], axis=1) <= 0.1
    return table | wall | ball


def test_preview_scene_command_writes_the_page_with_its_verdict(tmp_path, capsys):
    """kin preview --scene: exit 0, the verdict on stdout and in the page's title."""
    from kin.commands import preview

    page = tmp_path / "cell.html"
    argv = ["--robot", "ur5", "--q", *map(str, UR5_IN_WALL), "--scene", str(CELL)]
    assert preview.main([*argv, "--html", str(page)]) == 0
    out = capsys.readouterr().out
    assert "ur5: IN COLLISION (" in out and "link3 / wall" in out, out
    text = page.read_text()
    assert "<title>ur5: IN COLLISION (" in text and "link3 / wall" in text.split("</title>")[0]
    assert 'id="kin-caption"' in text and "; closest: " in text.split('id="kin-caption"')[1]


def test_preview_bad_scene_is_one_line_exit_2(tmp_path, capsys):
    """A scene with a negative size: exit 2, one line naming the file and field, no page."""
    scene = tmp_path / "bad.toml"
    scene.write_text("[[box]]\nsize = [1.0, -1.0, 1.0]\n")
    page = tmp_path / "bad.html"
    from kin.commands import preview

    assert preview.main(["--robot", "ur5", "--scene", str(scene), "--html", str(page)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.toml" in err[0] and "box[0].size[1]" in err[0], err
    assert not page.exists()
