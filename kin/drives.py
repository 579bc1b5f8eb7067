"""Stepper drives: joint angles to whole pulses and back, and the pose error of the rounding.

The model of paper 003 (eqs. 27-28): a joint driven by a stepper motor through a microstepping
driver, a gearbox and a belt turns ``360 deg / pulses_per_revolution`` per pulse, with
``pulses_per_revolution = steps_per_revolution * microstepping * gear_ratio * pulley_ratio``
(or the rounded count the controller uses). A joint angle ``q`` is sent as

    pulses = direction * ROUND((q - home) * pulses_per_revolution / 360 deg)        (27)

counted from the ``home`` the controller was calibrated at, and the joint then reaches

    q_reached = home + direction * pulses * 360 deg / pulses_per_revolution        (28)

``ROUND`` is MATLAB's (halves away from zero), as in the paper's GUI. The drives come from the
``[drives]`` section of a table file (:class:`dh2urdf.drive_section.JointDrive`); the tool error
of the rounding is FK at ``q_reached`` against FK at ``q``, through :mod:`kin.batch_fk`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable
from dh2urdf.drive_section import JointDrive

from .batch_fk import _joint_array, batch_forward_kinematics
from .exceptions import KinError

__all__ = [
    "DriveQuantization",
    "DrivesError",
    "JointDrive",
    "angles_to_pulses",
    "from_pulses",
    "pulses_to_angles",
    "quantize",
    "table_drives",
]


class DrivesError(KinError, ValueError):
    """A table has no stepper drive for some joints.

    Attributes:
        table: Name (or file) of the table.
        missing: Names of the joints without a drive.
    """

    def __init__(self, table: str, missing: tuple[str, ...]):
        self.table = table
        self.missing = missing
        section = "[drives." + "], [drives.".join(missing) + "]"
        super().__init__(
            f"'{table}' has no stepper drive for joint(s) {', '.join(missing)}: add {section} "
            "sections (steps_per_revolution, microstepping, gear_ratio, pulley_ratio, home) to "
            "the table file"
        )


def table_drives(table: DHTable) -> tuple[JointDrive, ...]:
    """The drive of every joint of ``table``, base to tip.

    Raises:
        DrivesError: Some joints have no drive; the message names the table and the section.
    """
    by_index = {drive.index: drive for drive in table.drives}
    missing = tuple(row.name for row in table.rows if row.index not in by_index)
    if missing:
        raise DrivesError(table.path or table.name, missing)
    return tuple(by_index[row.index] for row in table.rows)


def _round_half_away(x: np.ndarray) -> np.ndarray:
    return np.sign(x) * np.floor(np.abs(x) + 0.5)


def _drive_arrays(drives: Sequence[JointDrive]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    per_radian = np.array([d.pulses_per_revolution / (2.0 * np.pi) for d in drives])
    home = np.array([d.home for d in drives])
    direction = np.array([d.direction for d in drives], dtype=float)
    return per_radian, home, direction


def angles_to_pulses(drives: Sequence[JointDrive], q: npt.ArrayLike) -> np.ndarray:
    """Eq. (27): whole pulses from home for joint angles ``q`` [rad], shape (dof,) or (N, dof).

    Returns:
        Pulses [pulse] as int64, the shape of ``q``.
    """
    per_radian, home, direction = _drive_arrays(drives)
    q = np.asarray(q, dtype=float)
    return (direction * _round_half_away((q - home) * per_radian)).astype(np.int64)


def pulses_to_angles(drives: Sequence[JointDrive], pulses: npt.ArrayLike) -> np.ndarray:
    """Eq. (28): joint angles [rad] reached after ``pulses`` [pulse] counted from home."""
    per_radian, home, direction = _drive_arrays(drives)
    return home + direction * np.asarray(pulses, dtype=float) / per_radian


@dataclass(frozen=True, eq=False)
class DriveQuantization:
    """Joint angles asked, the whole pulses sent, and what the arm reaches (N configurations).

    Attributes:
        q_asked: Joint angles asked, (N, dof) [rad].
        pulses: Pulses from home per joint (eq. 27), (N, dof) [pulse].
        q_reached: Joint angles the pulses give (eq. 28), (N, dof) [rad].
        joint_error: ``q_reached - q_asked``, (N, dof) [rad]; at most half a step per joint.
        step_size: Joint angle of one pulse per joint, (dof,) [rad].
        p_world_tool_asked: Tool position at ``q_asked``, (N, 3) [m].
        p_world_tool_reached: Tool position at ``q_reached``, (N, 3) [m].
        tool_rotation_error: Angle of ``R_asked^T R_reached`` of the tool, (N,) [rad].
    """

    q_asked: np.ndarray
    pulses: np.ndarray
    q_reached: np.ndarray
    joint_error: np.ndarray
    step_size: np.ndarray
    p_world_tool_asked: np.ndarray
    p_world_tool_reached: np.ndarray
    tool_rotation_error: np.ndarray

    @property
    def tool_position_error(self) -> np.ndarray:
        """``p_reached - p_asked`` in world axes, (N, 3) [m]."""
        return self.p_world_tool_reached - self.p_world_tool_asked

    @property
    def tool_position_error_norm(self) -> np.ndarray:
        """Distance between the tool points reached and asked, (N,) [m]."""
        return np.linalg.norm(self.tool_position_error, axis=1)


def _from_angles(table: DHTable, q: np.ndarray, q_reached: np.ndarray, pulses: np.ndarray):
    drives = table_drives(table)
    T_asked = batch_forward_kinematics(table, q)
    T_reached = batch_forward_kinematics(table, q_reached)
    R_delta = np.einsum("nji,njk->nik", T_asked[:, :3, :3], T_reached[:, :3, :3])
    cos_angle = np.clip((np.trace(R_delta, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    return DriveQuantization(
        q_asked=q,
        pulses=pulses,
        q_reached=q_reached,
        joint_error=q_reached - q,
        step_size=np.array([d.step_size for d in drives]),
        p_world_tool_asked=T_asked[:, :3, 3],
        p_world_tool_reached=T_reached[:, :3, 3],
        tool_rotation_error=np.arccos(cos_angle),
    )


def quantize(table: DHTable, q: npt.ArrayLike) -> DriveQuantization:
    """Round joint angles to whole pulses of the table's drives and the resulting errors.

    Args:
        table: A table with a drive per joint (its ``[drives]`` section).
        q: Joint angles asked, (dof,) or (N, dof) [rad].

    Raises:
        DrivesError: A joint has no drive.
        JointVectorError: ``q`` does not have one value per joint.
    """
    drives = table_drives(table)
    q = _joint_array(table, q)
    pulses = angles_to_pulses(drives, q)
    return _from_angles(table, q, pulses_to_angles(drives, pulses), pulses)


def from_pulses(
    table: DHTable, pulses: npt.ArrayLike, q_asked: npt.ArrayLike | None = None
) -> DriveQuantization:
    """What pulses counted from home reach; errors against ``q_asked`` (default: reached)."""
    drives = table_drives(table)
    pulses = np.asarray(np.rint(_joint_array(table, pulses)), dtype=np.int64)
    q_reached = pulses_to_angles(drives, pulses)
    q = q_reached if q_asked is None else _joint_array(table, q_asked)
    return _from_angles(table, q, q_reached, pulses)
