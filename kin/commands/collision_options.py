"""A command's ``--scene``/``--srdf``/``--padding`` options and the collision checker they ask for."""

from __future__ import annotations

import argparse
from typing import Any

from ..cli import finite_float


def add_collision_options(
    parser: argparse.ArgumentParser, scene: str, srdf: str, self_check: bool = False
) -> None:
    """Add ``--scene FILE``, ``--srdf FILE`` and ``--padding`` (in the command's ``--unit``).

    Args:
        parser: The command's parser.
        scene: The help of ``--scene`` (what the command does with the cell).
        srdf: The help of ``--srdf``.
        self_check: The command checks the arm against itself without either file, so
            ``--padding`` stands alone (default 0); else it needs one of them
            (:func:`check_padding`).
    """
    parser.add_argument("--scene", metavar="FILE", help=scene)
    parser.add_argument("--srdf", metavar="FILE", help=srdf)
    if self_check:
        parser.add_argument(
            "--padding",
            type=finite_float,
            default=0.0,
            help="margin around every shape [--unit] (default 0): closer counts as a collision",
        )
    else:
        parser.add_argument(
            "--padding",
            type=finite_float,
            help="with --scene/--srdf: margin around every shape [--unit] (default 0)",
        )


def check_padding(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Exit 2 with one line when ``--padding`` comes without ``--scene`` or ``--srdf``."""
    if args.padding is not None and args.scene is None and args.srdf is None:
        parser.error("--padding needs --scene or --srdf")


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
