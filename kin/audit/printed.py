"""Match the readings of a table against printed samples, all readings and samples at once.

The forward kinematics of every reading at every sample is one array computation
(:mod:`kin.audit.fk_many`), and so is the comparison with the printed values, over (readings,
samples, values). A printed value is reproduced when the computed one gives it at its printed precision: rounded
(``|computed - printed| <= 10**-decimals / 2``), or, under the reading "printed values truncated",
also truncated (the printed digits are the computed ones cut short). A sample is reproduced when
all its printed values are.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .audited_table import AuditedTable
from .fk_many import many_tool_poses
from .readings import Reading, sample_meters, sample_radians
from .samples import SampleSet

#: Configurations (readings x samples) computed per block.
BLOCK = 100_000

#: Slack [printed unit] for values on a rounding tie or a truncation edge (floating-point noise).
EPS = 1e-9


@dataclass(frozen=True, eq=False)
class SampleScore:
    """How one reading does on a sample set.

    Attributes:
        reading: The reading.
        reproduced: Per sample, all its printed values reproduced (N,).
        within_limits: Per sample, the joint values lie within the table's limits (N,).
        values_reproduced: Number of printed values reproduced, over all samples.
        values: Number of printed values.
        position_residual_m: Per sample, distance between computed and printed position [m] (N,).
        orientation_residual: Per sample, largest orientation difference (N,): [rad] for
            roll-pitch-yaw, [-] for matrix entries; NaN without printed orientation.
        order: Place of the reading in the generation order (ties keep it).
    """

    reading: Reading
    reproduced: np.ndarray
    within_limits: np.ndarray
    values_reproduced: int
    values: int
    position_residual_m: np.ndarray
    orientation_residual: np.ndarray
    order: int

    @property
    def count(self) -> int:
        """Number of samples reproduced."""
        return int(self.reproduced.sum())

    @property
    def max_residual_m(self) -> float:
        """Largest position residual over the samples [m]."""
        return float(np.max(self.position_residual_m))

    @property
    def rank_key(self) -> tuple:
        """Sort key, best first: samples, in-limit samples, values, fewest changes, residual."""
        both = int((self.reproduced & self.within_limits).sum())
        changes = len(self.reading.changes) if self.values_reproduced else 0
        return (
            -self.count,
            -both,
            -self.values_reproduced,
            changes,
            self.max_residual_m,
            self.order,
        )


def rpy_of(rotations: np.ndarray) -> np.ndarray:
    """Roll, pitch, yaw [rad] of rotation matrices (..., 3, 3), ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    r = rotations
    pitch = np.arctan2(-r[..., 2, 0], np.hypot(r[..., 0, 0], r[..., 1, 0]))
    yaw = np.arctan2(r[..., 1, 0], r[..., 0, 0])
    roll = np.arctan2(r[..., 2, 1], r[..., 2, 2])
    return np.stack([roll, pitch, yaw], axis=-1)


def _joint_values(audited: AuditedTable, reading: Reading, q: np.ndarray) -> np.ndarray:
    """Joint values [rad] / [m] of the printed ones under ``reading``."""
    revolute = np.array([r.joint_type == "revolute" for r in audited.table.rows])
    scaled = np.where(revolute, q * sample_radians(reading), q * sample_meters(reading))
    return scaled * reading.signs


def predicted_values(
    audited: AuditedTable, samples: SampleSet, readings: list[Reading]
) -> np.ndarray:
    """The values (R, N, K) each reading computes for the samples, in the printed units.

    All readings at once (:func:`kin.audit.fk_many.many_tool_poses`), in blocks of about
    :data:`BLOCK` configurations.
    """
    revolute = np.array([r.joint_type == "revolute" for r in audited.table.rows])
    out = []
    step = max(1, BLOCK // max(len(samples), 1))
    for start in range(0, len(readings), step):
        chunk = readings[start : start + step]
        rad = np.array([sample_radians(r) for r in chunk])[:, None, None]
        met = np.array([sample_meters(r) for r in chunk])[:, None, None]
        signs = np.stack([r.signs for r in chunk])[:, None, :]
        q = np.where(revolute, samples.q[None] * rad, samples.q[None] * met) * signs
        poses = many_tool_poses([r.table for r in chunk], q)
        parts = [poses[..., :3, 3] / met]
        if samples.orientation == "rpy":
            parts.append(rpy_of(poses[..., :3, :3]) / rad)
        elif samples.orientation == "matrix":
            parts.append(poses[..., :3, :3].reshape(len(chunk), len(samples), 9))
        out.append(np.concatenate(parts, axis=2))
    return np.concatenate(out)


def _within_limits(audited: AuditedTable, reading: Reading, q_printed: np.ndarray) -> np.ndarray:
    q = _joint_values(audited, reading, q_printed)
    if any(c.kind == "offsets" for c in reading.changes):  # printed values are DH angles
        q = q - np.array(
            [r.theta if r.joint_type == "revolute" else r.d for r in audited.table.rows]
        )
    table = audited.table
    return np.all((q >= table.lower - 1e-9) & (q <= table.upper + 1e-9), axis=1)


def score_readings(
    audited: AuditedTable, samples: SampleSet, readings: list[Reading]
) -> list[SampleScore]:
    """Score every reading on the samples; best first.

    Args:
        audited: The table under audit (its units are the samples' units).
        samples: The printed samples.
        readings: The readings to try (e.g. :func:`kin.audit.readings.candidate_readings`).
    """
    computed = predicted_values(audited, samples, readings)  # (R, N, K)
    printed = samples.values[None]
    given = ~np.isnan(printed)
    unit = 10.0 ** (-samples.decimals[None].astype(float))
    if samples.orientation == "rpy":  # compare angles modulo one turn, in the printed unit
        turn = 2 * np.pi / np.array([sample_radians(r) for r in readings])[:, None, None]
        wrapped = printed + (computed - printed + turn / 2) % turn - turn / 2
        computed = np.where(np.arange(computed.shape[2]) >= 3, wrapped, computed)
    error = np.abs(computed - printed)
    rounded = error <= unit / 2 + EPS
    same_side = (printed == 0) | (np.sign(computed) == np.sign(printed))
    cut = same_side & (np.abs(printed) <= np.abs(computed) + EPS)
    cut &= np.abs(computed) - np.abs(printed) < unit + EPS
    truncated = np.array([r.truncated for r in readings])[:, None, None]
    ok = rounded | (truncated & cut) | ~given
    reproduced = ok.all(axis=2)
    values_ok = (ok & given).sum(axis=(1, 2))
    difference = np.where(given, computed - printed, 0.0)
    meters = np.array([sample_meters(r) for r in readings])[:, None]
    position = np.linalg.norm(difference[:, :, :3], axis=2) * meters
    if samples.orientation == "none":
        orientation = np.full(position.shape, np.nan)
    else:
        orientation = np.abs(difference[:, :, 3:]).max(axis=2)
        if samples.orientation == "rpy":
            orientation = orientation * np.array([sample_radians(r) for r in readings])[:, None]
    scores = [
        SampleScore(
            reading=reading,
            reproduced=reproduced[k],
            within_limits=_within_limits(audited, reading, samples.q),
            values_reproduced=int(values_ok[k]),
            values=int(given.sum()),
            position_residual_m=position[k],
            orientation_residual=orientation[k],
            order=k,
        )
        for k, reading in enumerate(readings)
    ]
    return sorted(scores, key=lambda s: s.rank_key)
