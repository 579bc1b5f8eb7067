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
    "framing_distance",
    "tight_framing",
    "view_box",
]

#: meshcat's vertical field of view [deg], the page's width / height it is fitted for (800 x 600),
#: and the room left around what is drawn (the points' extremes stay 1 / 1.08 inside the edges).
CAMERA_FOV_DEG = 75.0
CAMERA_ASPECT = 4.0 / 3.0
FRAMING_MARGIN = 1.08
#: Rounds of re-aiming at the centre of the projected box (each halves the offset or better).
_CENTRING_ROUNDS = 6


def _tan_half_fov(zoom: float) -> float:
    """tan of half the vertical field of view of meshcat's camera at ``zoom``."""
    return float(np.tan(np.radians(CAMERA_FOV_DEG) / 2.0)) / zoom


def _screen_axes(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The picture's up and across (to the right) unit vectors for a camera along ``direction``."""
    up = np.array([0.0, 0.0, 1.0]) - direction[2] * direction
    up /= np.linalg.norm(up)
    return up, np.cross(direction, up)


def framing_distance(points: np.ndarray, direction: np.ndarray, zoom: float = 1.0) -> float:
    """Camera distance [m] from the aim point at which ``points`` (N, 3) all lie in the view.

    The camera looks back along ``direction`` (unit, world frame, not vertical) with world z up,
    meshcat's vertical field of view :data:`CAMERA_FOV_DEG` at ``zoom``, a :data:`CAMERA_ASPECT` page;
    each point, relative to the aim point, needs ``D >= p.d + |p.up| / tan(fov_v / 2)`` and the
    same across with the horizontal field; :data:`FRAMING_MARGIN` more keeps it off the edges.
    """
    up, across = _screen_axes(direction)
    tan_v = _tan_half_fov(zoom)
    needed = points @ direction + np.maximum(
        np.abs(points @ up) / tan_v, np.abs(points @ across) / (CAMERA_ASPECT * tan_v)
    )
    return FRAMING_MARGIN * float(needed.max())


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

    The aim starts at the centre of the points' box and moves, a few rounds, to where the
    projected box is centred in the picture; the distance then fits every point
    (:func:`framing_distance`). The share is the projected box's area over the picture's, in
    [0, 1 / FRAMING_MARGIN**2].

    Args:
        points: Points to keep in view, (N, 3), world frame [m].
        direction: Unit vector from the aim point towards the camera (not vertical).
        min_distance: The camera stands at least this far from the aim point [m] (one point).
        zoom: The camera's zoom (a narrower field: the camera stands farther back).
    """
    up, across = _screen_axes(direction)
    tan_v = _tan_half_fov(zoom)
    aim = 0.5 * (points.min(axis=0) + points.max(axis=0))
    distance = max(framing_distance(points - aim, direction, zoom), min_distance)
    for _ in range(_CENTRING_ROUNDS):
        left, right, bottom, top = view_box(points, aim, direction, distance, zoom)
        shift_x, shift_y = 0.5 * (left + right), 0.5 * (bottom + top)
        aim = aim + distance * tan_v * (CAMERA_ASPECT * shift_x * across + shift_y * up)
        distance = max(framing_distance(points - aim, direction, zoom), min_distance)
    left, right, bottom, top = view_box(points, aim, direction, distance, zoom)
    return aim, distance, 0.25 * (right - left) * (top - bottom)
