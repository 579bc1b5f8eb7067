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
import numpy.typing as npt

from dh2urdf import DHTable
from dh2urdf.command_line import angle_scale, length_scale
from dh2urdf.exceptions import UnitWarning
from dh2urdf.output_text import shown_name
from dh2urdf.quoted_input import quoted
from dh2urdf.table_units import RADIAN_SUSPECT
from dh2urdf.table_values import MAX_LENGTH

from ..exceptions import JointVectorError, NotWithinLimitsError


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

    def columns(self) -> list[str]:
        """``"name [unit]"`` of every joint, the names as text output shows them (escaped)."""
        return [f"{shown_name(n)} [{u}]" for n, u in zip(self.joint_names, self.labels)]

    def describe(self) -> str:
        """``"name [unit], ..."`` of every joint, for messages and headers."""
        return ", ".join(self.columns())

    def to_si(
        self, values: Sequence[float], option: str = "--q", *, warn_units: bool = True
    ) -> np.ndarray:
        """Joint values given in command-line units, in SI ([rad] or [m]).

        Revolute values may be any finite number (a warning when, without ``--deg``, one is
        more than a turn, outside its joint's limits and inside them read as degrees: see
        :meth:`unit_slip`); prismatic ones at most ``MAX_LENGTH`` (1e6 m) in magnitude, the bound
        of a table's lengths, so that forward kinematics stays finite.

        Args:
            values: One value per joint, in command-line units.
            option: The option that gave them, for messages.
            warn_units: Give :meth:`unit_slip`'s line as a :class:`UnitWarning` (False: the
                caller folds it into its own warning line).

        Raises:
            JointVectorError: Not one value per joint, a value not finite or a prismatic value
                beyond 1e6 m; the message names the robot, the joint and the option.
        """
        nq = len(self.joint_names)
        try:
            if isinstance(values, (list, tuple)) and any(
                isinstance(v, (str, bytes, bool)) for v in values
            ):  # NumPy reads "1_000" as 1000 and true as 1 (JSON "seed_q")
                raise TypeError("a text or boolean value")
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
        if warn_units:
            slip = self.unit_slip(array, option)
            if slip is not None:
                warnings.warn(slip, UnitWarning, stacklevel=2)
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

    def unit_slip(self, values: npt.ArrayLike, option: str = "--q") -> str | None:
        """The line that says the first radian value looks like degrees, or None.

        Like degrees: more than a turn, outside its joint's limits, inside them read as degrees.
        A value inside the limits is what the arm does (ABB and FANUC joint 6 turn +-400 to
        450 deg): no line. Without limits (``lower`` None), more than a turn is enough.

        Args:
            values: One value per joint, in command-line units.
            option: The option that gave them.
        """
        given = np.asarray(values, dtype=float).reshape(-1).tolist()
        if "rad" not in self.labels:
            return None
        if self.lower is None or self.upper is None:
            return radian_slip(option, [v for v, u in zip(given, self.labels) if u == "rad"])
        for value, unit, name, low, high in zip(
            given, self.labels, self.joint_names, self.lower, self.upper
        ):
            if unit != "rad" or abs(value) <= RADIAN_SUSPECT or low <= value <= high:
                continue
            if low <= math.radians(value) <= high:
                return (
                    f"{option} value {value:g} rad of joint '{shown_name(name)}' is outside its "
                    f"range [{low:.6g}, {high:.6g}] rad, inside it as {value:g} deg: degrees? "
                    "then add --deg"
                )
        return None

    def from_si(self, q: np.ndarray) -> np.ndarray:
        """SI joint values ([rad] or [m]) in command-line units."""
        return np.asarray(q, dtype=float) / self.scales


def beyond_a_turn(values: Sequence[float]) -> float | None:
    """The first of ``values`` [rad] more than a turn in magnitude (degrees?), or None."""
    return next((value for value in values if abs(value) > RADIAN_SUSPECT), None)


def radian_slip(option: str, values: Sequence[float]) -> str | None:
    """The line that says a value in radians exceeds a turn (degrees?), or None."""
    value = beyond_a_turn(values)
    if value is None:
        return None
    return f"{option} value {value:g} rad is more than a turn: degrees? then add --deg"


def limits_line(violations: Sequence[NotWithinLimitsError], slip: str | None = None) -> str | None:
    """One warning line for the joints outside their limits and a unit slip, or None.

    A unit slip (:meth:`JointUnits.unit_slip`) is the line, with the number of joints outside
    their limits when it is more than the slip's one; else the one joint outside, or the count
    and every joint (name, value and limits, in SI).

    Args:
        violations: The joints outside their limits (:func:`kin.configuration.limit_violations`).
        slip: The unit slip's line, or None.
    """
    if slip is not None:
        if len(violations) <= 1:  # the slip's joint
            return slip
        return f"{slip}; as given, {len(violations)} joints are outside their limits"
    if not violations:
        return None
    if len(violations) == 1:
        v = violations[0]
        return (
            f"joint '{shown_name(v.joint)}' value {v.value:.6g} {v.unit} is outside its limits "
            f"[{v.lower:.6g}, {v.upper:.6g}] {v.unit}"
        )
    joints = "; ".join(
        f"'{shown_name(v.joint)}' {v.value:.6g} {v.unit} [{v.lower:.6g}, {v.upper:.6g}]"
        for v in violations
    )
    return f"{len(violations)} joints are outside their limits: {joints}"
