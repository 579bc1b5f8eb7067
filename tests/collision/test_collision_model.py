"""The collision model and its queries, against hand-computed distances, the URDF's own shapes
counted with ElementTree, Pinocchio's FK of the original URDF and its own mesh (BVH) check."""

from __future__ import annotations

import logging
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support.stick_arms import stick_robot
from support.urdf_reference import erd

import kin
from dh2urdf import ROBOTS
from kin.collision import (
    CollisionChecker,
    CollisionModelError,
    load_collision_model,
)
from kin.collision.requests import CONTACT_TOLERANCE
from kin.collision.srdf import read_srdf

PANDA = "panda_description/urdf/panda.urdf"
#: Every link of Panda's URDF with a <collision> (link8 has none): the chain to panda_link8 and
#: the hand and fingers beyond it, held at their joints' values.
PANDA_LINKS = (
    *(f"panda_link{i}" for i in range(8)),
    "panda_hand",
    "panda_leftfinger",
    "panda_rightfinger",
)


@pytest.fixture(scope="module")
def panda() -> kin.RobotModel:
    return kin.load_robot(str(erd(PANDA)), tip="panda_link8")


@pytest.fixture(scope="module")
def ur5() -> kin.RobotModel:
    """The shipped UR5's DH chain as 1 cm sticks: the hand-computed cases below."""
    return stick_robot("ur5")


def _collision_counts(root: ET.Element) -> dict[str, int]:
    return {
        link.get("name", ""): len(link.findall("collision"))
        for link in root.iter("link")
        if link.findall("collision")
    }


def _scene(tmp_path: Path, text: str, name: str = "scene.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_dh_robot_has_the_writers_link_cylinders(ur5):
    """A DH robot: one shape per <collision> of the generated URDF, on the same links."""
    expected = _collision_counts(ET.fromstring(ur5.urdf))
    model = load_collision_model(ur5)
    counted = {link: model.owners.count(link) for link in model.links}
    assert counted == expected and sum(expected.values()) == 6
    assert "cylinder as given" in model.shape_note


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_every_shipped_robot_has_a_model(name):
    """Every shipped robot: shapes on its links; with three or more, some pair is checked."""
    model = load_collision_model(kin.load_robot(name))
    assert len(model.links) >= 1, f"{name=}"
    assert bool(model.pairs) == (len(model.links) >= 3), f"{name=} {model.links}"


def test_panda_shapes_per_link_and_srdf_pairs(panda):
    """Panda: one shape per <collision> of every link; the SRDF's pairs are allowed."""
    root = ET.parse(erd(PANDA)).getroot()
    counts = _collision_counts(root)
    srdf = erd("panda_description/srdf/panda.srdf")
    model = load_collision_model(panda, srdf=srdf)
    assert model.links == PANDA_LINKS
    assert {link: model.owners.count(link) for link in model.links} == {
        link: counts[link] for link in PANDA_LINKS
    }
    assert "convex hulls" in model.shape_note
    expected = set()
    for element in ET.parse(srdf).getroot().iter("disable_collisions"):
        a, b = element.get("link1"), element.get("link2")
        if a in PANDA_LINKS and b in PANDA_LINKS:
            expected.add(frozenset((a, b)))
    srdf_pairs = {frozenset(p) for p, why in model.disabled.items() if why.startswith("srdf")}
    adjacent = {frozenset(p) for p, why in model.disabled.items() if why == "adjacent"}
    rigid = {frozenset(p) for p, why in model.disabled.items() if why == "rigid"}
    assert srdf_pairs == expected - adjacent - rigid
    assert len(adjacent) == 10  # the chain's 7, link7/hand, the hand and each finger
    assert rigid == {  # on joint 7 with the fingers held
        frozenset(("panda_link7", "panda_leftfinger")),
        frozenset(("panda_link7", "panda_rightfinger")),
        frozenset(("panda_leftfinger", "panda_rightfinger")),
    }
    assert len(model.pairs) == 55 - len(adjacent | srdf_pairs | rigid)


def test_panda_shapes_sit_where_the_original_urdf_puts_them(panda):
    """Shape placements on the DH model equal the original URDF's link poses times their origin."""
    path = str(erd(PANDA))
    model = load_collision_model(panda)
    original = pin.buildModelFromUrdf(path)
    odata = original.createData()
    data = panda.model.createData()
    geometry_data = pin.GeometryData(model.geometry_model)
    root = ET.parse(path).getroot()
    origins: list[pin.SE3] = []  # in the URDF's order, as the model's shapes
    for link in root.iter("link"):
        for collision in link.findall("collision"):
            origin = collision.find("origin")
            xyz = [float(v) for v in (origin.get("xyz") if origin is not None else "0 0 0").split()]
            rpy = [float(v) for v in (origin.get("rpy") if origin is not None else "0 0 0").split()]
            origins.append(pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz)))
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = rng.uniform(panda.lower, panda.upper)
        full = pin.neutral(original)
        for name, value in zip(panda.joint_names, q, strict=True):
            full[original.joints[original.getJointId(name)].idx_q] = value
        pin.framesForwardKinematics(original, odata, full)
        pin.updateGeometryPlacements(panda.model, data, model.geometry_model, geometry_data, q)
        base = odata.oMf[original.getFrameId("panda_link0")].inverse()
        for index, owner in enumerate(model.owners):  # the fingers at 0: the URDF's neutral
            expected = base * odata.oMf[original.getFrameId(owner)] * origins[index]
            assert np.allclose(
                geometry_data.oMg[index].homogeneous, expected.homogeneous, atol=1e-9
            ), owner


def test_hand_computed_distance_and_depth_to_a_sphere(ur5, tmp_path):
    """UR5 at zero: the base cylinder (radius 0.01 m on the z axis) to a ball of radius 0.1 m."""
    checker = CollisionChecker(
        load_collision_model(
            ur5, scene=_scene(tmp_path, '[[sphere]]\nname="ball"\nradius=0.1\nxyz=[0,0.15,0.03]\n')
        )
    )
    closest = checker.distance(np.zeros(6))
    assert (closest.a, closest.b) == ("frame0", "ball")
    assert closest.distance == pytest.approx(0.15 - 0.01 - 0.1, abs=1e-9)
    assert np.allclose(closest.point_a, [0, 0.01, 0.03]) and np.allclose(
        closest.point_b, [0, 0.05, 0.03]
    )
    assert not checker.in_collision(np.zeros(6)) and checker.collisions(np.zeros(6)) == ()
    inside = _scene(tmp_path, '[[sphere]]\nname="ball"\nradius=0.1\nxyz=[0,0.05,0.05]\n', "b.toml")
    checker = CollisionChecker(load_collision_model(ur5, scene=inside))
    contacts = {(c.a, c.b): c for c in checker.collisions(np.zeros(6))}
    assert contacts[("frame0", "ball")].depth == pytest.approx(0.1 + 0.01 - 0.05, abs=1e-9)
    assert checker.in_collision(np.zeros(6))


def test_padding_counts_as_contact(ur5, tmp_path):
    """A padding of 0.05 m makes the 0.04 m gap a contact 0.01 m deep."""
    scene = _scene(tmp_path, '[[sphere]]\nname="ball"\nradius=0.1\nxyz=[0,0.15,0.03]\n')
    checker = CollisionChecker(load_collision_model(ur5, scene=scene, padding=0.05))
    assert checker.in_collision(np.zeros(6))
    assert checker.distance(np.zeros(6)).distance == pytest.approx(-0.01, abs=1e-9)
    assert checker.collisions(np.zeros(6))[0].depth == pytest.approx(0.01, abs=1e-9)


def test_box_scene_hand_computed(ur5, tmp_path):
    """A box whose face is 0.03 m from the base cylinder's side; the same cell as a URDF."""
    toml = '[[box]]\nname="block"\nsize=[0.1,0.1,0.1]\nxyz=[-0.09,0,0.04]\nrpy=[0,0,0]\n'
    checker = CollisionChecker(load_collision_model(ur5, scene=_scene(tmp_path, toml)))
    closest = checker.distance(np.zeros(6))
    assert (closest.b, closest.distance) == ("block", pytest.approx(0.04 - 0.01, abs=1e-6))
    urdf = _scene(
        tmp_path,
        '<robot name="cell"><link name="block"><collision><origin xyz="-0.09 0 0.04"/>'
        '<geometry><box size="0.1 0.1 0.1"/></geometry></collision></link></robot>',
        "cell.urdf",
    )
    closest = CollisionChecker(load_collision_model(ur5, scene=urdf)).distance(np.zeros(6))
    assert (closest.b, closest.distance) == ("block", pytest.approx(0.03, abs=1e-6))


def test_ur5_meshes_folded_and_free_as_pinocchios_own_mesh_check():
    """UR5 (maker's meshes): hulls enclose the meshes, so their distance is never larger, and a
    folded arm collides under both; Pinocchio's own URDF reading (BVH meshes) is the reference."""
    path = str(erd("ur_description/urdf/ur5_robot.urdf"))
    robot = kin.load_robot(path, tip="tool0")
    model = load_collision_model(robot)
    checker = CollisionChecker(model)
    original = pin.buildModelFromUrdf(path)
    folder = Path(path).parent
    dirs = [str(p) for p in [folder, *folder.parents][:6]]
    meshes = pin.buildGeomFromUrdf(original, path, pin.GeometryType.COLLISION, package_dirs=dirs)
    names = [g.name for g in meshes.geometryObjects]
    for a, b in model.pairs:
        meshes.addCollisionPair(
            pin.CollisionPair(
                next(i for i, n in enumerate(names) if n.startswith(a + "_")),
                next(i for i, n in enumerate(names) if n.startswith(b + "_")),
            )
        )
    mdata, gdata = original.createData(), pin.GeometryData(meshes)
    free = np.array([0.0, -1.57, 0.0, -1.57, 0.0, 0.0])
    folded = np.array([0.0, -1.57, 3.1, 0.0, 0.0, 0.0])
    verdicts = []
    for q in (free, folded):
        full = pin.neutral(original)
        for name, value in zip(robot.joint_names, q, strict=True):
            joint = original.joints[original.getJointId(name)]
            full[joint.idx_q] = value
        reference = pin.computeCollisions(
            original, original.createData(), meshes, gdata, full, False
        )
        pin.computeDistances(original, mdata, meshes, gdata, full)
        mesh_distance = min(r.min_distance for r in gdata.distanceResults)
        ours = checker.distance(q).distance
        assert ours <= mesh_distance + 1e-6, (q, ours, mesh_distance)
        verdicts.append((bool(reference), checker.in_collision(q)))
    assert verdicts == [(False, False), (True, True)]


def test_batches_equal_single_queries(panda):
    """in_collision_batch and distances_batch give the single answers; contact below distance 0,
    free above the contact tolerance (configuration 46: 4.7 um apart, in contact with depth 0)."""
    model = load_collision_model(
        panda,
        srdf=erd("panda_description/srdf/panda.srdf"),
        scene=Path(__file__).parents[1] / "data" / "collision" / "cell.toml",
    )
    checker = CollisionChecker(model)
    qs = np.random.default_rng(7).uniform(panda.lower, panda.upper, (300, panda.nq))
    single = np.array([checker.in_collision(q) for q in qs])
    assert 0 < single.sum() < len(qs)
    assert np.array_equal(checker.in_collision_batch(qs), single)
    assert np.array_equal(checker.in_collision_batch(qs, threads=1), single)
    distances = checker.distances_batch(qs)
    assert not (distances < 0)[~single].any() and not (distances > CONTACT_TOLERANCE)[single].any()
    assert 0 < distances[46] < CONTACT_TOLERANCE and single[46]
    assert np.array_equal(np.array([bool(checker.collisions(q)) for q in qs]), single)


def test_configuration_wrappers(ur5):
    """Configuration.collisions/distance ask the checker at the configuration's q."""
    checker = CollisionChecker(load_collision_model(ur5))
    folded = kin.Configuration(ur5, [0, -1.5, 3.1, 0, 0, 0])
    contacts = folded.collisions(checker)
    assert [(c.a, c.b) for c in contacts] == [("link2", "frame3")] and contacts[0].depth > 0
    assert folded.distance(checker).distance < 0 < kin.Configuration(ur5).distance(checker).distance


def test_missing_robot_mesh_warns_once_and_drops_the_shape(tmp_path, caplog):
    """A URDF mesh that cannot be found: one warning naming file and link; other shapes kept."""
    source = erd(PANDA)
    root = ET.parse(source).getroot()
    folder = source.parent
    for mesh in root.iter("mesh"):
        rest = mesh.get("filename", "")[len("package://") :]
        mesh.set("filename", str(next(p / rest for p in folder.parents if (p / rest).is_file())))
    link3 = next(link for link in root.iter("link") if link.get("name") == "panda_link3")
    link3.find("collision/geometry/mesh").set("filename", str(tmp_path / "gone.stl"))
    (tmp_path / "panda.urdf").write_bytes(ET.tostring(root))
    robot = kin.load_robot(str(tmp_path / "panda.urdf"), tip="panda_link8")
    with caplog.at_level(logging.WARNING, logger="kin.collision"):
        model = load_collision_model(robot)
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) == 1 and "gone.stl" in lines[0] and "panda_link3" in lines[0], lines
    assert "panda_link3" not in model.links and len(model.links) == len(PANDA_LINKS) - 1


@pytest.mark.parametrize(
    ("text", "field"),
    [
        ("[[box]]\nsize=[0.1, nan, 0.1]\n", "box[0].size[1]"),
        ("[[box]]\nsize=[0.1, -0.1, 0.1]\n", "box[0].size[1]"),
        ("[[sphere]]\nradius=-1\n", "sphere[0].radius"),
        ("[[sphere]]\nradius=0.1\nxyz=[0, inf, 0]\n", "sphere[0].xyz[1]"),
        ("[[cylinder]]\nradius=0.1\n", "cylinder[0].length"),
        ("[[sphere]]\nradius=0.1\ncolour='red'\n", "sphere[0].colour"),
        ("[[cone]]\nradius=0.1\n", "cone"),
        ("[[box]]\nsize=[1,1,1]\nname='a'\n[[sphere]]\nradius=1\nname='a'\n", "'a'"),
        ("[[mesh]]\nfile='nowhere.stl'\n", "mesh[0].file"),
        ("[[mesh]]\nfile='junk.stl'\n", "mesh[0].file"),
        ("[[box]\nsize=1\n", "not a TOML"),
        ("[[sphere]]\nradius=0.1\nname='frame0'\n", "'frame0'"),
    ],
)
def test_bad_scene_names_file_and_field(ur5, tmp_path, text, field):
    """Bad scene input: a CollisionModelError naming the file and the field, one line."""
    (tmp_path / "junk.stl").write_bytes(b"solid junk\nnot a facet\n")
    path = _scene(tmp_path, text)
    with pytest.raises(CollisionModelError) as caught:
        load_collision_model(ur5, scene=path)
    message = str(caught.value)
    assert str(path) in message and field in message and "\n" not in message, message


def test_bad_srdf(panda, tmp_path, caplog):
    """An SRDF naming a link the robot lacks, or not XML: an error; another robot's name: a warning."""
    srdf = tmp_path / "arm.srdf"
    srdf.write_text(
        '<robot name="panda"><disable_collisions link1="panda_link1" link2="shoulder"/></robot>'
    )
    with pytest.raises(CollisionModelError, match=r"arm\.srdf: disable_collisions\[0\]\.link2"):
        load_collision_model(panda, srdf=srdf)
    srdf.write_text("<robot name='panda'><disable_collisions")
    with pytest.raises(CollisionModelError, match="not XML"):
        load_collision_model(panda, srdf=srdf)
    srdf.write_text(
        '<robot name="ur5"><disable_collisions link1="panda_link1" link2="panda_link5" reason="x"/></robot>'
    )
    with caplog.at_level(logging.WARNING, logger="kin.collision"):
        disabled = read_srdf(
            srdf, "panda", {"panda_link1", "panda_link5"}, {"panda_link1", "panda_link5"}
        )
    assert disabled == {("panda_link1", "panda_link5"): "srdf: x"}
    assert len(caplog.records) == 1 and "'ur5'" in caplog.records[0].getMessage()


def test_bad_padding(ur5):
    """A negative or non-finite padding is refused."""
    for padding in (-0.01, math.nan):
        with pytest.raises(CollisionModelError, match="padding"):
            load_collision_model(ur5, padding=padding)


HOSTILE = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**30), 10**30),
    st.booleans(),
    st.text(max_size=3),
)


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    size=st.lists(HOSTILE, min_size=0, max_size=4),
    radius=HOSTILE,
    xyz=st.lists(HOSTILE, max_size=4),
)
def test_hostile_scene_values(ur5, tmp_path, size, radius, xyz):
    """Any values: a model whose sizes are finite and > 0, or one CollisionModelError line."""
    import json

    def toml(value):  # noqa: ANN001, ANN202
        if isinstance(value, float) and not math.isfinite(value):
            return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
        if isinstance(value, bool):
            return "true" if value else "false"
        if isinstance(value, list):
            return "[" + ", ".join(toml(v) for v in value) + "]"
        return json.dumps(value)

    path = _scene(
        tmp_path,
        f"[[box]]\nsize = {toml(size)}\nxyz = {toml(xyz)}\n[[sphere]]\nradius = {toml(radius)}\n",
    )
    try:
        model = load_collision_model(ur5, scene=path)
    except CollisionModelError as err:
        assert str(path) in str(err) and "\n" not in str(err)
        return
    good = [
        v for v in (*size, radius) if not isinstance(v, bool | str) and math.isfinite(v) and v > 0
    ]
    assert len(good) == 4 and model.scene_objects == ("box1", "sphere1")
    assert np.isfinite(CollisionChecker(model).distance(np.zeros(6)).distance)
