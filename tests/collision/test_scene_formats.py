"""Scenes as users write them: units in a scene TOML, their slips, and MoveIt PlanningScenes.

A PlanningScene (JSON, YAML) is checked against a TOML scene written by hand for the same cell
(poses composed by hand, quaternions of simple rotations written out): the same verdicts and
distances at random ur5 configurations. Degrees and radians, millimetres and meters give the
same placements; each slip is one warning line naming the file and the field; each malformed
PlanningScene one error line naming the field; random PlanningScene-like documents raise
nothing but CollisionModelError.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dh2urdf.exceptions import UnitWarning
from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.planning_scene import read_planning_scene
from kin.collision.scene import load_scene, read_scene
from kin.exceptions import CollisionModelError

S = math.sqrt(0.5)  # cos 45 deg = sin 45 deg: the quaternion of a quarter turn
#: A wedge (its hull): vertices [m], and its triangles.
WEDGE = [(0.0, 0.0, 0.0), (0.25, 0.0, 0.0), (0.0, 0.25, 0.0), (0.0, 0.0, 0.125), (0.25, 0, 0.125)]
WEDGE_TRIANGLES = [(0, 2, 1), (0, 1, 3), (1, 4, 3), (0, 3, 2), (2, 3, 4), (1, 2, 4)]


def _pose(xyz=(0.0, 0.0, 0.0), quat_xyzw=(0.0, 0.0, 0.0, 1.0)) -> dict:
    x, y, z, w = quat_xyzw
    return {
        "position": dict(zip("xyz", xyz)),
        "orientation": {"x": x, "y": y, "z": z, "w": w},
    }


def _stl(path: Path) -> Path:
    """The wedge as an ASCII STL."""
    lines = ["solid wedge"]
    for triangle in WEDGE_TRIANGLES:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {x!r} {y!r} {z!r}" for x, y, z in (WEDGE[i] for i in triangle)]
        lines += ["endloop", "endfacet"]
    path.write_text("\n".join([*lines, "endsolid wedge", ""]))
    return path


def planning_scene() -> dict:
    """A cell as a PlanningScene: a rotated object with an offset box, a ball, a cylinder, meshes."""
    mesh = {
        "vertices": [dict(zip("xyz", v)) for v in WEDGE],
        "triangles": [{"vertex_indices": list(t)} for t in WEDGE_TRIANGLES],
    }
    return {
        "name": "cell",
        "is_diff": False,
        "robot_state": {"joint_state": {"name": [], "position": []}},
        "world": {
            "collision_objects": [
                {
                    "id": "table",
                    "header": {"frame_id": "world", "stamp": {"sec": 0, "nanosec": 0}},
                    "primitives": [{"type": 1, "dimensions": [1.6, 1.6, 0.05]}],
                    "primitive_poses": [_pose((0.0, 0.0, -0.045))],
                    "operation": 0,
                },
                {  # pose: 0.5, 0, 0.3 turned 90 deg about z; the box 0.1 along the pose's x
                    "id": "post",
                    "header": {"frame_id": "base_link"},
                    "pose": _pose((0.5, 0.0, 0.3), (0.0, 0.0, S, S)),
                    "primitives": [
                        {"type": "BOX", "dimensions": [0.3, 0.1, 0.2]},
                        {"type": "cylinder", "dimensions": [0.4, 0.05]},
                    ],
                    "primitive_poses": [
                        _pose((0.1, 0.0, 0.0)),
                        _pose((0.0, -0.2, 0.0), (S, 0.0, 0.0, S)),  # 90 deg about x
                    ],
                },
                {
                    "id": "ball",
                    "header": {"frame_id": "/world"},
                    "primitives": [{"type": 2, "dimensions": [0.1]}],
                    "primitive_poses": [{"position": {"x": 0.0, "y": 0.45, "z": 0.5}}],
                },
                {
                    "id": "wedges",
                    "header": {"frame_id": "world"},
                    "pose": _pose((-0.4, -0.3, 0.2)),
                    "meshes": [mesh, {"file": "wedge.stl", "scale": 1.0}],
                    "mesh_poses": [_pose(), _pose((0.0, 0.0, 0.3))],
                },
            ]
        },
    }


#: The same cell written by hand as a scene TOML (the post's poses composed on paper).
TOML = """
[[box]]
name = "table"
size = [1.6, 1.6, 0.05]
xyz = [0.0, 0.0, -0.045]

[[box]]
name = "post[0]"
size = [0.3, 0.1, 0.2]
xyz = [0.5, 0.1, 0.3]
rpy = [0.0, 0.0, 1.5707963267948966]

[[cylinder]]
name = "post[1]"
radius = 0.05
length = 0.4
xyz = [0.7, 0.0, 0.3]
rpy = [1.5707963267948966, 0.0, 1.5707963267948966]

[[sphere]]
name = "ball"
radius = 0.1
xyz = [0.0, 0.45, 0.5]

[[mesh]]
name = "wedges[0]"
file = "wedge.stl"
xyz = [-0.4, -0.3, 0.2]

[[mesh]]
name = "wedges[1]"
file = "wedge.stl"
xyz = [-0.4, -0.3, 0.5]
"""


@pytest.fixture(scope="module")
def ur5():
    return load_robot("ur5")


@pytest.fixture()
def cell(tmp_path: Path) -> Path:
    _stl(tmp_path / "wedge.stl")
    (tmp_path / "cell.toml").write_text(TOML)
    (tmp_path / "cell.json").write_text(json.dumps(planning_scene()))
    return tmp_path


def _same_cell(ur5, toml: Path, other: Path) -> None:
    """The same verdicts and distances (1e-9 m) at 150 random configurations."""
    reference = CollisionChecker(load_collision_model(ur5, scene=toml))
    checker = CollisionChecker(load_collision_model(ur5, scene=other))
    assert set(checker.model.scene_objects) == {"table", "post", "ball", "wedges"}
    rng = np.random.default_rng(43)
    verdicts = []
    for q in rng.uniform(-math.pi, math.pi, (150, 6)):
        expected, got = reference.distance(q), checker.distance(q)
        assert got.distance == pytest.approx(expected.distance, abs=1e-9), f"{q=}"
        verdicts.append(reference.in_collision(q))
        assert checker.in_collision(q) == verdicts[-1], f"{q=}"
    assert 10 < sum(verdicts) < 140  # both verdicts seen


def test_a_planning_scene_in_json_is_the_hand_written_toml_cell(ur5, cell):
    """JSON: each primitive at pose * primitive_pose, meshes inline and by file."""
    by_name = {s.name: s for s in read_scene(cell / "cell.toml")}
    for shape in read_scene(cell / "cell.json"):
        twin = by_name[shape.name]
        assert shape.kind == twin.kind
        assert np.allclose(shape.placement.homogeneous, twin.placement.homogeneous, atol=1e-12)
    _same_cell(ur5, cell / "cell.toml", cell / "cell.json")


def test_a_planning_scene_in_yaml_is_the_same_cell(ur5, cell):
    """YAML (PyYAML), named by suffix and, without one, by its ``world:`` line."""
    yaml = pytest.importorskip("yaml")
    text = yaml.safe_dump(planning_scene())
    (cell / "cell.yaml").write_text(text)
    (cell / "cell.scene").write_text(text)
    _same_cell(ur5, cell / "cell.toml", cell / "cell.yaml")
    assert len(read_scene(cell / "cell.scene")) == 6


def test_yaml_without_pyyaml_is_one_line_with_the_install_hint(cell, monkeypatch):
    (cell / "cell.yaml").write_text("world: {}\n")
    monkeypatch.setitem(sys.modules, "yaml", None)
    with pytest.raises(CollisionModelError) as caught:
        read_scene(cell / "cell.yaml")
    assert "pip install pyyaml" in str(caught.value) and "\n" not in str(caught.value)


def test_the_allowed_collision_matrix_disables_its_pairs(ur5, cell):
    """A pair the matrix allows is not checked (reason acm); a default allows all of a name's."""
    links = load_collision_model(ur5).links
    document = planning_scene()
    names = [links[-1], "ball", "table"]
    document["allowed_collision_matrix"] = {
        "entry_names": names,
        "entry_values": [
            {"enabled": [False, True, False]},
            {"enabled": [True, False, True]},
            {"enabled": [False, True, False]},
        ],
        "default_entry_names": ["post"],
        "default_entry_values": [True],
    }
    (cell / "acm.json").write_text(json.dumps(document))
    model = load_collision_model(ur5, scene=cell / "acm.json")
    assert model.disabled[(links[-1], "ball")] == "acm"
    assert all(model.disabled[(link, "post")] == "acm" for link in links)
    assert (links[-1], "table") in model.pairs and ("post", links[0]) not in model.pairs
    plain = load_collision_model(ur5, scene=cell / "cell.json")
    assert len(plain.pairs) - len(model.pairs) == 1 + len(links)


def test_degrees_and_radians_millimetres_and_meters_place_alike(tmp_path):
    """angle_unit = "deg" and length_unit = "mm" give the radian-meter scene's placements."""
    (tmp_path / "si.toml").write_text(
        "[[box]]\nsize = [0.3, 0.1, 0.2]\nxyz = [0.5, -0.25, 0.125]\nrpy = [0.5, -0.25, 2.0]\n"
        "[[cylinder]]\nradius = 0.05\nlength = 0.4\nrpy = [3.0, 0.0, -1.0]\n"
    )
    deg = [math.degrees(a) for a in (0.5, -0.25, 2.0)]
    (tmp_path / "deg_mm.toml").write_text(
        'angle_unit = "deg"\nlength_unit = "mm"\n'
        f"[[box]]\nsize = [300, 100, 200]\nxyz = [500, -250, 125]\nrpy = {deg!r}\n"
        "[[cylinder]]\nradius = 50\nlength = 400\n"
        f"rpy = {[math.degrees(3.0), 0.0, math.degrees(-1.0)]!r}\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no slip warned on either
        si, other = read_scene(tmp_path / "si.toml"), read_scene(tmp_path / "deg_mm.toml")
    for a, b in zip(si, other):
        assert np.allclose(a.placement.homogeneous, b.placement.homogeneous, atol=1e-12)
    assert np.allclose(other[0].geometry.halfSide, [0.15, 0.05, 0.1], atol=1e-15)
    assert (other[1].geometry.radius, other[1].geometry.halfLength) == pytest.approx((0.05, 0.2))


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("[[box]]\nsize = [1, 1, 1]\nrpy = [0, 0, 90]\n", "field 'box[0].rpy[2]': 90 rad is"),
        ("[[sphere]]\nradius = 0.1\nxyz = [150, 0, 0]\n", "field 'sphere[0].xyz[0]': 150 m"),
        ('length_unit = "cm"\n[[sphere]]\nradius = 1\nxyz = [0, 2500, 0]\n', "check length_unit"),
    ],
)
def test_a_slip_is_one_warning_line_naming_the_file_and_the_field(tmp_path, text, words):
    (tmp_path / "slip.toml").write_text(text)
    with pytest.warns(UnitWarning) as caught:
        read_scene(tmp_path / "slip.toml")
    assert len(caught) == 1
    said = str(caught[0].message)
    assert said.startswith(str(tmp_path / "slip.toml")) and words in said and "\n" not in said


def test_degrees_said_and_near_places_warn_nothing(tmp_path):
    (tmp_path / "ok.toml").write_text(
        'angle_unit = "deg"\n[[box]]\nsize = [1, 1, 1]\nxyz = [19, 0, 0]\nrpy = [0, 0, 90]\n'
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        (box,) = read_scene(tmp_path / "ok.toml")
    assert np.allclose(box.placement.rotation, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("[[box]]\nsize = [40, 1, 1]\n", "box[0].size[0]: 40 m is more than the 10 m"),
        ("[[box]]\nsize = [1, 1, 1]\nxyz = [0, 0, 5000]\n", "box[0].xyz[2]: 5000 m is beyond"),
        ('angle_unit = "grad"\n', "angle_unit: 'grad' is not a unit; choose one of: deg, rad"),
        ("length_unit = 1\n", "length_unit: 1 is not a unit; choose one of: cm, m, mm"),
    ],
)
def test_a_bad_unit_or_a_millimetre_beyond_the_bounds_is_one_error_line(tmp_path, text, words):
    (tmp_path / "bad.toml").write_text(text)
    with pytest.raises(CollisionModelError) as caught:
        read_scene(tmp_path / "bad.toml")
    said = str(caught.value)
    assert words in said and "\n" not in said
    if "m is" in words:
        assert said.endswith('are the lengths in millimeters? then write length_unit = "mm"')


def test_kin_check_prints_a_slip_as_one_warning_line(tmp_path):
    (tmp_path / "slip.toml").write_text("[[sphere]]\nradius = 0.1\nxyz = [0, 0, 900]\n")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "kin",
            "check",
            "--robot",
            "ur5",
            "--q",
            "0",
            "0",
            "0",
            "0",
            "0",
            "0",
            "--scene",
            str(tmp_path / "slip.toml"),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert done.stderr.splitlines() == [
        f"kin check: warning: {tmp_path / 'slip.toml'}, field 'sphere[0].xyz[2]': 900 m from the arm's "
        'base (more than 20 m): are the lengths in millimeters? then write length_unit = "mm"'
    ]


def test_a_planning_scene_far_away_warns_with_the_ros_hint(cell):
    document = planning_scene()
    document["world"]["collision_objects"][2]["primitive_poses"][0]["position"]["z"] = 500.0
    (cell / "far.json").write_text(json.dumps(document))
    with pytest.warns(UnitWarning) as caught:
        read_scene(cell / "far.json")
    assert [str(w.message) for w in caught] == [
        f"{cell / 'far.json'}, field 'world.collision_objects[2].primitive_poses[0].position.z': "
        "500 m from the arm's base (more than 20 m): are the lengths in millimeters? a "
        "PlanningScene is in meters: divide them by 1000"
    ]


def _broken(change) -> dict:
    document = planning_scene()
    change(document["world"]["collision_objects"])
    return document


def _set(path: list, value):
    def change(objects):
        node = objects
        for key in path[:-1]:
            node = node[key]
        if value is KeyError:
            del node[path[-1]]
        else:
            node[path[-1]] = value

    return change


MALFORMED = {
    "missing id": (_set([1, "id"], KeyError), "world.collision_objects[1].id: None is not"),
    "missing header": (_set([0, "header"], KeyError), "collision_objects[0].header: None is not"),
    "three dimensions for a sphere": (
        _set([2, "primitives", 0, "dimensions"], [0.1, 0.2, 0.3]),
        "world.collision_objects[2].primitives[0].dimensions: [0.1, 0.2, 0.3] is not 1 number",
    ),
    "one dimension for a cylinder": (
        _set([1, "primitives", 1, "dimensions"], [0.4]),
        "collision_objects[1].primitives[1].dimensions: [0.4] is not 2 number(s) [height, radius]",
    ),
    "NaN": (
        _set([2, "primitives", 0, "dimensions"], [float("nan")]),
        "world.collision_objects[2].primitives[0].dimensions[0]: nan is not finite",
    ),
    "NaN orientation": (
        _set([1, "pose", "orientation", "w"], float("nan")),
        "world.collision_objects[1].pose.orientation.w: nan is not finite",
    ),
    "unknown type": (
        _set([0, "primitives", 0, "type"], 7),
        "world.collision_objects[0].primitives[0].type: 7 is not read; choose BOX (1)",
    ),
    "a cone": (_set([0, "primitives", 0, "type"], "CONE"), "(a CONE is not)"),
    "a pose short": (
        _set([1, "primitive_poses"], [{}]),
        "world.collision_objects[1].primitive_poses: 1 pose(s) for 2 primitives",
    ),
    "a misspelt key": (_set([0, "primitve_poses"], []), "[0].primitve_poses: unknown key"),
    "a plane": (_set([0, "planes"], [{"coef": [0, 0, 1, 0]}]), "[0].planes: planes (infinite)"),
    "a removal": (_set([0, "operation"], 1), "[0].operation: REMOVE is an edit of a scene"),
    "a bad triangle": (
        _set([3, "meshes", 0, "triangles", 2, "vertex_indices"], [0, 1, 9]),
        "[3].meshes[0].triangles[2].vertex_indices: [0, 1, 9] is not 3 indices of the 5",
    ),
    "a flat mesh": (
        _set([3, "meshes", 0, "vertices"], [{"x": x, "y": y} for x, y, _ in WEDGE]),
        "world.collision_objects[3].meshes[0]: not a solid",
    ),
    "a twin id": (_set([1, "id"], "table"), "world.collision_objects[1].id: 'table' is given"),
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_a_malformed_planning_scene_is_one_error_line_naming_the_field(cell, case):
    change, words = MALFORMED[case]
    (cell / "bad.json").write_text(json.dumps(_broken(change)))
    with pytest.raises(CollisionModelError) as caught:
        load_scene(cell / "bad.json")
    said = str(caught.value)
    assert said.startswith(f"{cell / 'bad.json'}: ") and "\n" not in said
    assert words in said, said


@pytest.mark.parametrize(
    ("change", "words"),
    [
        (
            lambda d: d["world"]["collision_objects"][1]["header"].update(frame_id="camera"),
            "world.collision_objects[1].header.frame_id: frame 'camera' is neither the robot's "
            "base 'base_link' nor 'world'",
        ),
        (
            lambda d: d.update(
                allowed_collision_matrix={
                    "entry_names": ["ball", "gripper"],
                    "entry_values": [{"enabled": [False, True]}, {"enabled": [True, False]}],
                }
            ),
            "allowed_collision_matrix.entry_names[1]: 'gripper' is neither a link of the robot",
        ),
        (
            lambda d: d.update(
                allowed_collision_matrix={
                    "entry_names": ["ball", "table"],
                    "entry_values": [{"enabled": [False, True]}, {"enabled": [False, False]}],
                }
            ),
            "allowed_collision_matrix.entry_values[0].enabled[1]: True where",
        ),
    ],
)
def test_another_frame_or_an_unknown_matrix_name_is_one_error_line(ur5, cell, change, words):
    document = planning_scene()
    change(document)
    (cell / "bad.json").write_text(json.dumps(document))
    with pytest.raises(CollisionModelError) as caught:
        load_collision_model(ur5, scene=cell / "bad.json")
    assert words in str(caught.value) and "\n" not in str(caught.value)


_LEAVES = (
    st.none()
    | st.booleans()
    | st.integers(-(10**20), 10**20)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.sampled_from(["BOX", "box", "SPHERE", "CYLINDER", "CONE", "world", "base_link", ""])
    | st.text(max_size=6)
)
_KEYS = st.sampled_from(
    [
        "id",
        "header",
        "frame_id",
        "pose",
        "position",
        "orientation",
        "x",
        "y",
        "z",
        "w",
        "primitives",
        "primitive_poses",
        "type",
        "dimensions",
        "meshes",
        "mesh_poses",
        "vertices",
        "triangles",
        "vertex_indices",
        "operation",
        "planes",
        "file",
        "scale",
        "entry_names",
        "entry_values",
        "enabled",
        "default_entry_names",
        "default_entry_values",
        "octomap",
        "collision_objects",
        "world",
    ]
)
_VALUES = st.recursive(
    _LEAVES,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(_KEYS, inner, max_size=5),
    max_leaves=25,
)
_PRIMITIVE = st.fixed_dictionaries(
    {
        "type": st.sampled_from([1, 2, 3, 4, "BOX"]) | _LEAVES,
        "dimensions": st.lists(_LEAVES, max_size=4),
    }
)
_OBJECT = st.fixed_dictionaries(
    {
        "id": st.sampled_from(["a", "b", "table"]) | _LEAVES,
        "header": st.fixed_dictionaries({"frame_id": st.sampled_from(["world", "x"]) | _LEAVES}),
        "primitives": st.lists(_PRIMITIVE | _VALUES, max_size=3),
        "primitive_poses": st.lists(_VALUES, max_size=3),
    },
    optional={"pose": _VALUES, "meshes": _VALUES, "mesh_poses": _VALUES, "planes": _VALUES},
)
_DOCUMENT = (
    st.fixed_dictionaries(
        {"world": st.fixed_dictionaries({"collision_objects": st.lists(_OBJECT, max_size=3)})},
        optional={
            "allowed_collision_matrix": _VALUES | st.dictionaries(_KEYS, _VALUES, max_size=4)
        },
    )
    | _VALUES
)


@settings(
    max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(document=_DOCUMENT)
def test_any_planning_scene_like_document_raises_only_collision_model_error(tmp_path, document):
    """Random documents: a scene, or one CollisionModelError line; nothing else escapes."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnitWarning)
            scene = read_planning_scene(str(tmp_path / "random.json"), json.dumps(document), False)
            scene.for_robot("base_link", {"base_link", "link1", "a", "b"}, ["base_link", "link1"])
    except CollisionModelError as err:
        assert "\n" not in str(err)
