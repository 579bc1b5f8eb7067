"""The optional ``[drives]`` section of a table file: a stepper drive per joint.

Format (lengths and angles in the table's ``length_unit`` / ``angle_unit``)::

    [drives.shoulder]              # a joint name, or its 1-based row index as a string: "2"
    steps_per_revolution = 200     # full steps of the motor per motor revolution
    microstepping = 8              # driver microsteps per full step (1/8 stepping -> 8)
    gear_ratio = 26.851            # motor revolutions per gearbox output revolution (optional, 1)
    pulley_ratio = 1.0             # gearbox output revolutions per joint revolution (optional, 1)
    pulses_per_revolution = 42962  # optional: the count the controller uses, when it rounds the
                                   # product above (within 1 pulse of it)
    home = 90.0                    # joint value the pulses are counted from (optional, 0)
    direction = 1                  # +1, or -1 for a motor turning against the joint (optional)

Joints without an entry have no drive. Only revolute joints take a drive (a prismatic one is
refused with a :class:`TableError`); pulses follow eqs. (27)-(28) of paper 003:
``pulses = round((q - home) * pulses_per_revolution / 360 deg)``, ``q = home + pulses * 360 deg /
pulses_per_revolution`` (times ``direction``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .exceptions import TableError

_KEYS = {
    "steps_per_revolution",
    "microstepping",
    "gear_ratio",
    "pulley_ratio",
    "pulses_per_revolution",
    "home",
    "direction",
}
_REQUIRED = ("steps_per_revolution", "microstepping")


@dataclass(frozen=True)
class JointDrive:
    """A stepper drive of one revolute joint (eqs. 27-28 of paper 003).

    Attributes:
        index: 1-based row of the joint in the table.
        joint: Joint name.
        steps_per_revolution: Full motor steps per motor revolution [step/rev] (200 for 1.8 deg).
        microstepping: Driver microsteps per full step [pulse/step] (16 for 1/16 stepping).
        gear_ratio: Motor revolutions per gearbox output revolution [-].
        pulley_ratio: Gearbox output revolutions per joint revolution [-] (belt and pulleys).
        pulses_per_revolution: Pulses per joint revolution the controller counts [pulse/rev]:
            the product of the four above, or the rounded count the table gives.
        home: Joint value the pulse count starts from [rad].
        direction: +1, or -1 when a positive pulse count turns the joint negatively.
    """

    index: int
    joint: str
    steps_per_revolution: float
    microstepping: float
    gear_ratio: float = 1.0
    pulley_ratio: float = 1.0
    pulses_per_revolution: float = 0.0
    home: float = 0.0
    direction: int = 1

    def __post_init__(self) -> None:
        if self.pulses_per_revolution <= 0.0:
            object.__setattr__(self, "pulses_per_revolution", self.geared_pulses_per_revolution)

    @property
    def geared_pulses_per_revolution(self) -> float:
        """Steps x microsteps x gear x pulley [pulse/rev], before any rounding."""
        return self.steps_per_revolution * self.microstepping * self.gear_ratio * self.pulley_ratio

    @property
    def step_size(self) -> float:
        """Joint angle of one pulse [rad]."""
        return 2.0 * math.pi / self.pulses_per_revolution


def _positive(path: str, value: Any, row: int, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise TableError(path, f"expected a finite number, got {value!r}", row, f"drives.{key}")
    if value <= 0:
        raise TableError(path, f"expected a positive number, got {value!r}", row, f"drives.{key}")
    return float(value)


def _drive(path: str, row: Any, data: Any, radians: float) -> JointDrive:
    if not isinstance(data, dict):
        raise TableError(path, "expected a table of drive fields", row.index, "drives")
    unknown = sorted(set(data) - _KEYS)
    if unknown:
        raise TableError(
            path,
            f"unknown drive field; allowed fields: {', '.join(sorted(_KEYS))}",
            row.index,
            f"drives.{unknown[0]}",
        )
    for key in _REQUIRED:
        if key not in data:
            raise TableError(path, "missing required drive field", row.index, f"drives.{key}")
    if row.joint_type != "revolute":
        raise TableError(path, "drives of prismatic joints are not supported", row.index, "drives")
    values = {k: _positive(path, data[k], row.index, k) for k in _KEYS & set(data) - {"home"}}
    direction = data.get("direction", 1)
    if direction not in (1, -1) or isinstance(direction, bool):
        raise TableError(
            path, f"expected 1 or -1, got {direction!r}", row.index, "drives.direction"
        )
    home = data.get("home", 0.0)
    if isinstance(home, bool) or not isinstance(home, int | float) or not math.isfinite(home):
        raise TableError(path, f"expected a finite number, got {home!r}", row.index, "drives.home")
    drive = JointDrive(
        index=row.index,
        joint=row.name,
        steps_per_revolution=values["steps_per_revolution"],
        microstepping=values["microstepping"],
        gear_ratio=values.get("gear_ratio", 1.0),
        pulley_ratio=values.get("pulley_ratio", 1.0),
        pulses_per_revolution=values.get("pulses_per_revolution", 0.0),
        home=float(home) * radians,
        direction=int(direction),
    )
    if abs(drive.pulses_per_revolution - drive.geared_pulses_per_revolution) >= 1.0:
        raise TableError(
            path,
            f"pulses_per_revolution {drive.pulses_per_revolution:g} is not within 1 pulse of "
            f"steps x microstepping x gear x pulley = {drive.geared_pulses_per_revolution:g}",
            row.index,
            "drives.pulses_per_revolution",
        )
    return drive


def parse_drives(path: str, data: Any, rows: tuple, radians: float) -> tuple[JointDrive, ...]:
    """The ``[drives]`` section: one :class:`JointDrive` per listed joint, in row order.

    Args:
        path: The table file (for messages).
        data: The parsed ``[drives]`` table: joint name or row index -> drive fields.
        rows: The table's :class:`~dh2urdf.dh_table.DHRow` rows.
        radians: Radians per angle unit of the table (for ``home``).

    Raises:
        TableError: An unknown joint, an unknown or bad field; the message names row and field.
    """
    if not isinstance(data, dict):
        raise TableError(path, "expected a table [drives.<joint>]", None, "drives")
    by_key = {row.name: row for row in rows} | {str(row.index): row for row in rows}
    drives: dict[int, JointDrive] = {}
    for key, fields in data.items():
        row = by_key.get(key)
        if row is None:
            names = ", ".join(row.name for row in rows)
            raise TableError(
                path,
                f"unknown joint {key!r} in [drives]; joints: {names} (or row numbers 1-{len(rows)})",
                None,
                f"drives.{key}",
            )
        if row.index in drives:
            raise TableError(path, "the joint has two drives", row.index, f"drives.{key}")
        drives[row.index] = _drive(path, row, fields, radians)
    return tuple(drives[i] for i in sorted(drives))
