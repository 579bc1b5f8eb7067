"""A DH table's own meshes (``[[joints.mesh]]``, ``[[base_mesh]]``) are drawn as its other body
pieces: see-through (alpha :data:`kin.viewer.see_through.BODY_OPACITY`), shaded, so the joint
markers and the DH triads inside them show.

Before, they were opaque, and the makers' STL files (whose facet normals are zero in
example-robot-data) were black silhouettes: the UR5 table of ``dh2urdf from-urdf`` hid its joints.
The STL normals are checked against trimesh's face normals of the same file.
"""

from __future__ import annotations

import numpy as np
import pytest
from support.preview_page import page_commands
from support.urdf_reference import ARMS, erd

from dh2urdf.command import main as dh2urdf_main
from kin import load_robot

viewer_module = pytest.importorskip("kin.viewer")
see_through = pytest.importorskip("kin.viewer.see_through")
mesh_files = pytest.importorskip("kin.viewer.mesh_files")

FOREARM_STL = erd("ur_description/meshes/ur5/collision/forearm.stl")
FOREARM_DAE = erd("ur_description/meshes/ur5/visual/forearm.dae")
BASE_STL = erd("ur_description/meshes/ur5/collision/base.stl")
#: Two joints; an STL and a COLLADA mesh on row 2, an STL base; each visual too (use "both").
TABLE = f"""
name = "meshed"
convention = "standard"
length_unit = "m"
angle_unit = "rad"

[[joints]]
type = "revolute"
a = 0.3
alpha = 0.0
d = 0.1
theta = 0.0
limits = [-3.0, 3.0]

[[joints]]
type = "revolute"
a = 0.3
alpha = 0.0
d = 0.0
theta = 0.0
limits = [-3.0, 3.0]
[[joints.mesh]]
file = "{FOREARM_STL}"
rpy = [0.0, 1.5707963267948966, 0.0]
xyz = [-0.3, 0.0, 0.0]
[[joints.mesh]]
file = "{FOREARM_DAE}"
rpy = [0.0, 1.5707963267948966, 0.0]
xyz = [-0.3, 0.0, 0.1]
use = "visual"

[[base_mesh]]
file = "{BASE_STL}"
"""
ORANGE = 0xE5_7F_19  # the DH writer's joint markers (0.9, 0.5, 0.1)


def _mesh_materials(tmp_path) -> tuple[list[tuple[str, dict]], list[dict]]:
    """The (format, material) of each mesh file the page draws, and the joint markers' materials."""
    table = tmp_path / "meshed.toml"
    table.write_text(TABLE, encoding="utf-8")
    viewer = viewer_module.RobotViewer(load_robot(table))
    meshes, joints = [], []
    for command in page_commands(viewer.static_html()):
        if command["type"] != "set_object" or "/robot/visuals/" not in command["path"]:
            continue
        drawn = command["object"]
        geometry, material = drawn["geometries"][0], drawn["materials"][0]
        if geometry["type"] == "_meshfile":
            meshes.append((geometry["format"], material))
        elif material["color"] == ORANGE:
            joints.append(material)
    return meshes, joints


def test_table_meshes_are_see_through_and_the_joints_opaque(tmp_path):
    """Every mesh of the table (two STL, one COLLADA, read from the TOML above) is drawn with
    the body's alpha, as meshcat geometry with that material; both joint markers stay opaque."""
    meshes, joints = _mesh_materials(tmp_path)
    assert sorted(kind for kind, _ in meshes) == ["dae", "stl", "stl"], meshes
    for _, material in meshes:
        assert material["transparent"] is True
        assert material["opacity"] == pytest.approx(see_through.BODY_OPACITY)
    assert len(joints) == 2 and all(m["opacity"] == 1.0 for m in joints), joints


def _stl_facets(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """Normals (N, 3) and vertices (N, 3, 3) of a binary STL, read with NumPy here."""
    count = int.from_bytes(data[80:84], "little")
    assert len(data) == 84 + 50 * count
    rows = np.frombuffer(
        data, np.dtype([("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")]), count, 84
    )
    return rows["n"].astype(float), rows["v"].astype(float)


def test_stl_normals_are_trimesh_face_normals(tmp_path):
    """The maker's forearm (zero normals in the file) and a hand-written ASCII tetrahedron: the
    same facets in the same order, each normal trimesh's face normal of that facet."""
    trimesh = pytest.importorskip("trimesh")
    stored, _ = _stl_facets(FOREARM_STL.read_bytes())
    assert not np.any(stored)  # the file's own normals are all zero
    corners = ["0 0 0", "1 0 0", "0 1 0", "0 0 1"]
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]  # counter-clockwise seen from outside
    ascii_stl = tmp_path / "tetra.stl"
    ascii_stl.write_text(
        "solid t\n"
        + "".join(
            "facet normal 0 0 0\nouter loop\n"
            + "".join(f"vertex {corners[i]}\n" for i in face)
            + "endloop\nendfacet\n"
            for face in faces
        )
        + "endsolid t\n",
        encoding="utf-8",
    )
    for path in (FOREARM_STL, ascii_stl):
        normals, vertices = _stl_facets(mesh_files.stl_with_normals(path))
        mesh = trimesh.load(str(path), process=False)
        np.testing.assert_allclose(vertices, mesh.triangles, atol=1e-6)
        expected = mesh.face_normals
        areas = mesh.area_faces > 1e-12
        np.testing.assert_allclose(normals[areas], expected[areas], atol=1e-5)
    np.testing.assert_allclose(normals[3], np.ones(3) / np.sqrt(3), atol=1e-6)  # outward


def _page(table, q, opaque: bool, monkeypatch, view=None) -> tuple[str, object]:
    """A page of ``table`` at ``q`` with every DH triad, the camera at ``view`` (or framed on the
    arm), and the view; ``opaque``: as before (the body pieces keep their alpha 1)."""
    from kin.viewer import robot_viewer

    if opaque:
        monkeypatch.setattr(robot_viewer, "see_through_body", lambda model: ())
    robot = load_robot(table)
    viewer = viewer_module.RobotViewer(robot)
    viewer.show_frames([f"frame{i}" for i in range(robot.nq + 1)], 0.06 * viewer.arm_length)
    viewer.display(q)
    if view is None:
        view = viewer.fit_camera()
    else:
        viewer.set_view(view)
    monkeypatch.undo()
    return viewer.static_html(), view


@pytest.mark.browser
def test_the_joints_show_through_the_ur5_table_meshes(tmp_path, capsys, monkeypatch):
    """UR5 read by dh2urdf from-urdf, with its meshes and without (--no-meshes), one camera: the
    orange joint markers and red x axes (red above blue by 0.25) cover most of the pixels through
    the see-through meshes that they cover with no meshes at all, and more than the opaque meshes
    left (measured 29,402 see-through, 39,693 bare, 23,043 opaque)."""
    from kin.viewer import screenshot

    if screenshot.find_chromium() is None:
        pytest.skip("no chromium on PATH (apt-get install chromium)")
    image = pytest.importorskip("matplotlib.image")
    urdf = str(erd(ARMS["ur5"][0]))
    meshed, bare = tmp_path / "ur5.toml", tmp_path / "ur5-bare.toml"
    assert dh2urdf_main(["from-urdf", urdf, "--tip", "tool0", "-o", str(meshed)]) == 0
    assert dh2urdf_main(["from-urdf", urdf, "--tip", "tool0", "--no-meshes", "-o", str(bare)]) == 0
    capsys.readouterr()
    q = [0.0, -1.5, 1.5, 0.0, 0.0, 0.0]
    view = None
    warm = {}
    for name, table, opaque in [
        ("see-through", meshed, False),
        ("opaque", meshed, True),
        ("bare", bare, False),
    ]:
        text, view = _page(table, q, opaque, monkeypatch, view)
        page = tmp_path / f"{name}.html"
        page.write_text(text, encoding="utf-8")
        png = screenshot.render(page, tmp_path / f"{name}.png", budget_ms=4000)
        rgb = image.imread(png)[30:, :, :3].astype(float)  # below the controls bar
        warm[name] = int((rgb[..., 0] - rgb[..., 2] > 0.25).sum())
    assert warm["see-through"] > 0.7 * warm["bare"], warm
    assert warm["see-through"] > 1.2 * warm["opaque"], warm
