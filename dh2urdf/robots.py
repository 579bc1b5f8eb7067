"""Registry of the robots shipped with the project: name -> frozen description."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .dh_table import DHTable
from .exceptions import UnknownRobotError
from .table_file import load_table

#: Folder of the shipped DH tables.
TABLES_DIR = Path(__file__).resolve().parent / "tables"
#: Folder of the generated URDFs shipped with the package. In the repository ``dh2urdf/urdf`` is a
#: link to the committed, diffable copy at the top (``urdf/``); the wheel holds the files.
URDF_DIR = Path(__file__).parent / "urdf"


@dataclass(frozen=True)
class RobotDescription:
    """A shipped robot.

    Attributes:
        name: Registry name (also the table and URDF file stem).
        tags: Short labels (``"paper"`` for the seed papers' arms, ``"industrial"`` for real arms).
        tool_frame: Name of the tool frame in the URDF.
    """

    name: str
    tags: tuple[str, ...]
    tool_frame: str = "tool"

    @property
    def table_path(self) -> Path:
        """Path of the DH table file."""
        return TABLES_DIR / f"{self.name}.toml"

    @property
    def urdf_path(self) -> Path:
        """Path of the generated URDF file."""
        return URDF_DIR / f"{self.name}.urdf"

    def load_table(self) -> DHTable:
        """Read the robot's DH table."""
        return load_table(self.table_path)


#: The robots, sorted by name.
ROBOTS: dict[str, RobotDescription] = {
    "humanoid7": RobotDescription("humanoid7", ("paper", "redundant")),
    "lab5": RobotDescription("lab5", ("paper",)),
    "ned5": RobotDescription("ned5", ("paper",)),
    "panda": RobotDescription("panda", ("industrial", "redundant")),
    "pickplace3": RobotDescription("pickplace3", ("paper",)),
    "planar2": RobotDescription("planar2", ("paper", "planar")),
    "puma560": RobotDescription("puma560", ("industrial",)),
    "scorbot": RobotDescription("scorbot", ("paper",)),
    "ur10": RobotDescription("ur10", ("industrial",)),
    "ur3": RobotDescription("ur3", ("industrial",)),
    "ur5": RobotDescription("ur5", ("industrial",)),
    "xarm7": RobotDescription("xarm7", ("industrial", "redundant")),
}


def robot_names() -> tuple[str, ...]:
    """Sorted names of the shipped robots."""
    return tuple(sorted(ROBOTS))


def get_robot(name: str) -> RobotDescription:
    """Description of a shipped robot.

    Raises:
        UnknownRobotError: ``name`` is not in the registry; the message lists the known names.
    """
    try:
        return ROBOTS[name]
    except KeyError:
        raise UnknownRobotError(name, robot_names()) from None
