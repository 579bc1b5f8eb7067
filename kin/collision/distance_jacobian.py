"""Distances of a collision model's checked pairs and their Jacobians, for the distance bound.

A pair's distance ``d`` is coal's signed distance between its two shapes (negative when they
overlap) less the model's padding [m]. Its rate is ``n^T (v_b - v_a)``: ``n`` the unit normal from
shape a to shape b (coal's), ``v_a`` and ``v_b`` the world-frame velocities of the two witness
points, each the velocity of the shape's joint moved to the point (``v_joint + w x arm``). A scene
object hangs on the world (joint 0) and does not move. The tests compare these rows with central
differences of coal's distances.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

__all__ = ["pair_rows"]

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def pair_rows(
    model: pin.Model,
    data: pin.Data,
    geometry_model: pin.GeometryModel,
    geometry_data: pin.GeometryData,
    padding: float,
    influence: float,
) -> tuple[np.ndarray, np.ndarray, float]:
    """Distances and distance Jacobians of the pairs closer than ``influence`` [m].

    Reads the placements, the joint Jacobians and the distances already in ``data`` and
    ``geometry_data`` (``pin.computeJointJacobians``, ``pin.updateGeometryPlacements``,
    ``pin.computeDistances``).

    Returns:
        ``(d, J_d, smallest)``: the close pairs' distances [m] (k,), the rows ``d d / d q``
        (k, nq) [m / rad], and the smallest distance of any pair [m] (inf without pairs).
    """
    results = geometry_data.distanceResults
    every = [result.min_distance - padding for result in results]
    close = [i for i, d in enumerate(every) if d < influence]
    rows = np.zeros((len(close), model.nv))
    objects, pairs = geometry_model.geometryObjects, geometry_model.collisionPairs
    jacobians: dict[int, np.ndarray] = {}
    for k, i in enumerate(close):
        result, pair = results[i], pairs[i]
        nx, ny, nz = result.normal.tolist()  # unit, from the first shape to the second
        for index, point, sign in (
            (pair.first, result.getNearestPoint1(), -1.0),
            (pair.second, result.getNearestPoint2(), 1.0),
        ):
            joint = objects[index].parentJoint
            if joint == 0:  # a scene object: it does not move
                continue
            jacobian = jacobians.get(joint)
            if jacobian is None:
                jacobian = jacobians[joint] = pin.getJointJacobian(model, data, joint, _LWA)
            ax, ay, az = (point - data.oMi[joint].translation).tolist()
            # n . (v_joint + w x arm) = n . v_joint + (arm x n) . w
            wrench = (nx, ny, nz, ay * nz - az * ny, az * nx - ax * nz, ax * ny - ay * nx)
            rows[k] += sign * (np.array(wrench) @ jacobian)
    distances = np.array([every[i] for i in close])
    return distances, rows, min(every, default=math.inf)
