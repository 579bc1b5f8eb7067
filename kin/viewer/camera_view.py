"""The side a preview looks at the arm from: large in the picture and not behind a wall.

:func:`choose_view` tries cameras around the arm (every 30 degrees of azimuth, two elevations,
through a :data:`LENS_ZOOM` lens) and frames the arm tightly from each
(:func:`~kin.viewer.camera_framing.tight_framing`). It keeps the cameras that see the most of the
arm's frame origins past the scene's objects (:class:`Obstacle`), then those whose picture the
arm's projected box fills to at least :data:`MIN_FILL` (else the fullest), and takes the one
nearest the usual view (from +x, +y and above): the same arm in another posture is seen from the
same side where it can be. Lengths in meters, world frame (the arm's base), z up.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .camera_framing import tight_framing

__all__ = [
    "DEFAULT_DIRECTION",
    "LENS_ZOOM",
    "MIN_FILL",
    "CameraView",
    "Obstacle",
    "choose_view",
]

#: From the aim point towards the usual camera: in front (+x), to the left (+y), above.
DEFAULT_DIRECTION = np.array([1.0, 0.8, 0.7]) / np.linalg.norm([1.0, 0.8, 0.7])
#: Share of the picture the arm's projected box is to cover, at least, where some side allows
#: (a third is promised; the box of the points drawn is a little larger than the pixels').
MIN_FILL = 0.4
#: The camera's zoom: meshcat's 75 degree field narrowed to about 42 degrees, a camera standing
#: twice as far back, so the near links do not loom over the far ones. ``--zoom`` multiplies it.
LENS_ZOOM = 2.0
#: Elevations of the cameras tried [deg]: the usual one's and a steeper one.
_ELEVATIONS_DEG = (float(np.degrees(np.arcsin(DEFAULT_DIRECTION[2]))), 50.0)
_AZIMUTH_STEP_DEG = 30.0
#: A sight line ends this share short of its point, so a base standing on a table is not hidden.
_SIGHT_SHORTENING = 0.97


@dataclass(frozen=True)
class CameraView:
    """Where meshcat's camera stands and what it looks at.

    Attributes:
        target: The point looked at (the mouse orbits it), world frame [m], shape (3,).
        position: The camera, world frame [m], shape (3,).
        zoom: Magnification of three.js's camera (2: things look twice as large), > 0.
    """

    target: np.ndarray
    position: np.ndarray
    zoom: float = 1.0


@dataclass(frozen=True)
class Obstacle:
    """A box that can stand between the camera and the arm (a scene object's bounding box).

    Attributes:
        T_world_box: The box frame's placement, (4, 4) [m].
        low: Lowest corner in the box frame [m], shape (3,).
        high: Highest corner in the box frame [m], shape (3,).
    """

    T_world_box: np.ndarray
    low: np.ndarray
    high: np.ndarray

    def hides(self, eye: np.ndarray, points: np.ndarray) -> np.ndarray:
        """Per point of ``points`` (N, 3): does the segment from ``eye`` (3,) to it cross the box?

        Segments are clipped to the box's slabs along each of its axes (world frame [m]).
        """
        rotation, origin = self.T_world_box[:3, :3], self.T_world_box[:3, 3]
        start = rotation.T @ (eye - origin)
        step = (points - origin) @ rotation - start  # (N, 3), in the box frame
        with np.errstate(divide="ignore", invalid="ignore"):
            t_low = (self.low - start) / step
            t_high = (self.high - start) / step
        parallel = np.abs(step) < 1e-12
        inside = (self.low <= start) & (start <= self.high)  # per axis, for parallel segments
        t_in = np.where(parallel, np.where(inside, -np.inf, np.inf), np.minimum(t_low, t_high))
        t_out = np.where(parallel, np.where(inside, np.inf, -np.inf), np.maximum(t_low, t_high))
        enter, leave = t_in.max(axis=1), t_out.min(axis=1)
        return (enter <= leave) & (leave >= 0.0) & (enter <= 1.0)


def choose_view(
    points: np.ndarray,
    sights: np.ndarray,
    obstacles: Sequence[Obstacle] = (),
    min_distance: float = 0.05,
) -> CameraView:
    """The camera that frames ``points`` best (see the module docstring for the rule).

    Args:
        points: Points to keep in the picture (the arm's shapes, a target, a path), (N, 3) [m].
        sights: Points of the arm that should not be hidden (its frame origins), (M, 3) [m].
        obstacles: Boxes of the scene that can hide them.
        min_distance: The camera stands at least this far from the point it looks at [m].

    Returns:
        The view, its zoom :data:`LENS_ZOOM`.
    """
    azimuth0 = float(np.arctan2(DEFAULT_DIRECTION[1], DEFAULT_DIRECTION[0]))
    step = np.radians(_AZIMUTH_STEP_DEG)
    turns = sorted(range(-5, 7), key=lambda k: (abs(k), -k))  # 0, 1, -1, 2, -2, ..., 6
    candidates = []  # nearest the usual view first
    for turn in turns:
        for elevation in np.radians(_ELEVATIONS_DEG):
            azimuth = azimuth0 + turn * step
            direction = np.array(
                [
                    np.cos(elevation) * np.cos(azimuth),
                    np.cos(elevation) * np.sin(azimuth),
                    np.sin(elevation),
                ]
            )
            aim, distance, fill = tight_framing(points, direction, min_distance, LENS_ZOOM)
            eye = aim + distance * direction
            candidates.append((_seen_share(eye, sights, obstacles), fill, aim, eye))
    most_seen = max(c[0] for c in candidates)
    visible = [c for c in candidates if c[0] >= most_seen - 1e-9]
    filled = [c for c in visible if c[1] >= MIN_FILL] or [max(visible, key=lambda c: c[1])]
    _, _, aim, eye = filled[0]
    return CameraView(target=aim, position=eye, zoom=LENS_ZOOM)


def _seen_share(eye: np.ndarray, sights: np.ndarray, obstacles: Sequence[Obstacle]) -> float:
    """Share of ``sights`` that no obstacle hides from ``eye`` (1 without sights or obstacles)."""
    if len(sights) == 0 or not obstacles:
        return 1.0
    ends = eye + _SIGHT_SHORTENING * (sights - eye)
    hidden = np.zeros(len(sights), dtype=bool)
    for obstacle in obstacles:
        hidden |= obstacle.hides(eye, ends)
    return 1.0 - float(hidden.mean())
