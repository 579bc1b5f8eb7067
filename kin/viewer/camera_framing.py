"""How far a camera stands back so that every given point is in meshcat's view.

Lengths in meters, angles in degrees, world frame with z up (meshcat's camera keeps it up).
"""

from __future__ import annotations

import numpy as np

__all__ = ["CAMERA_ASPECT", "CAMERA_FOV_DEG", "FRAMING_MARGIN", "framing_distance"]

#: meshcat's vertical field of view [deg], the page's width / height it is fitted for (800 x 600),
#: and the room left around what is drawn: robot_viewer.CAMERA_DISTANCE alone cut a UR5's raised
#: elbow off the top of the page; it stands back as far as every corner needs.
CAMERA_FOV_DEG = 75.0
CAMERA_ASPECT = 4.0 / 3.0
FRAMING_MARGIN = 1.08


def framing_distance(points: np.ndarray, direction: np.ndarray) -> float:
    """Camera distance [m] from the aim point at which ``points`` (N, 3) all lie in the view.

    The camera looks back along ``direction`` (unit, world frame) with world z up, meshcat's
    vertical field of view :data:`CAMERA_FOV_DEG` and a :data:`CAMERA_ASPECT` page; each point,
    relative to the aim point, needs ``D >= p.d + |p.up| / tan(fov_v / 2)`` and the same across
    with the horizontal field; :data:`FRAMING_MARGIN` more keeps it off the edges.
    """
    up = np.array([0.0, 0.0, 1.0]) - direction[2] * direction
    up /= np.linalg.norm(up)
    across = np.cross(direction, up)
    tan_v = np.tan(np.radians(CAMERA_FOV_DEG) / 2.0)
    needed = points @ direction + np.maximum(
        np.abs(points @ up) / tan_v, np.abs(points @ across) / (CAMERA_ASPECT * tan_v)
    )
    return FRAMING_MARGIN * float(needed.max())
