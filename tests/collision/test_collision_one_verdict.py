"""One verdict near contact: in_collision, its batch, collisions() and distance() agree.

Issue 42: coal's verdict-only query (``in_collision``) called overlaps of 1-7.5 um with a cylinder
free while ``collisions()`` and ``distance()`` said colliding; at a 1e-9 m gap ``in_collision``
said free while ``collisions()`` listed contacts; ``distance()`` gave 0.0 for gaps of 1e-9 to
1e-6 m. Judged here against gaps placed by hand (a cylinder link beside a box, a sphere or a
cylinder, whose distance is the gap exactly), and in a property test against coal's own distance
asked afresh (and the analytic distance of spheres and boxes).
"""

from __future__ import annotations

import math

import coal
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.requests import CONTACT_TOLERANCE, prepare_requests

#: A one-joint arm: a cylinder of radius 5 cm, 20 cm long, turning about its own axis (z).
ARM = """<robot name="probe">
 <link name="base"/>
 <link name="arm"><collision><geometry><cylinder radius="0.05" length="0.2"/></geometry>
 </collision></link>
 <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
  <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""
#: Objects whose side faces the cylinder's side at x = 0.05 + gap (each 5 cm from its centre).
OBJECTS = {
    "box": "size = [0.1, 0.1, 0.1]",
    "sphere": "radius = 0.05",
    "cylinder": "radius = 0.05\nlength = 0.1",
}
GAPS = [1e-5 * 3, 1.5e-5, 7.5e-6, 3e-6, 1e-6, 1e-7, 1e-8, 1e-9, 0.0]
GAPS += [-g for g in GAPS[2:-1]] + [-1e-5, -3e-5]


@pytest.fixture(scope="module")
def probe(tmp_path_factory):
    folder = tmp_path_factory.mktemp("probe")
    (folder / "probe.urdf").write_text(ARM, encoding="utf-8")
    return folder, load_robot(str(folder / "probe.urdf"), None, "arm")


@pytest.mark.parametrize("kind", sorted(OBJECTS))
@pytest.mark.parametrize("gap", GAPS)
def test_every_query_gives_the_verdict_of_the_gap(probe, kind, gap):
    """In contact below the tolerance, free above it; collisions() lists what in_collision counts;
    distance() is the gap (not 0.0 for gaps of 1e-7 to 1e-6 m)."""
    folder, robot = probe
    scene = folder / f"{kind}.toml"
    scene.write_text(f"[[{kind}]]\n{OBJECTS[kind]}\nxyz = [{0.1 + gap!r}, 0.0, 0.0]\n")
    checker = CollisionChecker(load_collision_model(robot, scene=scene))
    q = np.zeros(1)
    verdict = checker.in_collision(q)
    assert verdict is (gap < CONTACT_TOLERANCE), f"{kind=} {gap=}"
    assert checker.in_collision_batch(q[None])[0] == verdict, f"{kind=} {gap=}"
    contacts = checker.collisions(q)
    assert bool(contacts) == verdict, f"{kind=} {gap=}"
    assert all(c.depth >= 0.0 for c in contacts)
    closest = checker.distance(q)
    assert closest.distance == pytest.approx(gap, abs=max(1e-8, 1e-3 * abs(gap))), f"{kind=}"
    if contacts:
        assert contacts[0].depth == pytest.approx(max(0.0, -gap), abs=1e-8), f"{kind=} {gap=}"
        assert np.isfinite(contacts[0].point_a).all() and np.isfinite(contacts[0].point_b).all()


def test_padding_shifts_the_verdict_by_itself(probe):
    """A box 2 mm away: free without padding, in contact at 3 mm, depth 1 mm."""
    folder, robot = probe
    scene = folder / "near.toml"
    scene.write_text("[[box]]\nsize = [0.1, 0.1, 0.1]\nxyz = [0.102, 0.0, 0.0]\n")
    q = np.zeros(1)
    assert not CollisionChecker(load_collision_model(robot, scene=scene)).in_collision(q)
    padded = CollisionChecker(load_collision_model(robot, scene=scene, padding=0.003))
    assert padded.in_collision(q) and padded.in_collision_batch(q[None])[0]
    (contact,) = padded.collisions(q)
    assert contact.depth == pytest.approx(0.001, abs=1e-8)
    assert padded.distance(q).distance == pytest.approx(-0.001, abs=1e-8)


# -- property: random primitive pairs at tiny gaps and overlaps --------------------------------

KINDS = ("box", "sphere", "cylinder", "capsule", "hull")


def _shape(kind: str, sizes: list[float], seed: int) -> coal.CollisionGeometry:
    a, b, c = sizes
    if kind == "box":
        return coal.Box(2 * a, 2 * b, 2 * c)
    if kind == "sphere":
        return coal.Sphere(a)
    if kind == "cylinder":
        return coal.Cylinder(a, 2 * b)
    if kind == "capsule":
        return coal.Capsule(a, 2 * b)
    points = coal.StdVec_Vec3s()
    for point in np.random.default_rng(seed).normal(size=(24, 3)) * [a, b, c]:
        points.append(point)
    return coal.ConvexBase.convexHull(points, False, "Qt")


def _reference(g1, m1: pin.SE3, g2, m2: pin.SE3) -> tuple[float, np.ndarray]:
    """Signed distance [m] by coal with a fresh request (GJK to 1e-10), the unit normal 1 -> 2."""
    request = coal.DistanceRequest()
    request.gjk_tolerance = 1e-10
    result = coal.DistanceResult()
    d = coal.distance(
        g1,
        coal.Transform3s(m1.rotation, m1.translation),
        g2,
        coal.Transform3s(m2.rotation, m2.translation),
        request,
        result,
    )
    return float(d), np.asarray(result.normal, dtype=float)


def _analytic(kind1, g1, m1, kind2, g2, m2) -> float | None:
    """Sphere-sphere and sphere-box signed distance [m] (box-sphere outside the box only)."""
    if kind1 == kind2 == "sphere":
        return float(np.linalg.norm(m2.translation - m1.translation)) - g1.radius - g2.radius
    if {kind1, kind2} == {"sphere", "box"}:
        (box, mb), (sphere, ms) = ((g1, m1), (g2, m2)) if kind1 == "box" else ((g2, m2), (g1, m1))
        local = mb.rotation.T @ (ms.translation - mb.translation)
        half = np.asarray(box.halfSide)
        outside = np.maximum(np.abs(local) - half, 0.0)
        if not outside.any():
            return None
        return float(np.linalg.norm(outside)) - sphere.radius
    return None


sizes = st.lists(st.floats(0.005, 1.0), min_size=3, max_size=3)
angles = st.lists(st.floats(-math.pi, math.pi), min_size=3, max_size=3)
# nearly axis-aligned placements too: coal's support functions err where a direction's component
# is tiny but not zero
near_axes = st.sampled_from([0.0, 1e-9, -1e-7, 1e-5, math.pi / 2])
tilts = st.one_of(angles, st.lists(near_axes, min_size=3, max_size=3))


@settings(max_examples=400, deadline=None, derandomize=True)
@example(  # the void example: its reference is -DBL_MAX (seen on a CI run)
    kinds=("cylinder", "cylinder"),
    sizes1=[0.875, 1.0, 1.0],
    sizes2=[0.875, 1.0, 1.0],
    rpy1=[0.0, 0.0, 0.0],
    rpy2=[0.0, 0.0, 0.0],
    direction=[0.0, 1.0, 0.0],
    gap=0.0,
    padding=0.0,
    seed=0,
)
@given(
    kinds=st.tuples(st.sampled_from(KINDS), st.sampled_from(KINDS)),
    sizes1=sizes,
    sizes2=sizes,
    rpy1=tilts,
    rpy2=tilts,
    direction=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).filter(
        lambda v: np.linalg.norm(v) > 0.1
    ),
    gap=st.one_of(st.floats(-3e-5, 3e-5), st.sampled_from([1e-9, -1e-9, 1e-6, -1e-6, 0.0])),
    padding=st.sampled_from([0.0, 0.0, 0.002]),
    seed=st.integers(0, 100),
)
def test_verdict_is_never_free_where_the_shapes_overlap(
    kinds, sizes1, sizes2, rpy1, rpy2, direction, gap, padding, seed
):
    """Random pairs at tiny gaps: the checker's verdict query (the requests every query uses) is
    in contact where coal's fresh distance, or the analytic one, says overlap beyond 1 um, free
    where it says apart by more than the tolerance + 1 um; its distance query is within 3 um."""
    g1, g2 = _shape(kinds[0], sizes1, seed), _shape(kinds[1], sizes2, seed + 1)
    m1 = pin.SE3(pin.rpy.rpyToMatrix(*rpy1), np.zeros(3))
    unit = np.asarray(direction) / np.linalg.norm(direction)
    far = 2.0 * (max(sizes1) + max(sizes2)) + 0.05
    m2 = pin.SE3(pin.rpy.rpyToMatrix(*rpy2), far * unit)
    d0, normal = _reference(g1, m1, g2, m2)
    m2 = pin.SE3(m2.rotation, m2.translation - (d0 - padding - gap) * normal)  # about gap apart

    geometry = pin.GeometryModel()
    for name, g, m in (("one", g1, m1), ("two", g2, m2)):
        geometry.addGeometryObject(pin.GeometryObject(name, 0, 0, m, g))
    geometry.addCollisionPair(pin.CollisionPair(0, 1))
    model = pin.Model()
    data, geometry_data = model.createData(), pin.GeometryData(geometry)
    prepare_requests(geometry_data, padding)
    pin.updateGeometryPlacements(model, data, geometry, geometry_data, np.zeros(0))
    verdict = pin.computeCollision(geometry, geometry_data, 0)
    ours = pin.computeDistance(geometry, geometry_data, 0).min_distance - padding

    reference, _ = _reference(g1, m1, g2, m2)
    exact = _analytic(kinds[0], g1, m1, kinds[1], g2, m2)
    # coal's fresh query has no answer for some exact touches (two equal cylinders side by side
    # along a line: its EPA returns -DBL_MAX): no reference to compare with, the example is void.
    assume(exact is not None or abs(reference) < 1e3)
    truth = (reference if exact is None else exact) - padding
    said = f"{kinds=} {truth=} {ours=} {verdict=}"
    if truth < -1e-6:
        assert verdict, said
    if truth > CONTACT_TOLERANCE + 1e-6:
        assert not verdict, said
    assert abs(ours - truth) < 3e-6, said
    if ours < 0:
        assert verdict, said  # distance() below 0 is never a free verdict
