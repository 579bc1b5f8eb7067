"""The units rule of every command: ``--unit`` for every length, ``--deg`` for revolute angles.

A joint value is a length when the joint is prismatic (in ``--unit``, like every position) and an
angle when it is revolute (degrees with ``--deg``, else radians). Inside, everything is SI: meters
and radians. JSON output stays SI and says so per joint (``"q_units": ["rad", "m", ...]``).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from dh2urdf import DHTable
from dh2urdf.command_line import angle_scale, length_scale
from dh2urdf.exceptions import UnitWarning
from dh2urdf.quoted_input import quoted
from dh2urdf.table_file import RADIAN_SUSPECT
from dh2urdf.table_values import MAX_LENGTH

from ..exceptions import JointVectorError


def joint_types_code(table: DHTable) -> str:
    """Joint types as runs, base to tip: ``"6R"``, ``"2R1P1R"`` (two revolute, one prismatic, ...)."""
    runs: list[list] = []
    for row in table.rows:
        letter = "R" if row.joint_type == "revolute" else "P"
        if runs and runs[-1][1] == letter:
            runs[-1][0] += 1
        else:
            runs.append([1, letter])
    return "".join(f"{count}{letter}" for count, letter in runs)


@dataclass(frozen=True, eq=False)
class JointUnits:
    """Per-joint units of one robot on the command line.

    Attributes:
        robot: Robot name (for messages).
        joint_names: Joint names, base to tip.
        scales: SI value per command-line unit, per joint ([rad]/[deg or rad], [m]/[--unit]).
        labels: Command-line unit per joint (``"deg"``, ``"rad"``, ``"mm"``, ...).
        si_labels: SI unit per joint (``"rad"`` or ``"m"``).
        lower: Lower limit per joint [rad] or [m], or None (then no limit-aware unit warning).
        upper: Upper limit per joint [rad] or [m], or None.
    """

    robot: str
    joint_names: tuple[str, ...]
    scales: np.ndarray
    labels: tuple[str, ...]
    si_labels: tuple[str, ...]
    lower: np.ndarray | None = None
    upper: np.ndarray | None = None

    @classmethod
    def of(cls, name: str, table: DHTable, unit: str = "m", degrees: bool = False) -> JointUnits:
        """Units of the joints of ``table`` for ``--unit unit`` and ``--deg``."""
        revolute = [row.joint_type == "revolute" for row in table.rows]
        angle, length = angle_scale(degrees), length_scale(unit)
        angle_label = "deg" if degrees else "rad"
        scales = np.array([angle if r else length for r in revolute], dtype=float)
        scales.setflags(write=False)
        return cls(
            robot=name,
            joint_names=table.joint_names,
            scales=scales,
            labels=tuple(angle_label if r else unit for r in revolute),
            si_labels=tuple("rad" if r else "m" for r in revolute),
            lower=table.lower,
            upper=table.upper,
        )

    def describe(self) -> str:
        """``"name [unit], ..."`` of every joint, for messages and headers."""
        return ", ".join(f"{n} [{u}]" for n, u in zip(self.joint_names, self.labels))

    def to_si(self, values: Sequence[float], option: str = "--q") -> np.ndarray:
        """Joint values given in command-line units, in SI ([rad] or [m]).

        Revolute values may be any finite number (a warning when, without ``--deg``, one is
        more than a turn, outside its joint's limits and inside them read as degrees);
        prismatic ones at most ``MAX_LENGTH`` (1e6 m) in magnitude, the bound of a table's lengths,
        so that forward kinematics stays finite.

        Raises:
            JointVectorError: Not one value per joint, a value not finite or a prismatic value
                beyond 1e6 m; the message names the robot, the joint and the option.
        """
        nq = len(self.joint_names)
        try:
            array = np.array(values, dtype=float).reshape(-1)
        except (TypeError, ValueError) as err:
            raise JointVectorError(
                f"{option} must be numbers for '{self.robot}', got {quoted(values)}", nq, -1
            ) from err
        if array.size != nq:
            raise JointVectorError(
                f"{option} needs {nq} values for '{self.robot}' ({self.describe()}), "
                f"got {array.size}",
                nq,
                array.size,
            )
        if not np.isfinite(array).all():
            raise JointVectorError(
                f"{option} values must be finite, got {quoted(array.tolist())}", nq, array.size
            )
        if self.labels and "rad" in self.labels:
            self._warn_degrees(option, array)
        si = array * self.scales
        for name, value, given, unit, si_unit in zip(
            self.joint_names, si.tolist(), array.tolist(), self.labels, self.si_labels
        ):
            if si_unit == "m" and abs(value) > MAX_LENGTH:
                raise JointVectorError(
                    f"{option}: prismatic joint '{name}' value {given:g} {unit} is beyond "
                    f"{MAX_LENGTH:g} m, the longest length a table may give; check the value "
                    "and --unit",
                    nq,
                    array.size,
                )
        return si

    def _warn_degrees(self, option: str, values: np.ndarray) -> None:
        """A :class:`~dh2urdf.exceptions.UnitWarning` for the first radian value like degrees.

        Like degrees: more than a turn, outside its joint's limits, inside them read as degrees.
        A value inside the limits is what the arm does (ABB and FANUC joint 6 turn +-400 to
        450 deg): no warning. Without limits (``lower`` None), more than a turn is enough.
        """
        if self.lower is None or self.upper is None:
            warn_radians(option, [v for v, u in zip(values.tolist(), self.labels) if u == "rad"])
            return
        for value, unit, name, low, high in zip(
            values.tolist(), self.labels, self.joint_names, self.lower, self.upper
        ):
            if unit != "rad" or abs(value) <= RADIAN_SUSPECT or low <= value <= high:
                continue
            if low <= math.radians(value) <= high:
                warnings.warn(
                    f"{option} value {value:g} rad of joint '{name}' is outside its range "
                    f"[{low:.6g}, {high:.6g}] rad, inside it as {value:g} deg: degrees? then "
                    "add --deg",
                    UnitWarning,
                    stacklevel=4,
                )
                return

    def from_si(self, q: np.ndarray) -> np.ndarray:
        """SI joint values ([rad] or [m]) in command-line units."""
        return np.asarray(q, dtype=float) / self.scales


def warn_radians(option: str, values: Sequence[float]) -> None:
    """A :class:`~dh2urdf.exceptions.UnitWarning` when a value in radians exceeds a turn."""
    for value in values:
        if abs(value) > RADIAN_SUSPECT:
            warnings.warn(
                f"{option} value {value:g} rad is more than a turn: degrees? then add --deg",
                UnitWarning,
                stacklevel=3,
            )
            return
