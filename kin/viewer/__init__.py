"""Browser preview of a robot through meshcat: arm, frame triads, targets, paths, point clouds.

Needs ``meshcat`` (a dependency of the package); ``import kin`` never loads it. ``RobotViewer(robot)`` records a scene for a static HTML page (``write_page``);
``RobotViewer(robot, serve=True)`` drives a live meshcat server instead.
"""

from __future__ import annotations

try:
    import meshcat  # noqa: F401
except ModuleNotFoundError as err:  # the optional dependency, with the way to get it
    raise ModuleNotFoundError(
        f"kin.viewer needs meshcat ({err}); install it: pip install meshcat", name="meshcat"
    ) from err

from .exceptions import PageWriteError, ViewerError, ViewerInputError
from .markers import draw_points, draw_sphere, draw_triad
from .page_file import write_page
from .robot_viewer import RobotViewer
from .scene_recorder import SceneRecorder

__all__ = [
    "PageWriteError",
    "RobotViewer",
    "SceneRecorder",
    "ViewerError",
    "ViewerInputError",
    "draw_points",
    "draw_sphere",
    "draw_triad",
    "write_page",
]
