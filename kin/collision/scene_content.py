"""What a scene file holds, whatever its format: :class:`Scene`, and the rules its readers share.

The readers (:mod:`.scene`: TOML and URDF; :mod:`.planning_scene`: a MoveIt PlanningScene) make a
:class:`Scene`; :func:`mesh_file` reads a mesh a scene names, :func:`check_frames` says whether a
PlanningScene's objects are placed in the robot's base frame.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from dh2urdf.quoted_input import quoted

from ..exceptions import CollisionModelError
from .urdf_shapes import Shape, load_mesh

if TYPE_CHECKING:
    from .allowed_matrix import AllowedMatrix
    from .attached import AttachedObject

__all__ = ["Scene", "check_frames", "mesh_file"]


@dataclass(frozen=True)
class Scene:
    """What a scene file holds.

    Attributes:
        path: The file.
        objects: Its shapes, each placed in the world (the arm's base frame) [m].
        frames: Per object of a PlanningScene, ``(field, frame_id)``: the frame its pose is in.
        allowed: A PlanningScene's allowed collision matrix (None: none given).
        attached: Objects attached to the robot's links (a TOML's ``[[attached]]``).
    """

    path: str
    objects: tuple[Shape, ...]
    frames: tuple[tuple[str, str], ...] = ()
    allowed: AllowedMatrix | None = None
    attached: tuple[AttachedObject, ...] = ()

    def for_robot(
        self, base: str, known: Collection[str], links: Collection[str]
    ) -> dict[tuple[str, str], str]:
        """The pairs the scene allows (``"acm"``), once its frames are checked against ``base``.

        Args:
            base: The robot's base link, the world of the scene.
            known: Every link of the robot's URDF and every scene object name.
            links: The links that have shapes in the model.

        Raises:
            CollisionModelError: An object's frame is neither ``base`` nor ``world``, or the
                matrix names what is neither a link nor an object.
        """
        check_frames(self.path, self.frames, base)
        if self.allowed is None:
            return {}
        objects = {shape.owner for shape in self.objects}
        return self.allowed.pairs(self.path, known, links, objects)


def check_frames(where: str, frames: tuple[tuple[str, str], ...], base: str) -> None:
    """Raise unless every ``(field, frame_id)`` is ``base`` or ``world`` (a leading / aside).

    Raises:
        CollisionModelError: Names the field, the frame and the frames accepted.
    """
    for field, frame in frames:
        if frame.lstrip("/") not in (base, "world"):
            raise CollisionModelError(
                where,
                f"{field}: frame {quoted(frame)} is neither the robot's base {base!r} nor "
                f"'world'; only objects placed in the base frame are read: give their poses "
                f"in {base!r}",
            )


def mesh_file(where: str, field: str, file: Any, scale: np.ndarray) -> Any:
    """The convex hull of the mesh ``file`` (relative to the scene's folder), scaled [m/unit].

    Raises:
        CollisionModelError: ``file`` is not a file name, or the mesh cannot be read.
    """
    if not isinstance(file, str) or not file or "\0" in file:
        raise CollisionModelError(where, f"{field}: {file!r} is not a file name")
    mesh = Path(file) if Path(file).is_absolute() else Path(where).resolve().parent / file
    try:
        return load_mesh(mesh, scale)
    except OSError as err:
        raise CollisionModelError(where, f"{field}: {err}") from err
