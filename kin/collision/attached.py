"""Objects attached to the robot: a held part, a tool, a tool changer, moving with a link.

An :class:`AttachedObject` hangs on one link of the robot (``link``) at a fixed placement in that
link's frame, so it moves with the arm. The collision model checks it against every scene object
and every link of the robot but its own link, the ``touch_links`` it may touch, and the links that
ride on the same joint as its link (they never move against it: reason ``rigid``). Two attached
objects on different joints are checked against each other too.

Made by a scene file's ``[[attached]]`` entries (:mod:`.scene`, ``docs/scenes.md``), by
:func:`attached_object`, or given whole; :meth:`kin.collision.CollisionModel.attach` and
:meth:`~kin.collision.CollisionModel.detach` give a new model with or without one.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from dh2urdf.quoted_input import quoted

from ..exceptions import CollisionModelError
from .scene_values import coordinate, factor, length, number, vector
from .urdf_shapes import Shape, load_mesh

__all__ = ["AttachedObject", "attached_object"]


@dataclass(frozen=True)
class AttachedObject:
    """One object attached to a link.

    Attributes:
        name: Its name (unique among links, scene objects and attached objects).
        link: The robot's link it hangs on (any link of the URDF, with or without shapes).
        shapes: Its shapes, each ``placement`` = ``T_link_shape`` [m]; each ``owner`` is ``name``.
        touch_links: Links it may touch: pairs with them are not checked (reason ``touch``).
    """

    name: str
    link: str
    shapes: tuple[Shape, ...]
    touch_links: tuple[str, ...] = ()


def attached_object(
    name: str,
    link: str,
    *,
    box: npt.ArrayLike | None = None,
    sphere: float | None = None,
    cylinder: tuple[float, float] | None = None,
    mesh: str | Path | None = None,
    scale: float = 1.0,
    xyz: npt.ArrayLike = (0.0, 0.0, 0.0),
    rpy: npt.ArrayLike = (0.0, 0.0, 0.0),
    touch_links: Iterable[str] = (),
) -> AttachedObject:
    """An object of one shape on ``link``, placed at ``xyz`` [m], ``rpy`` [rad] in its frame.

    Args:
        name: The object's name.
        link: The link it hangs on.
        box: Full sides ``(x, y, z)`` [m].
        sphere: Radius [m].
        cylinder: ``(radius, length)`` [m], along the shape's z axis, centred.
        mesh: A mesh file (STL, DAE, OBJ), checked as its convex hull.
        scale: Meters per mesh file unit.
        xyz: The shape's centre in the link's frame [m].
        rpy: URDF roll-pitch-yaw of the shape in the link's frame [rad].
        touch_links: Links it may touch.

    Raises:
        CollisionModelError: Not exactly one shape, a size or place out of bounds, a bad name.
    """
    given = {
        k: v
        for k, v in {"box": box, "sphere": sphere, "cylinder": cylinder, "mesh": mesh}.items()
        if v is not None
    }
    field = f"attached {quoted(name)}"
    if len(given) != 1:
        raise CollisionModelError(
            "", f"{field}: give one shape of box, sphere, cylinder, mesh (got {sorted(given)})"
        )
    kind, value = next(iter(given.items()))
    import coal

    geometry: coal.CollisionGeometry
    if kind == "box":
        geometry = coal.Box(*vector("", f"{field}.box", _listed(value), length).tolist())
    elif kind == "sphere":
        geometry = coal.Sphere(length("", f"{field}.sphere", value))
    elif kind == "cylinder":
        radius, height = vector("", f"{field}.cylinder", _listed(value), length, size=2)
        geometry = coal.Cylinder(radius, height)
    else:
        try:
            geometry = load_mesh(Path(str(value)), np.full(3, factor("", f"{field}.scale", scale)))
        except OSError as err:
            raise CollisionModelError("", f"{field}.mesh: {err}") from err
    place = vector("", f"{field}.xyz", _listed(xyz), coordinate)
    angles = vector("", f"{field}.rpy", _listed(rpy), number)
    shape = Shape(name, name, geometry, pin.SE3(pin.rpy.rpyToMatrix(*angles), place), kind)
    return checked(AttachedObject(name, link, (shape,), tuple(touch_links)), "")


def _listed(value: Any) -> list[Any]:
    """The numbers of a sequence or array as a list (anything else as it is, to be refused)."""
    return (
        np.asarray(value).ravel().tolist()
        if isinstance(value, (list, tuple, np.ndarray))
        else value
    )


def checked(thing: AttachedObject, where: str) -> AttachedObject:
    """``thing`` when its name, link and touch links are strings, else one error line."""
    for field, value in [("name", thing.name), ("link", thing.link), *_touch(thing)]:
        if not isinstance(value, str) or not value:
            raise CollisionModelError(
                where, f"attached {quoted(thing.name)}.{field}: {quoted(value)} is not a name"
            )
    return thing


def _touch(thing: AttachedObject) -> list[tuple[str, object]]:
    return [(f"touch_links[{i}]", link) for i, link in enumerate(thing.touch_links)]


def check_names(
    things: tuple[AttachedObject, ...], links: Iterable[str], objects: Iterable[str], where: str
) -> None:
    """Raise unless every object hangs on a robot link, touches links only, and has its own name.

    Raises:
        CollisionModelError: Names the object, the field and (for a link) some choices.
    """
    links = tuple(links)
    taken = set(links) | set(objects)
    for thing in things:
        field = f"attached {quoted(thing.name)}"
        if thing.name in taken:
            raise CollisionModelError(
                where, f"{field}: the name is taken by a link, a scene object or another object"
            )
        taken.add(thing.name)
        for name, link in [("link", thing.link), *_touch(thing)]:
            if link not in links:
                shown = ", ".join(links[:12]) + (", ..." if len(links) > 12 else "")
                raise CollisionModelError(
                    where, f"{field}.{name}: the robot has no link {quoted(link)}; links: {shown}"
                )
