"""The pairs a verdict-only check tests, and their order: the likeliest contact first.

A verdict (``CollisionChecker.in_collision``) stops at the first pair in contact, so the order of
the pairs decides its cost, not its answer. On a model of primitives only (a DH table's link
cylinders and a scene: no broad phase, see :class:`~kin.collision.checker.CollisionChecker`) the
checker tests the pairs of a geometry model of its own, built here from the model's:

- a pair whose two shapes hang on the world (the base link against a scene object) is the same at
  every configuration: it is tested once, here. A free one is left out; one in contact comes
  first (then every verdict is True, as it would be anyway);
- the others by how often they were in contact over :data:`SAMPLES` configurations drawn as
  :func:`~kin.collision.always_pairs.sample_configurations` draws them, most often first (ties
  in the model's order).

The verdict is that of every pair tested: any pair in contact makes it True, and each pair's test
does not depend on what ran before (GJK starts from its default guess: :mod:`.requests`). On
humanoid7 in tests/data/collision/cell.toml, where two thirds of random configurations collide
(most with the upper arm on the table), a verdict tests 6.0 pairs on average instead of 8.9.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .always_pairs import sample_configurations
from .requests import prepare_requests

__all__ = ["SAMPLES", "verdict_geometry_model"]

#: Configurations sampled to count each pair's contacts [count] (a few ms on a DH arm).
SAMPLES = 256


def verdict_geometry_model(
    model: pin.Model, geometry_model: pin.GeometryModel, padding: float
) -> pin.GeometryModel:
    """A copy of ``geometry_model`` whose collision pairs are those a verdict tests, in order.

    Args:
        model: The arm's Pinocchio model (it places the shapes).
        geometry_model: The collision model's shapes and pairs.
        padding: Distance below which two shapes are in contact [m].

    Returns:
        The same shapes; the pairs as the module says.
    """
    data = model.createData()
    geometry_data = pin.GeometryData(geometry_model)
    prepare_requests(geometry_data, padding)
    objects = geometry_model.geometryObjects
    pairs = list(geometry_model.collisionPairs)
    fixed = [
        objects[p.first].parentJoint == 0 and objects[p.second].parentJoint == 0 for p in pairs
    ]
    pin.updateGeometryPlacements(model, data, geometry_model, geometry_data, pin.neutral(model))
    first = [k for k, f in enumerate(fixed) if f and _contact(geometry_model, geometry_data, k)]
    moving = [k for k, f in enumerate(fixed) if not f]
    contacts = np.zeros(len(pairs))
    if moving and not first:  # with a world pair in contact, every verdict stops at it
        for q in sample_configurations(model, SAMPLES):
            pin.updateGeometryPlacements(model, data, geometry_model, geometry_data, q)
            for k in moving:
                contacts[k] += _contact(geometry_model, geometry_data, k)
    order = first + sorted(moving, key=lambda k: -contacts[k])  # stable: ties keep the model's
    verdict = pin.GeometryModel(geometry_model)
    verdict.removeAllCollisionPairs()
    for k in order:
        verdict.addCollisionPair(pairs[k])
    return verdict


def _contact(geometry_model: pin.GeometryModel, geometry_data: pin.GeometryData, k: int) -> bool:
    return bool(pin.computeCollision(geometry_model, geometry_data, k))
