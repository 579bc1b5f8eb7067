"""The table under audit: its SI values and the units its file (and the samples) are written in."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

from dh2urdf import DHTable, get_robot, load_table
from dh2urdf.input_file import read_input
from dh2urdf.units import ANGLE_UNITS, LENGTH_UNITS


@dataclass(frozen=True)
class AuditedTable:
    """A DH table with the units of its file.

    Attributes:
        table: The table as written (SI values: meters, radians).
        length_unit: Length unit of the file (``"m"``, ``"cm"`` or ``"mm"``); sample positions
            and prismatic joint values are read in it.
        angle_unit: Angle unit of the file (``"deg"`` or ``"rad"``); sample joint angles and
            roll-pitch-yaw angles are read in it.
        path: The table file.
    """

    table: DHTable
    length_unit: str
    angle_unit: str
    path: str

    @property
    def meters(self) -> float:
        """Meters per length unit of the file."""
        return LENGTH_UNITS[self.length_unit]

    @property
    def radians(self) -> float:
        """Radians per angle unit of the file."""
        return ANGLE_UNITS[self.angle_unit]

    def length(self, value_m: float) -> str:
        """A length [m] written in the file's unit (``"28.774 cm"``)."""
        return f"{value_m / self.meters:.6g} {self.length_unit}"

    def angle(self, value_rad: float) -> str:
        """An angle [rad] written in the file's unit (``"-90 deg"``)."""
        return f"{value_rad / self.radians:.6g} {self.angle_unit}"


def load_audited_table(
    table: str | Path, base: str | None = None, tip: str | None = None
) -> AuditedTable:
    """Read a table file (or a shipped robot by name, or a URDF) with the units of its file.

    Args:
        table: Path of a ``.toml`` DH table, a shipped robot name (``"humanoid7"``), or a
            ``.urdf`` / ``.xacro`` file: the DH table of its chain from the root to the single
            tip (:func:`dh2urdf.urdf_to_dh.table_from_urdf`), in meters and radians.
        base: A URDF's base link (default: its root).
        tip: A URDF's tip link (default: the single leaf below the last moving joint).

    Raises:
        dh2urdf.UnknownRobotError: Neither a file nor a shipped robot name.
        dh2urdf.TableError: The table file is malformed.
        dh2urdf.urdf_chain.UrdfChainError: The URDF gives no serial chain.
    """
    text = str(table)
    if text.endswith((".urdf", ".xacro")):
        from dh2urdf.urdf_to_dh import table_from_urdf

        return AuditedTable(table_from_urdf(text, base, tip), "m", "rad", text)
    path = Path(text) if (text.endswith(".toml") or "/" in text) else get_robot(text).table_path
    loaded = load_table(path)  # validates, with errors naming file, row and field
    header = tomllib.loads(read_input(path).decode("utf-8-sig"))  # as load_table read it
    return AuditedTable(loaded, header["length_unit"], header["angle_unit"], str(path))
