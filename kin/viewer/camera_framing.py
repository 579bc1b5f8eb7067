"""Where a camera stands so that given points fill meshcat's view: aim, distance, filled share.

Lengths in meters, angles in degrees, world frame with z up (meshcat's camera keeps it up). The
camera looks from ``aim + distance * direction`` back at ``aim`` through a pinhole with meshcat's
vertical field of view narrowed by a zoom (three.js: ``tan(fov / 2) / zoom``) on a page of
:data:`CAMERA_ASPECT`.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "CAMERA_ASPECT",
    "CAMERA_FOV_DEG",
    "FRAMING_MARGIN",
    "tight_framing",
    "view_box",
]

#: meshcat's vertical field of view [deg], the page's width / height it is fitted for (800 x 600),
#: and the room left around what is drawn (the points' extremes stay 1 / 1.08 inside the edges).
CAMERA_FOV_DEG = 75.0
CAMERA_ASPECT = 4.0 / 3.0
FRAMING_MARGIN = 1.08


def _tan_half_fov(zoom: float) -> float:
    """The tangent of half the vertical field of view of meshcat's camera at ``zoom``."""
    return float(np.tan(np.radians(CAMERA_FOV_DEG) / 2.0)) / zoom


def _screen_axes(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The picture's up and across (to the right) unit vectors for a camera along ``direction``."""
    up = np.array([0.0, 0.0, 1.0]) - direction[2] * direction
    up /= np.linalg.norm(up)
    return up, np.cross(direction, up)


def view_box(
    points: np.ndarray, aim: np.ndarray, direction: np.ndarray, distance: float, zoom: float = 1.0
) -> tuple[float, float, float, float]:
    """Where ``points`` (N, 3) [m] fall in the picture: (left, right, bottom, top) in [-1, 1].

    -1 and 1 are the picture's edges (normalized device coordinates of the pinhole camera at
    ``aim + distance * direction`` at ``zoom``); a point behind the camera counts as beyond every edge.
    """
    up, across = _screen_axes(direction)
    tan_v = _tan_half_fov(zoom)
    relative = points - aim
    depth = distance - relative @ direction
    if np.any(depth <= 0.0):
        return -np.inf, np.inf, -np.inf, np.inf
    x = relative @ across / (depth * CAMERA_ASPECT * tan_v)
    y = relative @ up / (depth * tan_v)
    return float(x.min()), float(x.max()), float(y.min()), float(y.max())


def tight_framing(
    points: np.ndarray, direction: np.ndarray, min_distance: float = 0.05, zoom: float = 1.0
) -> tuple[np.ndarray, float, float]:
    """Aim point [m], distance [m] and filled share of the picture for ``points`` seen along ``direction``.

    In the camera's axes (across, up, and ``direction`` towards the camera) a point ``(a, u, w)``
    is inside the horizontal field, with the margin, when ``|a - x0| <= t (w0 - w)`` for a camera
    at ``(x0, y0, w0)`` and ``t = aspect tan(fov / 2) / zoom / margin``: the nearest camera has
    ``w0 + x0 / t = max(w + a / t)`` and ``w0 - x0 / t = max(w - a / t)``, and the same for the
    vertical field gives ``y0``; the camera stands as far back as the stricter of the two needs
    (and ``min_distance`` from the points' middle depth, which it aims at). The share is the
    projected box's area over the picture's, at most ``1 / FRAMING_MARGIN**2``.

    Args:
        points: Points to keep in view, (N, 3), world frame [m].
        direction: Unit vector from the aim point towards the camera (not vertical).
        min_distance: The camera stands at least this far from the aim point [m] (one point).
        zoom: The camera's zoom (a narrower field: the camera stands farther back).
    """
    up, across = _screen_axes(direction)
    a, u, w = points @ across, points @ up, points @ direction
    tan_v = _tan_half_fov(zoom) / FRAMING_MARGIN
    placed = []
    for side, tan in ((a, CAMERA_ASPECT * tan_v), (u, tan_v)):
        high, low = float(np.max(w + side / tan)), float(np.max(w - side / tan))
        placed.append((0.5 * (high + low), 0.5 * tan * (high - low)))  # (w0, lateral)
    middle = 0.5 * (float(w.min()) + float(w.max()))
    w0 = max(placed[0][0], placed[1][0], middle + min_distance)
    aim = placed[0][1] * across + placed[1][1] * up + middle * direction
    distance = w0 - middle
    left, right, bottom, top = view_box(points, aim, direction, distance, zoom)
    return aim, distance, 0.25 * (right - left) * (top - bottom)
