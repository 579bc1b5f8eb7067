"""A scene file's units (``length_unit``, ``angle_unit``) and its unit slips, as DH tables have.

The units and their factors are the tables' (:mod:`dh2urdf.units`): lengths ``m`` (default),
``cm``, ``mm``; angles ``rad`` (default), ``deg``. The slip rules are the tables' too
(:mod:`dh2urdf.table_file`), each one :class:`~dh2urdf.exceptions.UnitWarning` line naming the
file and the first field at fault, the value used as given:

- an ``rpy`` angle beyond a turn (:data:`~dh2urdf.table_units.RADIAN_SUSPECT`) in a radian scene:
  degrees read as radians;
- a coordinate farther than :data:`~dh2urdf.table_units.LENGTH_SUSPECT` (20 m, where a table's
  arm laid end to end is "not in meters") from the arm's base: millimetres read as meters.

Beyond the bounds of :mod:`.bounds` (a shape over 10 m, a coordinate beyond 1 km) the value is
an error, and its line carries the same hint (:attr:`UnitSlips.hint`).
"""

from __future__ import annotations

import warnings
from typing import Any

from dh2urdf.exceptions import UnitWarning
from dh2urdf.quoted_input import quoted
from dh2urdf.table_units import LENGTH_SUSPECT, RADIAN_SUSPECT
from dh2urdf.units import ANGLE_UNITS, LENGTH_UNITS

from ..exceptions import CollisionModelError

__all__ = ["UNIT_KEYS", "UnitSlips", "read_unit"]

#: The top-level keys of a scene TOML that name its units, and their defaults.
UNIT_KEYS: dict[str, str] = {"angle_unit": "rad", "length_unit": "m"}

#: The hint of a PlanningScene, whose lengths are meters by definition (ROS REP 103).
ROS_METERS = "are the lengths in millimeters? a PlanningScene is in meters: divide them by 1000"


def read_unit(where: str, document: dict[str, Any], key: str) -> str:
    """The unit the scene's ``key`` (``length_unit`` or ``angle_unit``) names, or its default.

    Raises:
        CollisionModelError: The value is not one of the units (:mod:`dh2urdf.units`).
    """
    choices = LENGTH_UNITS if key == "length_unit" else ANGLE_UNITS
    unit = document.get(key, UNIT_KEYS[key])
    if not isinstance(unit, str) or unit not in choices:
        raise CollisionModelError(
            where, f"{key}: {quoted(unit)} is not a unit; choose one of: {', '.join(choices)}"
        )
    return unit


class UnitSlips:
    """The first suspicious angle and the first far coordinate of one scene file, warned once.

    Args:
        where: The scene file.
        angle_unit: The unit its angles are written in (``"rad"``, ``"deg"``); quaternions
            (a PlanningScene) have none: ``""``.
        hint: What to do when lengths look like millimetres (ends the warning and the errors).
    """

    def __init__(self, where: str, angle_unit: str, hint: str):
        self.where = where
        self.angle_unit = angle_unit
        self.hint = hint
        self._angle: tuple[str, float] | None = None
        self._far: tuple[str, float] | None = None

    @classmethod
    def of_toml(cls, where: str, angle_unit: str, length_unit: str) -> UnitSlips:
        """The slips of a scene TOML: its hint names ``length_unit`` as a table's warning does."""
        unit = 'write length_unit = "mm"' if length_unit == "m" else "check length_unit"
        return cls(where, angle_unit, f"are the lengths in millimeters? then {unit}")

    def angle(self, field: str, written: float) -> None:
        """Note an angle as the file writes it (in its ``angle_unit``)."""
        if self._angle is None and self.angle_unit == "rad" and abs(written) > RADIAN_SUSPECT:
            self._angle = (field, written)

    def place(self, field: str, meters: float) -> None:
        """Note a coordinate of a shape's placement [m]."""
        if self._far is None and abs(meters) > LENGTH_SUSPECT:
            self._far = (field, meters)

    def warn(self) -> None:
        """One :class:`UnitWarning` per kind of slip noted (none when the file looks right)."""
        if self._angle is not None:
            field, value = self._angle
            warnings.warn(
                f"{self.where}, field '{field}': {value:g} rad is more than a turn: are the "
                'angles in degrees? then write angle_unit = "deg"',
                UnitWarning,
                stacklevel=3,
            )
        if self._far is not None:
            field, value = self._far
            warnings.warn(
                f"{self.where}, field '{field}': {value:g} m from the arm's base (more than "
                f"{LENGTH_SUSPECT:g} m): {self.hint}",
                UnitWarning,
                stacklevel=3,
            )
