"""The collision checker a command's ``--scene``/``--srdf``/``--padding`` options ask for."""

from __future__ import annotations

import argparse
from typing import Any


def collision_checker(args: argparse.Namespace, robot: Any, length: float) -> Any:
    """The checker of --scene/--srdf/--padding, or None when neither file is given.

    Args:
        args: Parsed options with ``scene``, ``srdf`` and ``padding`` (None: 0).
        robot: The robot (:class:`kin.RobotModel`).
        length: Meters per unit of ``--padding`` (the command's ``--unit``).

    Raises:
        kin.exceptions.CollisionModelError: A file cannot be read or does not fit the robot.
    """
    if args.scene is None and args.srdf is None:
        return None
    from ..collision import CollisionChecker, load_collision_model

    padding = 0.0 if args.padding is None else args.padding * length
    model = load_collision_model(robot, srdf=args.srdf, scene=args.scene, padding=padding)
    return CollisionChecker(model)
