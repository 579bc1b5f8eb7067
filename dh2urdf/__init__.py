"""From a Denavit-Hartenberg table to a validated URDF (meters, radians).

The URDF writer (``urdf_string``, ``write_urdf``) writes text with NumPy and string formatting;
only ``build_urdf`` (the same URDF as a yourdfpy model) imports yourdfpy and trimesh, which are slow
to import, and the MJCF writer (``mjcf_string``, ``write_mjcf``) imports MuJoCo; they are loaded on
first use so that reading tables, building a model from one and ``import kin`` stay fast.
"""

from typing import Any

from .dh_table import DHRow, DHTable, dh_link_transform
from .exceptions import Dh2UrdfError, TableError, UnknownRobotError, UrdfBuildError
from .robots import ROBOTS, RobotDescription, get_robot, robot_names
from .table_file import load_table, parse_table

__version__ = "0.3.0"

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
    "mjcf_string",
    "parse_table",
    "robot_names",
    "urdf_string",
    "write_mjcf",
    "write_urdf",
]


_LAZY = {"urdf_string", "write_urdf"}
_LAZY_MJCF = {"mjcf_string", "write_mjcf"}


def __getattr__(name: str) -> Any:
    if name == "build_urdf":
        from .yourdfpy_model import build_urdf

        return build_urdf
    if name in _LAZY:
        from . import urdf_writer

        return getattr(urdf_writer, name)
    if name in _LAZY_MJCF:
        from . import mjcf_writer

        return getattr(mjcf_writer, name)
    raise AttributeError(f"module 'dh2urdf' has no attribute {name!r}")
