"""A command's ``--scene``/``--srdf``/``--padding``/``--hold`` options and the checker they ask for."""

from __future__ import annotations

import argparse
from typing import Any

from ..cli import finite_float


def add_collision_options(
    parser: argparse.ArgumentParser, scene: str, srdf: str, self_check: bool = False
) -> None:
    """Add ``--scene FILE``, ``--srdf FILE``, ``--padding`` (in the command's ``--unit``), ``--hold``.

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
    parser.add_argument(
        "--hold",
        metavar="JOINT=VALUE",
        type=held_value,
        action="append",
        help="a URDF joint off the chain (a finger's) held at VALUE [rad, or m when prismatic: "
        "SI whatever --deg/--unit say]; repeatable; default: the SRDF's group state for it, "
        "else 0 (the output says which)",
    )


def held_value(text: str) -> tuple[str, float]:
    """``JOINT=VALUE`` as ``(joint, value)`` [rad or m] (argparse type of ``--hold``)."""
    name, equals, value = text.partition("=")
    if not equals or not name:
        raise argparse.ArgumentTypeError(f"{text!r} is not JOINT=VALUE (as finger_joint1=0.04)")
    return name, finite_float(value)


def held_joints(args: argparse.Namespace) -> dict[str, float]:
    """The ``--hold`` values, joint -> value [rad or m] (the last one given for a joint)."""
    return dict(getattr(args, "hold", None) or ())


def check_padding(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """Exit 2 with one line when ``--padding`` or ``--hold`` comes without ``--scene``/``--srdf``."""
    for option in ("padding", "hold"):
        if getattr(args, option) is not None and args.scene is None and args.srdf is None:
            parser.error(f"--{option} needs --scene or --srdf")


def collision_checker(args: argparse.Namespace, robot: Any, length: float) -> Any:
    """The checker of --scene/--srdf/--padding, or None when neither file is given.

    Args:
        args: Parsed options with ``scene``, ``srdf``, ``padding`` (None: 0) and ``hold``.
        robot: The robot (:class:`kin.RobotModel`).
        length: Meters per unit of ``--padding`` (the command's ``--unit``).

    Raises:
        kin.exceptions.CollisionModelError: A file cannot be read or does not fit the robot.
    """
    if args.scene is None and args.srdf is None:
        return None
    from ..collision import CollisionChecker, load_collision_model

    padding = 0.0 if args.padding is None else args.padding * length
    model = load_collision_model(
        robot, srdf=args.srdf, scene=args.scene, padding=padding, hold=held_joints(args)
    )
    return CollisionChecker(model)
