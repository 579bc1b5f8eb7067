"""``kin preview`` draws the objects attached to links (a scene's ``[[attached]]``) riding on them.

The reference is Pinocchio's forward kinematics of the URDF the link belongs to (the maker's URDF
of Panda, the URDF a DH table writes for UR5 and planar2), run here with
``pin.forwardKinematics`` and ``pin.updateFramePlacements``: the drawn node's transform must be
``T_world_link(q) @ T_link_object`` at every configuration displayed and at every keyframe of a
``--plan`` animation. An attached object in collision at the configuration shown is red.
"""

from __future__ import annotations

import json

import numpy as np
import pinocchio as pin
import pytest
from support.preview_page import page_commands, write_page
from support.urdf_reference import erd

from kin import load_robot
from kin.collision import attached_object, load_collision_model

viewer_module = pytest.importorskip("kin.viewer")
collision_view = pytest.importorskip("kin.viewer.collision_view")

PANDA = erd("panda_description/urdf/panda.urdf")
#: A part held in UR5's tool: 0.25 m along the tool's z axis, clear of the wrist.
HELD = """
[[box]]
name = "table"
size = [1.6, 1.6, 0.05]
xyz = [0.0, 0.0, -0.045]

[[attached]]
name = "part"
shape = "box"
size = [0.05, 0.05, 0.25]
link = "tool"
xyz = [0.0, 0.0, 0.16]
"""
#: UR5 [rad]: the part held clear of everything; and a wider part into the wrist (frame5).
UR5_FREE = ["0", "-1.5", "1.5", "0", "0", "0"]
WIDE = HELD.replace("[0.05, 0.05, 0.25]", "[0.08, 0.08, 0.3]").replace("0.16]", "0.15]")


def _se3(xyz, rpy) -> np.ndarray:
    return pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.asarray(xyz, dtype=float)).homogeneous


def _link_poses(model: pin.Model, base: str, link: str, joints: dict[str, float]) -> np.ndarray:
    """``T_base_link`` (4, 4) by Pinocchio's FK of ``model`` with the named joints set."""
    data = model.createData()
    q = pin.neutral(model)
    for name, value in joints.items():
        q[model.joints[model.getJointId(name)].idx_q] = value
    pin.forwardKinematics(model, data, q)
    pin.updateFramePlacements(model, data)
    T_world_base = data.oMf[model.getFrameId(base)].homogeneous
    return np.linalg.inv(T_world_base) @ data.oMf[model.getFrameId(link)].homogeneous


def _drawn(viewer, node: str) -> tuple[dict, np.ndarray]:
    """The recorded object (unpacked) and transform (4, 4) of a meshcat node."""
    import umsgpack
    from meshcat.servers.tree import find_node

    found = find_node(viewer.viewer.window.tree, ["meshcat", *node.split("/")])
    matrix = np.array(umsgpack.unpackb(found.transform)["matrix"], dtype=float)
    return umsgpack.unpackb(found.object)["object"], matrix.reshape(4, 4).T  # column-major


@pytest.mark.parametrize(
    ("arm", "link", "xyz", "rpy"),
    [("panda", "panda_hand", (0.01, -0.02, 0.12), (0.3, -0.2, 0.9)), ("ur5", "tool", (0, 0, 0.16), (0, 0, 0))],
)  # fmt: skip
def test_the_attached_box_rides_on_its_link(arm, link, xyz, rpy):
    """At five configurations: drawn transform = FK(link) @ placement; the box's sides as given."""
    if arm == "panda":
        robot = load_robot(PANDA, None, "panda_link8")
        reference = pin.buildModelFromUrdf(str(PANDA))
        base = "panda_link0"
    else:
        robot = load_robot("ur5")
        reference = pin.buildModelFromXML(robot.urdf)
        base = "base_link"
    part = attached_object("part", link, box=(0.04, 0.06, 0.2), xyz=xyz, rpy=rpy)
    model = load_collision_model(robot, attached=[part])
    viewer = viewer_module.RobotViewer(robot)
    (node,) = collision_view.show_attached(viewer, model)
    assert node == "scene/attached/part"
    rng = np.random.default_rng(7)
    low, high = np.maximum(robot.lower, -3.0), np.minimum(robot.upper, 3.0)
    for q in rng.uniform(low, high, size=(5, robot.nq)):
        viewer.display(q)
        drawn, T = _drawn(viewer, node)
        expected = _link_poses(reference, base, link, dict(zip(robot.joint_names, q)))
        np.testing.assert_allclose(T, expected @ _se3(xyz, rpy), atol=1e-9)
    geometry = drawn["geometries"][0]
    assert geometry["type"] == "BoxGeometry"
    np.testing.assert_allclose(
        [geometry["width"], geometry["height"], geometry["depth"]], [0.04, 0.06, 0.2]
    )
    color = drawn["materials"][0]["color"]
    assert color == collision_view.hex_color(collision_view.ATTACHED_RGB), hex(color)


def test_the_attached_object_rides_along_a_plan_animation(tmp_path, capsys):
    """kin preview --plan --scene: every keyframe of the part (position and quaternion) is
    FK(tool) @ placement at that frame's joint vector (an untimed plan: one frame a sample)."""
    robot = load_robot("planar2")
    path = [[-1.5, 0.0], [-0.7, 0.6], [0.2, 1.1], [0.9, 0.4], [1.5, 0.0]]
    record = {"status": "ok", "planner": "hand", "robot": "planar2", "path": path, "q": path}
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps(record), encoding="utf-8")
    scene = tmp_path / "held.toml"
    scene.write_text(
        "[[attached]]\nname = 'stick'\nshape = 'cylinder'\nradius = 0.01\nlength = 0.2\n"
        "link = 'tool'\nxyz = [0.1, 0.0, 0.0]\nrpy = [0.0, 1.5707963267948966, 0.0]\n",
        encoding="utf-8",
    )
    commands = page_commands(
        write_page(tmp_path, capsys, ["--plan", str(plan), "--scene", str(scene)])
    )
    (animation,) = [c for c in commands if c["type"] == "set_animation"]
    tracks = {
        track["name"]: [key["value"] for key in track["keys"]]
        for item in animation["animations"]
        if item["path"] == "/meshcat/scene/attached/stick"
        for track in item["clip"]["tracks"]
    }
    assert len(tracks[".position"]) == len(tracks[".quaternion"]) == len(path)
    reference = pin.buildModelFromXML(robot.urdf)
    placement = _se3([0.1, 0.0, 0.0], [0.0, np.pi / 2, 0.0])
    for q, position, quaternion in zip(path, tracks[".position"], tracks[".quaternion"]):
        expected = _link_poses(reference, "base_link", "tool", dict(zip(robot.joint_names, q)))
        expected = expected @ placement
        np.testing.assert_allclose(position, expected[:3, 3], atol=1e-6)
        x, y, z, w = quaternion  # three.js order
        rotation = pin.Quaternion(w, x, y, z).toRotationMatrix()
        np.testing.assert_allclose(rotation, expected[:3, :3], atol=1e-6)


def _held_viewer(cell: str, q: list[str], tmp_path):
    """The recorded viewer of ``kin preview --robot ur5 --q Q --scene CELL`` and its stdout."""
    from kin.commands import preview

    viewers = []
    keep = viewer_module.RobotViewer.close

    def close(self):  # the command closes its viewer last: keep it for the test
        viewers.append(self)
        keep(self)

    scene = tmp_path / "held.toml"
    scene.write_text(cell, encoding="utf-8")
    argv = ["--robot", "ur5", "--q", *q, "--scene", str(scene), "--html", str(tmp_path / "p.html")]
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(viewer_module.RobotViewer, "close", close)
        assert preview.main(argv) == 0
    return viewers[-1]


@pytest.mark.parametrize(("cell", "hit"), [(HELD, False), (WIDE, True)])
def test_an_attached_object_in_collision_is_red(cell, hit, tmp_path, capsys):
    """The wide part runs into UR5's wrist (frame5): red, named in the verdict; the slim one is
    free and teal. The verdict is the collision checker's, computed here."""
    from kin.collision import CollisionChecker

    viewer = _held_viewer(cell, UR5_FREE, tmp_path)
    out = capsys.readouterr().out
    scene = tmp_path / "held.toml"
    model = load_collision_model(load_robot("ur5"), scene=str(scene))
    contacts = CollisionChecker(model).collisions([float(v) for v in UR5_FREE])
    assert any("part" in (c.a, c.b) for c in contacts) == hit
    assert ("part" in out.splitlines()[0]) == hit, out
    drawn, _ = _drawn(viewer, "scene/attached/part")
    red = collision_view.hex_color(collision_view.COLLISION_RGB)
    teal = collision_view.hex_color(collision_view.ATTACHED_RGB)
    assert drawn["materials"][0]["color"] == (red if hit else teal)


@pytest.mark.browser
def test_the_picture_shows_the_attached_box(tmp_path, capsys):
    """Rendered by headless Chromium with the part and with its node hidden: the pixels that
    differ are the part's, and most of them are teal (green and blue well above red)."""
    from kin.viewer import screenshot

    if screenshot.find_chromium() is None:
        pytest.skip("no chromium on PATH (apt-get install chromium)")
    image = pytest.importorskip("matplotlib.image")
    from kin.viewer.page_file import captioned, titled

    viewer = _held_viewer(HELD, UR5_FREE, tmp_path)
    title = "; ".join(capsys.readouterr().out.splitlines()[:2])  # the verdict, the closest pair
    shown = tmp_path / "p.html"
    hidden = tmp_path / "hidden.html"
    viewer.viewer["scene/attached"].set_property("visible", False)
    hidden.write_text(captioned(titled(viewer.static_html(), title), title), encoding="utf-8")
    pictures = []
    for page in (shown, hidden):
        png = screenshot.render(page, tmp_path / f"{page.stem}.png", budget_ms=4000)
        pictures.append(image.imread(png)[..., :3].astype(float))
    rgb, without = pictures
    part = np.abs(rgb - without).max(axis=2) > 0.08
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    teal = part & (g > r + 0.25) & (b > r + 0.2)
    assert part.sum() > 2000 and teal.sum() > 0.8 * part.sum(), (part.sum(), teal.sum())
