"""The inertial of a DH table row's link that states its ``mass``: a uniform solid primitive.

A row's ``mass`` [kg] makes its moving link a uniform solid cylinder along the link's drawn
segment (of the row's ``radius``), or a solid sphere when the segment has no length, about its
centre of mass (:mod:`dh2urdf.urdf_writer`).
"""

from __future__ import annotations

import numpy as np

from .urdf_elements import Cylinder, Inertial, Visual

__all__ = ["cylinder_inertia", "primitive_inertial"]


def cylinder_inertia(mass: float, radius: float, length: float) -> np.ndarray:
    """Inertia of a uniform solid cylinder about its center of mass, axis z [kg m^2].

    ``Ixx = Iyy = m (3 r^2 + L^2) / 12``, ``Izz = m r^2 / 2``; a solid sphere ``2/5 m r^2``.

    Args:
        mass: Mass [kg].
        radius: Cylinder (or sphere) radius [m].
        length: Cylinder length [m]; 0 gives a solid sphere of ``radius`` instead.
    """
    if length <= 0.0:
        return np.eye(3) * 0.4 * mass * radius**2
    side = mass * (3.0 * radius**2 + length**2) / 12.0
    return np.diag([side, side, 0.5 * mass * radius**2])


def primitive_inertial(mass: float, radius: float, segment: list[Visual]) -> Inertial:
    """Inertial of the link's primitive: the cylinder of ``segment``, or a sphere at the origin."""
    if not segment:
        return Inertial(origin=np.eye(4), mass=mass, inertia=cylinder_inertia(mass, radius, 0.0))
    cylinder = segment[0].geometry
    assert isinstance(cylinder, Cylinder)
    origin = np.asarray(segment[0].origin, dtype=float)
    inertia = cylinder_inertia(mass, cylinder.radius, cylinder.length)
    return Inertial(origin=origin, mass=mass, inertia=inertia)
