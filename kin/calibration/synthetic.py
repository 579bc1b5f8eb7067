"""Synthetic calibration cases with a known truth: a nominal arm, the arm "as built", a tracker.

The arm as built is the nominal table written as URDF-style joint origins (``O_1 M(q_1) O_2
M(q_2) ... O_n M(q_n) O_tool``, ``M`` the joint's motion about or along z), each origin moved by
a random rigid error (every translation component normal with ``origin_mm``, every rotation
component with ``origin_deg``) and every joint reading shifted by a zero offset (``offset_deg``);
the tracker stands at a random pose, the measured point (or frame, or markers) at a random
offset from the flange. Its FK is this plain product of 4x4 matrices, independent of the
calibration's own model (:mod:`kin.calibration.prediction`). Measurements add normal noise
(``noise_mm`` per coordinate, ``noise_deg`` per rotation axis).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.spatial.transform import Rotation

from dh2urdf import DHTable
from dh2urdf.transforms import rot_x, rot_y, rot_z, translation

from .errors import Errors, errors
from .measurements import Measurements

if TYPE_CHECKING:
    from .calibration import Calibration


def _small(rng: np.random.Generator, mm: float, deg: float) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = Rotation.from_rotvec(rng.normal(0.0, np.radians(deg), 3)).as_matrix()
    out[:3, 3] = rng.normal(0.0, mm * 1e-3, 3)
    return out


def nominal_origins(table: DHTable) -> list[np.ndarray]:
    """The table's joint origins ``O_1 .. O_n`` and ``O_tool`` (URDF style, 4x4) [m]."""
    origins = []
    pending = np.array(table.T_world_base)
    for row in table.rows:
        twist = rot_x(row.alpha) @ rot_y(row.beta) if row.beta else rot_x(row.alpha)
        if table.convention == "standard":
            origins.append(pending @ rot_z(row.theta) @ translation(z=row.d))
            pending = translation(x=row.a) @ twist
        else:
            origins.append(
                pending @ twist @ translation(x=row.a) @ rot_z(row.theta) @ translation(z=row.d)
            )
            pending = np.eye(4)
    origins.append(pending @ table.T_last_tool)
    return origins


@dataclass(frozen=True, eq=False)
class TrueArm:
    """The arm as built, in the tracker's frame.

    Attributes:
        nominal: The nominal table.
        origins: Joint origins as built, ``O_1 .. O_n`` (4x4 each) [m]; the tool's is ``tool``.
        offsets: Zero offset of each joint reading [rad] / [m].
        T_measurement_world: The nominal table's world frame in the tracker's frame (4x4) [m].
        tool: The measured frame in the last joint's frame (after ``M(q_n)``) (4x4) [m].
        markers: Marker positions in that frame (K, 3) [m].
    """

    nominal: DHTable
    origins: tuple[np.ndarray, ...]
    offsets: np.ndarray
    T_measurement_world: np.ndarray
    tool: np.ndarray
    markers: np.ndarray

    def last_frames(self, q: np.ndarray) -> np.ndarray:
        """The frame after the last joint's motion, in the tracker's frame (N, 4, 4) [m]."""
        q = np.atleast_2d(q) + self.offsets
        out = np.broadcast_to(self.T_measurement_world, (len(q), 4, 4)).copy()
        for i, (row, origin) in enumerate(zip(self.nominal.rows, self.origins)):
            value = row.direction * q[:, i]
            motion = np.tile(np.eye(4), (len(q), 1, 1))
            if row.joint_type == "revolute":
                c, s = np.cos(value), np.sin(value)
                motion[:, 0, 0] = motion[:, 1, 1] = c
                motion[:, 0, 1], motion[:, 1, 0] = -s, s
            else:
                motion[:, 2, 3] = value
            out = out @ origin @ motion
        return out

    def measure(
        self,
        q: np.ndarray,
        poses: bool,
        rng: np.random.Generator | None = None,
        noise_mm: float = 0.05,
        noise_deg: float = 0.01,
    ) -> Measurements:
        """What the tracker reads at ``q`` (N, n): ``tool``'s poses or the markers, noisy with ``rng``."""
        last = self.last_frames(q)
        n = len(last)
        if poses:
            frames = last @ self.tool
            points = frames[:, None, :3, 3].copy()
            rotations: np.ndarray | None = frames[:, :3, :3].copy()
        else:
            points = last[:, None, :3, 3] + np.einsum("nij,kj->nki", last[:, :3, :3], self.markers)
            rotations = None
        if rng is not None:
            points = points + rng.normal(0.0, noise_mm * 1e-3, points.shape)
            if rotations is not None:
                turn = Rotation.from_rotvec(
                    rng.normal(0.0, np.radians(noise_deg), (n, 3))
                ).as_matrix()
                rotations = turn @ rotations
        return Measurements(np.atleast_2d(q).copy(), points, rotations, np.arange(2, n + 2))


def true_arm(
    table: DHTable,
    seed: int = 0,
    origin_mm: float = 0.5,
    origin_deg: float = 0.05,
    offset_deg: float = 0.05,
    markers: int = 1,
) -> TrueArm:
    """A random arm as built from ``table`` (see the module's text), reproducible by ``seed``."""
    rng = np.random.default_rng(seed)
    nominal = nominal_origins(table)
    origins = tuple(o @ _small(rng, origin_mm, origin_deg) for o in nominal[:-1])
    offsets = np.array(
        [
            np.radians(offset_deg) if r.joint_type == "revolute" else offset_deg * 1e-3
            for r in table.rows
        ]
    ) * rng.normal(0.0, 1.0, table.dof)
    where = np.eye(4)
    where[:3, :3] = Rotation.random(random_state=rng).as_matrix()
    where[:3, 3] = rng.uniform(-2.0, 2.0, 3)
    tool = nominal[-1] @ _small(rng, 0.0, 0.0)
    tool[:3, 3] += rng.uniform(-0.05, 0.05, 3)
    tool[:3, :3] = tool[:3, :3] @ Rotation.from_rotvec(rng.uniform(-0.5, 0.5, 3)).as_matrix()
    marker_points = nominal[-1][:3, 3] + rng.uniform(-0.05, 0.05, (markers, 3))
    return TrueArm(table, origins, offsets, where, tool, marker_points)


def random_configurations(table: DHTable, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` joint vectors uniform within the limits (N, n) [rad] / [m]."""
    return rng.uniform(table.lower, table.upper, (count, table.dof))


def held_out_errors(
    arm: TrueArm, calibration: Calibration, count: int = 1000, seed: int = 12345
) -> Errors:
    """Errors of the calibrated model on ``count`` fresh configurations of the true arm (no noise)."""
    q = random_configurations(arm.nominal, count, np.random.default_rng(seed))
    truth = arm.measure(q, poses=calibration.measurements.rotations is not None)
    return errors(calibration.model, calibration.x, truth)
