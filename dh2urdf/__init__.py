"""From a Denavit-Hartenberg table to a validated URDF (meters, radians)."""

from .dh_table import DHRow, DHTable, dh_link_transform
from .exceptions import Dh2UrdfError, TableError, UnknownRobotError, UrdfBuildError
from .robots import ROBOTS, RobotDescription, get_robot, robot_names
from .table_file import load_table, parse_table
from .urdf_writer import build_urdf, urdf_string, write_urdf

__version__ = "0.1.0"

__all__ = [
    "DHRow",
    "DHTable",
    "Dh2UrdfError",
    "ROBOTS",
    "RobotDescription",
    "TableError",
    "UnknownRobotError",
    "UrdfBuildError",
    "build_urdf",
    "dh_link_transform",
    "get_robot",
    "load_table",
    "parse_table",
    "robot_names",
    "urdf_string",
    "write_urdf",
]
