"""The spheres of the fast checks (kin.collision.sphere_fit, kin.collision.sphere_bound).

Judged apart from the code under test: enclosure by points drawn on every shape's surface here
(scipy's hull of a mesh's points, the primitives' own faces); the lower bounds against coal's
distance of every checked pair (Pinocchio's computeDistances, the padding taken off), over
thousands of random configurations of Panda (the maker's URDF and SRDF, examples/cell.toml),
UR5 and humanoid7 (DH tables) in the same cell; the scene shapes' signed distances against coal's
distance from a point, on random shapes and points (hypothesis).
"""

from __future__ import annotations

from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull
from support.urdf_reference import erd

import kin
from kin.collision import attached_object, load_collision_model
from kin.collision.requests import prepare_requests
from kin.collision.sphere_bound import SphereBound, _SceneShapes, sphere_bound
from kin.collision.sphere_fit import enclosing_spheres, largest_gap
from kin.collision.urdf_shapes import convex_hull

CELL = Path(__file__).resolve().parents[2] / "examples" / "cell.toml"
#: coal's error near contact [m] (kin.collision.requests): the bound may exceed coal's distance
#: by no more than this.
COAL_ERROR = 3e-6


def _panda():
    robot = kin.load_robot(erd("panda_description/urdf/panda.urdf"), None, "panda_link8")
    return load_collision_model(robot, srdf=erd("panda_description/srdf/panda.srdf"), scene=CELL)


@pytest.fixture(scope="module")
def models():
    """name -> collision model in the example cell (Panda with a box in its hand, UR5 padded)."""
    panda = _panda()
    held = attached_object(
        "part",
        "panda_hand",
        box=[0.05, 0.03, 0.12],
        xyz=[0, 0, 0.15],
        touch_links=["panda_leftfinger", "panda_rightfinger"],
    )
    return {
        "panda": panda.attach(held),
        "ur5": load_collision_model(kin.load_robot("ur5"), scene=CELL, padding=0.01),
        "humanoid7": load_collision_model(kin.load_robot("humanoid7"), scene=CELL),
    }


def _surface(geometry: coal.CollisionGeometry, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` random points on the shape's surface, in its frame [m]."""
    if isinstance(geometry, coal.Sphere):
        unit = rng.normal(size=(count, 3))
        return geometry.radius * unit / np.linalg.norm(unit, axis=1, keepdims=True)
    if isinstance(geometry, coal.Box):
        half = np.asarray(geometry.halfSide)
        points = rng.uniform(-1.0, 1.0, (count, 3)) * half
        axis = rng.integers(0, 3, count)
        points[np.arange(count), axis] = np.sign(rng.uniform(-1, 1, count)) * half[axis]
        return points
    if isinstance(geometry, (coal.Cylinder, coal.Capsule)):
        r, h = geometry.radius, geometry.halfLength
        angle = rng.uniform(0.0, 2.0 * np.pi, count)
        z = rng.uniform(-h, h, count)
        rim = np.column_stack([r * np.cos(angle), r * np.sin(angle), z])
        if isinstance(geometry, coal.Capsule):  # half the points on the end caps
            unit = rng.normal(size=(count, 3))
            cap = r * unit / np.linalg.norm(unit, axis=1, keepdims=True)
            cap[:, 2] = np.where(cap[:, 2] > 0, cap[:, 2] + h, cap[:, 2] - h)
            return np.vstack([rim[: count // 2], cap[count // 2 :]])
        disc = np.sqrt(rng.uniform(0, 1, count)) * r  # half the points on the flat ends
        ends = np.column_stack([disc * np.cos(angle), disc * np.sin(angle), np.sign(z) * h])
        return np.vstack([rim[: count // 2], ends[count // 2 :]])
    points = np.array(geometry.points()).reshape(-1, 3)
    hull = ConvexHull(points)
    triangles = points[hull.simplices[rng.integers(0, len(hull.simplices), count)]]
    u, v = rng.uniform(0, 1, (2, count))
    flip = u + v > 1.0
    u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
    return (
        triangles[:, 0]
        + u[:, None] * (triangles[:, 1] - triangles[:, 0])
        + v[:, None] * (triangles[:, 2] - triangles[:, 0])
    )


def _inside(points: np.ndarray, centers: np.ndarray, radii: np.ndarray) -> np.ndarray:
    gaps = np.linalg.norm(points[:, None, :] - centers[None], axis=2) - radii[None]
    return gaps.min(axis=1) <= 1e-12


def test_every_shape_lies_inside_its_spheres(models):
    """(a) Random surface points of every arm shape (links, fingers, the held box) are covered."""
    rng = np.random.default_rng(0)
    shapes = [coal.Capsule(0.04, 0.3), coal.Cylinder(0.2, 0.05), coal.Box(0.3, 0.2, 0.004)]
    for model in models.values():
        scene = set(model.scene_objects)
        shapes += [
            obj.geometry
            for obj, owner in zip(model.geometry_model.geometryObjects, model.owners)
            if owner not in scene
        ]
    kinds = {type(g).__name__ for g in shapes}
    assert {"Convex", "Box", "Cylinder", "Capsule"} <= kinds
    for geometry in shapes:
        centers, radii = enclosing_spheres(geometry)
        points = _surface(geometry, 4000, rng)
        assert _inside(points, centers, radii).all(), type(geometry).__name__
        # the cover is not the shape's bounding ball alone, nor wildly larger than the shape
        assert 0.0 <= largest_gap(geometry, centers, radii, 60) < 2.0 * radii.max()


def _exact(model, q: np.ndarray) -> np.ndarray:
    """coal's distance of every checked pair at ``q``, padding taken off [m]."""
    data = model.robot.model.createData()
    geometry_data = pin.GeometryData(model.geometry_model)
    prepare_requests(geometry_data, model.padding)
    pin.computeDistances(model.robot.model, data, model.geometry_model, geometry_data, q)
    return np.array([r.min_distance for r in geometry_data.distanceResults]) - model.padding


@pytest.mark.parametrize("name", ["panda", "ur5", "humanoid7"])
def test_the_bound_never_exceeds_coal_distance(models, name):
    """(b) Over 2,000 random configurations, each positive bound is at most coal's distance."""
    model = models[name]
    robot = model.robot
    bound = SphereBound(model)
    rng = np.random.default_rng(7)
    qs = rng.uniform(robot.lower, robot.upper, (2000, robot.nq))
    bounds = bound.lower_bounds(qs)
    assert np.array_equal(bounds[11], bound.lower_bounds(qs[11]))  # one row, or many
    shown = 0
    for q, lower in zip(qs, bounds):
        exact = _exact(model, q)
        positive = np.isfinite(lower)
        assert (lower[positive] <= exact[positive] + COAL_ERROR).all(), (q, lower - exact)
        assert (lower[~positive] == -np.inf).all()
        shown += int(positive.sum())
    # the bounds decide most pairs (not a bound that says -inf everywhere)
    assert shown > 0.5 * bounds.size, shown / bounds.size


def test_the_bound_is_made_once_per_model(models):
    model = models["ur5"]
    assert sphere_bound(model) is sphere_bound(model)


_PLACES = st.tuples(*[st.floats(-0.5, 0.5)] * 3)
_TURNS = st.tuples(*[st.floats(-3.2, 3.2)] * 3)
_SIZES = st.floats(0.01, 0.4)


@settings(max_examples=60, deadline=None)
@given(
    kind=st.sampled_from(["box", "sphere", "cylinder", "capsule", "convex"]),
    sizes=st.tuples(_SIZES, _SIZES, _SIZES),
    xyz=_PLACES,
    rpy=_TURNS,
    seed=st.integers(0, 2**16),
)
def test_scene_distances_are_coal_distances_from_a_point(kind, sizes, xyz, rpy, seed):
    """A scene shape's distance from a point: coal's where it is a primitive, at most coal's for a
    hull (through its bounding box), for points outside; negative inside."""
    a, b, c = sizes
    rng = np.random.default_rng(seed)
    geometry = {
        "box": lambda: coal.Box(a, b, c),
        "sphere": lambda: coal.Sphere(a),
        "cylinder": lambda: coal.Cylinder(a, b),
        "capsule": lambda: coal.Capsule(a, b),
        "convex": lambda: convex_hull(rng.uniform(-1, 1, (20, 3)) * [a, b, c], "random points"),
    }[kind]()
    placement = pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz))
    shapes = _SceneShapes([pin.GeometryObject("thing", 0, 0, placement, geometry)])
    points = rng.uniform(-1.0, 1.0, (40, 3))
    found = shapes.distances(points[None])[0, :, 0]
    tiny = coal.Sphere(1e-9)
    where = coal.Transform3s(placement.rotation, placement.translation)
    for point, value in zip(points, found):
        result = coal.DistanceResult()
        exact = coal.distance(
            tiny,
            coal.Transform3s(np.eye(3), point),
            geometry,
            where,
            coal.DistanceRequest(),
            result,
        )
        if exact > 1e-6:  # outside: the distance (at most it for a hull's box)
            if kind == "convex":
                assert value <= exact + 1e-8  # the test point is a ball of 1e-9 m
            else:
                assert value == pytest.approx(exact, abs=1e-7)
        else:
            assert value <= 1e-7


def test_threads_share_a_bound(models):
    """One model's bound from four threads at once gives each thread its own configurations'."""
    from concurrent.futures import ThreadPoolExecutor

    model = models["panda"]
    bound = sphere_bound(model)
    rng = np.random.default_rng(2)
    chunks = [rng.uniform(model.robot.lower, model.robot.upper, (300, 7)) for _ in range(4)]
    alone = [np.array([bound.lower_bounds(q) for q in chunk]) for chunk in chunks]
    with ThreadPoolExecutor(4) as pool:
        together = list(pool.map(lambda c: np.array([bound.lower_bounds(q) for q in c]), chunks))
    for a, b in zip(alone, together):
        assert np.array_equal(a, b)
