"""The robot of a command: ``--robot NAME|TABLE.toml|ARM.urdf [--base LINK] [--tip LINK]``.

Every command that takes a robot adds these options with :func:`add_robot_arguments` and loads
it with :func:`load_robot_argument`: a shipped robot's name, a DH table file, or a URDF whose
chain from ``--base`` (default: its root link) to ``--tip`` (default: the single leaf below its
last joint) is read as a DH table (:func:`dh2urdf.urdf_to_dh.table_from_urdf`).
"""

from __future__ import annotations

import argparse

from ..robot_model import RobotModel

#: The help of ``--robot``.
ROBOT_HELP = (
    "shipped robot name, a DH table file (.toml) or a URDF (.urdf, or any file whose root element "
    "is <robot>; .xacro with xacrodoc)"
)


def add_robot_arguments(parser: argparse.ArgumentParser, required: bool = True) -> None:
    """Add ``--robot`` (required unless ``required`` is False), ``--base`` and ``--tip``."""
    parser.add_argument("--robot", required=required, help=ROBOT_HELP)
    parser.add_argument(
        "--base", metavar="LINK", help="base link of a URDF's chain (default: its root link)"
    )
    parser.add_argument(
        "--tip",
        metavar="LINK",
        help="tip link of a URDF's chain (default: the single leaf below its last joint)",
    )


def load_robot_argument(args: argparse.Namespace) -> RobotModel:
    """The robot the options name (see :func:`kin.load_robot` for the errors it raises)."""
    from ..robot_model import load_robot

    return load_robot(args.robot, getattr(args, "base", None), getattr(args, "tip", None))
