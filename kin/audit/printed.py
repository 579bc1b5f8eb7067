"""Match the readings of a table against printed samples, all readings and samples at once.

The forward kinematics of every reading at every sample is one array computation
(:mod:`kin.audit.fk_many`), and so is the comparison with the printed values, over (readings,
samples, values). A printed value is reproduced when the computed one gives it at its printed
precision: rounded (``|computed - printed| <= 10**-decimals / 2 + joint slack``), or, under the
reading "printed values truncated", also truncated (the printed digits are the computed ones cut
short). The joint slack is the first-order effect of the rounding of the printed joint values
themselves: per joint, the change of the computed value when that joint moves by half a unit
of its last printed digit, summed over the joints (:func:`joint_slack`); a source that prints
joint values to 6 decimals of degrees moves its tool by a few 1e-6 mm, which a position printed
to 4 decimals must be allowed. A sample is reproduced when all its printed values are.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .audited_table import AuditedTable
from .fk_many import many_tool_poses
from .readings import Reading, sample_meters, sample_radians
from .samples import SampleSet

#: Configurations (readings x samples) computed per block.
BLOCK = 100_000

#: Printed joint values with at least this many decimals are taken as rounded (their rounding
#: enters the tolerance); fewer decimals as exact inputs.
ROUNDED_JOINT_DECIMALS = 2

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
        joint_slack: Per sample and printed value, the tolerance added for the rounding of
            the printed joint values (N, K) [printed unit] (:func:`joint_slack`).
    """

    reading: Reading
    reproduced: np.ndarray
    within_limits: np.ndarray
    values_reproduced: int
    values: int
    position_residual_m: np.ndarray
    orientation_residual: np.ndarray
    order: int
    joint_slack: np.ndarray | None = None

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
        q = q * audited.table.directions  # DH angle theta + direction * q
    table = audited.table
    return np.all((q >= table.lower - 1e-9) & (q <= table.upper + 1e-9), axis=1)


def joint_slack(
    audited: AuditedTable, samples: SampleSet, readings: list[Reading], computed: np.ndarray
) -> np.ndarray:
    """The rounding of the printed joint values, carried to the printed values (R, N, K).

    Per joint ``j``: ``|value(q + h_j e_j) - value(q)|`` with ``h_j`` half a unit of the last
    printed digit of ``q_j`` (a first-order bound of what that rounding moves each value),
    summed over the joints. A joint value printed with fewer than
    :data:`ROUNDED_JOINT_DECIMALS` decimals counts as exact (``h_j = 0``): sources choose
    inputs such as 90 or -30.5 and print them whole; values such as 41.1993 are outputs.
    """
    if samples.q_decimals is None:
        return np.zeros(1)
    total = np.zeros_like(computed)
    decimals = samples.q_decimals.astype(float)
    # A value printed with fewer than ROUNDED_JOINT_DECIMALS decimals (90, -30.5) is a chosen
    # input, exact; more decimals (41.1993) are the rounded output of a computation.
    half = np.where(decimals >= ROUNDED_JOINT_DECIMALS, 0.5 * 10.0 ** (-decimals), 0.0)
    if not half.any():
        return total
    for j in range(samples.q.shape[1]):
        moved_q = samples.q.copy()
        moved_q[:, j] += half[:, j]
        moved = predicted_values(audited, replace(samples, q=moved_q), readings)
        change = np.abs(moved - computed)
        if samples.orientation == "rpy":  # angles: the change modulo one turn
            turn = 2 * np.pi / np.array([sample_radians(r) for r in readings])[:, None, None]
            wrapped = np.minimum(change, np.abs(turn - change))
            change = np.where(np.arange(change.shape[2]) >= 3, wrapped, change)
        total += change
    return total


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
    slack = joint_slack(audited, samples, readings, computed)
    printed = samples.values[None]
    given = ~np.isnan(printed)
    unit = 10.0 ** (-samples.decimals[None].astype(float))
    if samples.orientation == "rpy":  # compare angles modulo one turn, in the printed unit
        turn = 2 * np.pi / np.array([sample_radians(r) for r in readings])[:, None, None]
        wrapped = printed + (computed - printed + turn / 2) % turn - turn / 2
        computed = np.where(np.arange(computed.shape[2]) >= 3, wrapped, computed)
    error = np.abs(computed - printed)
    rounded = error <= unit / 2 + slack + EPS
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
            joint_slack=slack[k] if slack.ndim == 3 else np.zeros(computed.shape[1:]),
        )
        for k, reading in enumerate(readings)
    ]
    return sorted(scores, key=lambda s: s.rank_key)
