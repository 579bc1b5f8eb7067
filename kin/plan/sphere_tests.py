"""The tests of :mod:`kin.plan.sphere_motion`, made from a collision model: the arrays of its twin.

Per joint its parent, coordinate index, axis and placement; per sphere its joint and center; per
test its spheres (or scene shape), its arms [m/rad] (joints carrying both centers of a self test
left out) and its offset (radii and padding) [m]; per pair of shapes a group of tests, a coarse
one first; per scene shape its kind, rotation, center and half sizes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..path.pair_distances import PROVEN_APART

if TYPE_CHECKING:  # pragma: no cover
    from ..collision.model import CollisionModel

__all__ = ["sphere_tests"]

#: Rounding taken off every test value [m] (the bounds' own arithmetic; far below coal's error).
_ROUNDING = 1e-9
#: Joints the rule covers, by Pinocchio's short name -> their fixed axis (None: the model's own).
_AXES: dict[str, tuple[float, float, float] | None] = {
    "JointModelRX": (1.0, 0.0, 0.0),
    "JointModelRY": (0.0, 1.0, 0.0),
    "JointModelRZ": (0.0, 0.0, 1.0),
    "JointModelRevoluteUnaligned": None,
}


def sphere_tests(model: CollisionModel) -> dict[str, np.ndarray] | None:
    """The arrays of ``model``'s tests (the module), or None where the rule does not apply.

    None: a joint that is not revolute with one coordinate, or a pair of shapes fixed to the
    world within twice the contact tolerance.
    """
    from ..collision.sphere_bound import sphere_bound
    from ..collision.sphere_fit import enclosing_spheres

    pin_model = model.robot.model
    axes = []
    for joint in list(pin_model.joints)[1:]:
        name = joint.shortname()
        if name not in _AXES or joint.nq != 1:
            return None
        fixed = _AXES[name]
        axes.append(np.asarray(fixed if fixed is not None else joint.extract().axis, dtype=float))
    if pin_model.nq != model.robot.nq:
        return None
    bound = sphere_bound(model)
    if len(bound.fixed_pairs) and not (bound._fixed[bound.fixed_pairs] > PROVEN_APART).all():
        return None
    geometry = model.geometry_model.geometryObjects
    nj = pin_model.njoints
    parents = np.array(pin_model.parents, dtype=np.int32)
    qidx = np.array([-1] + [int(j.idx_q) for j in list(pin_model.joints)[1:]], dtype=np.int32)
    axis = np.vstack([np.zeros(3), np.array(axes).reshape(-1, 3)])
    axis /= np.maximum(np.linalg.norm(axis, axis=1), 1e-300)[:, None]
    place = np.array(
        [np.concatenate([p.rotation.ravel(), p.translation]) for p in pin_model.jointPlacements]
    )
    links = [float(np.linalg.norm(p.translation)) for p in pin_model.jointPlacements]
    nq = pin_model.nq

    centers: list[np.ndarray] = []
    radii: list[float] = []
    joints: list[int] = []
    spheres_of: dict[int, np.ndarray] = {}
    coarse_of: dict[int, int] = {}
    for index in range(len(geometry)):
        if model.owners[index] in model.scene_objects:
            continue
        obj = geometry[index]
        local, radius = enclosing_spheres(obj.geometry)
        local = local @ obj.placement.rotation.T + obj.placement.translation
        start = len(radii)
        centers += list(local)
        radii += list(radius)
        joints += [int(obj.parentJoint)] * len(radius)
        spheres_of[index] = np.arange(start, len(radii))
        middle = 0.5 * (local.min(axis=0) + local.max(axis=0))
        coarse_of[index] = len(radii)
        centers.append(middle)
        radii.append(float((np.linalg.norm(local - middle, axis=1) + radius).max()))
        joints.append(int(obj.parentJoint))
    sphere_center = np.array(centers, dtype=float).reshape(-1, 3)
    sphere_radius = np.array(radii, dtype=float)
    sphere_joint = np.array(joints, dtype=np.int32)
    arms = np.zeros((len(sphere_radius), nq))
    for s in range(len(sphere_radius)):
        center, k = sphere_center[s], int(sphere_joint[s])
        arm = float(np.linalg.norm(center))
        if k > 0:  # its own joint turns it about the axis: its distance from the axis
            u = axis[k]
            arms[s, qidx[k]] += float(np.linalg.norm(center - (center @ u) * u))
            arm += links[k]
            k = int(parents[k])
        while k > 0:
            arms[s, qidx[k]] += arm
            arm += links[k]
            k = int(parents[k])

    def ancestors(joint: int) -> set[int]:
        found = set()
        while joint > 0:
            found.add(joint)
            joint = int(parents[joint])
        return found

    scene_index = {
        i: k
        for k, i in enumerate(
            i for i in range(len(geometry)) if model.owners[i] in model.scene_objects
        )
    }
    shapes = [geometry[i] for i in scene_index]
    kind, rotation, middle, half, swept = _scene_arrays(shapes)
    test_a: list[int] = []
    test_b: list[int] = []
    test_k: list[int] = []
    test_arms: list[np.ndarray] = []
    test_offset: list[float] = []
    group_start = [0]
    pad = float(model.padding) + _ROUNDING
    for pair in model.geometry_model.collisionPairs:
        a, b = int(pair.first), int(pair.second)
        if geometry[a].parentJoint == 0 and geometry[b].parentJoint == 0:
            continue  # fixed: shown apart once (above)
        if a in scene_index or b in scene_index:
            arm_obj, k = (b, scene_index[a]) if a in scene_index else (a, scene_index[b])
            for s in [coarse_of[arm_obj], *spheres_of[arm_obj].tolist()]:
                test_a.append(s)
                test_b.append(-1)
                test_k.append(k)
                test_arms.append(arms[s])
                test_offset.append(sphere_radius[s] + swept[k] + pad)
        else:
            shared = ancestors(int(geometry[a].parentJoint)) & ancestors(
                int(geometry[b].parentJoint)
            )
            keep = np.ones(nq)
            for joint in shared:
                keep[qidx[joint]] = 0.0
            firsts = [coarse_of[a], *spheres_of[a].tolist()]
            seconds = [coarse_of[b], *spheres_of[b].tolist()]
            members = [(coarse_of[a], coarse_of[b])] + [
                (i, j) for i in firsts[1:] for j in seconds[1:]
            ]
            for i, j in members:
                test_a.append(i)
                test_b.append(j)
                test_k.append(-1)
                test_arms.append((arms[i] + arms[j]) * keep)
                test_offset.append(sphere_radius[i] + sphere_radius[j] + pad)
        group_start.append(len(test_a))
    arrays = {
        "parent": parents,
        "qidx": qidx,
        "axis": np.ascontiguousarray(axis, dtype=float),
        "placement": np.ascontiguousarray(place, dtype=float).reshape(nj, 12),
        "sphere_joint": sphere_joint,
        "sphere_center": np.ascontiguousarray(sphere_center),
        "test_a": np.array(test_a, dtype=np.int32),
        "test_b": np.array(test_b, dtype=np.int32),
        "test_k": np.array(test_k, dtype=np.int32),
        "test_arms": np.ascontiguousarray(np.array(test_arms).reshape(-1, nq), dtype=float),
        "test_offset": np.array(test_offset, dtype=float),
        "group_start": np.array(group_start, dtype=np.int32),
        "shape_kind": kind,
        "shape_rotation": rotation,
        "shape_center": middle,
        "shape_half": half,
    }
    return arrays


_KIND = {"Box": 0, "Sphere": 1, "Cylinder": 2, "Capsule": 3}


def _scene_arrays(shapes: list[Any]) -> tuple[np.ndarray, ...]:
    """Per scene shape: kind, rotation (world from shape), center, half sizes, swept radius."""
    import coal

    from ..collision.sphere_fit import swept_radius

    kind, rotation, middle, half, swept = [], [], [], [], []
    for obj in shapes:
        geometry = obj.geometry
        R = np.asarray(obj.placement.rotation, dtype=float)
        t = np.asarray(obj.placement.translation, dtype=float)
        offset = np.zeros(3)
        if isinstance(geometry, coal.Sphere):
            k, size = 1, [geometry.radius, 0.0, 0.0]
        elif isinstance(geometry, coal.Cylinder):
            k, size = 2, [geometry.radius, geometry.halfLength, 0.0]
        elif isinstance(geometry, coal.Capsule):
            k, size = 3, [geometry.radius, geometry.halfLength, 0.0]
        elif isinstance(geometry, coal.Box):
            k, size = 0, list(np.asarray(geometry.halfSide, dtype=float))
        else:  # any other shape through its bounding box, which encloses it
            geometry.computeLocalAABB()
            box = geometry.aabb_local
            low, high = np.asarray(box.min_, dtype=float), np.asarray(box.max_, dtype=float)
            k, size, offset = 0, list(0.5 * (high - low)), 0.5 * (high + low)
        kind.append(k)
        rotation.append(R.ravel())
        middle.append(t + R @ offset)
        half.append(size)
        swept.append(swept_radius(geometry))
    return (
        np.array(kind, dtype=np.int32),
        np.array(rotation, dtype=float).reshape(-1, 9),
        np.array(middle, dtype=float).reshape(-1, 3),
        np.array(half, dtype=float).reshape(-1, 3),
        np.array(swept, dtype=float),
    )
