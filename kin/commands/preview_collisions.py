"""``kin preview --scene/--srdf``: the cell, the attached objects, the verdict at the q shown.

The collision model is loaded before the scene is built (a bad scene is one line, exit 2, no
server started); its attached objects are drawn before any animation is recorded, so that they
ride on their links through it (:func:`kin.viewer.collision_view.show_attached`). Once the arm
stands at the configuration shown (the last of an animation), the links and objects in collision
there turn red and the closest pair is drawn.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from dh2urdf.output_text import shown_name

from ..cli import length_scale
from .collision_options import held_joints

if TYPE_CHECKING:
    from ..collision import CollisionModel
    from ..robot_model import RobotModel
    from ..viewer import RobotViewer

__all__ = ["load_model", "show_collisions"]


def load_model(robot: RobotModel, args: argparse.Namespace) -> CollisionModel:
    """The collision model of --scene, --srdf, --padding (in --unit) and --hold.

    Raises:
        kin.exceptions.CollisionModelError: A bad scene, SRDF, padding or hold.
    """
    from ..collision import load_collision_model

    return load_collision_model(
        robot,
        srdf=args.srdf,
        scene=args.scene,
        padding=args.padding * length_scale(args.unit),
        hold=held_joints(args),
    )


def show_collisions(viewer: RobotViewer, model: CollisionModel, args: argparse.Namespace) -> str:
    """Draw the scene, the links and objects in collision at the shown q (red), the closest pair.

    Prints the verdict and the closest pair; returns the page title that names them.
    """
    from ..collision import CollisionChecker
    from ..viewer.collision_view import (
        show_attached,
        show_closest,
        show_colliding_links,
        show_scene,
    )

    checker = CollisionChecker(model)
    contacts = checker.collisions(viewer.q)
    named = {name for c in contacts for name in (c.a, c.b)}
    show_scene(viewer, model, colliding=named & set(model.scene_objects))
    show_attached(viewer, model, colliding=named & {thing.name for thing in model.attached})
    show_colliding_links(viewer, sorted(named & set(model.links)))
    pairs = ", ".join(f"{shown_name(c.a)} / {shown_name(c.b)}" for c in contacts)
    verdict = f"IN COLLISION ({pairs})" if contacts else "collision-free"
    title = f"{shown_name(viewer.robot.name)}: {verdict}"
    print(title)
    if model.pairs:
        scale = length_scale(args.unit)
        label = show_closest(viewer, checker.distance(viewer.q), args.unit, scale)
        print(label)
        title = f"{title}; {label}"
    return title
