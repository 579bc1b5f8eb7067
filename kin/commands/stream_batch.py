"""The compiled route of ``kin ik --stdin``: the lines of a batch answered together.

Where the solver's first stage has a batched, compiled form (:attr:`BatchRoute.batch`:
:func:`kin.ik.batch_solve.start_free_joint_answers`, the free-joint closed form's scans in
threads), full poses and positions go to it together:

- the plainest lines (:func:`~.stream_reader.plain_groups`), read into arrays with one check
  for all, their stage started as soon as they are read (:meth:`BatchRoute.start`), their
  answers encoded when it ends (:meth:`BatchRoute.finish`,
  :func:`~.stream_records.encode_found`);
- the other lines the stage takes, once read one by one (:meth:`BatchRoute.solve_together`).

The lines it leaves unanswered (NaN rows) go to the solver one by one, with the targets the
line-by-line reader would make (the same float64 values): the answers are those of each line
alone. Units: targets in ``--unit`` and rad (deg with ``--deg``) as read, SI inside.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from ..exceptions import KinError
from ..ik.angles import rpy_matrices
from ..ik.targets.target import PoseTarget, Target
from .joint_units import JointUnits
from .stream_records import PlainWriter, batch_record, encode_found
from .targets import build_target

logger = logging.getLogger(__name__)

#: ``batch(points (N, 3), rotations (N, 3, 3) or None, seeds (N, nq))`` -> what finishes it:
#: ``() -> (q, position errors, rotation errors)``, NaN rows where it gives no answer.
BatchStage = Callable[..., Callable[[], tuple[np.ndarray, np.ndarray, np.ndarray]]]


def _no_answers() -> dict[int, str]:
    """The answers of a group of plain lines the batch stage did not take: none."""
    return {}


@dataclass(frozen=True)
class BatchRoute:
    """The batch stage of one robot and solver, over the lines of a read batch.

    Attributes:
        batch: The solver's batched first stage (:data:`BatchStage`).
        nq: Number of joints.
        seed: Default seed [rad] / [m], or None (zeros).
        length: Meters per ``--unit``.
        angle: Radians per input angle unit.
        units: The joint units (``"q_units"`` of the answers).
        pipeline: The solver's name, as the answers report it.
    """

    batch: BatchStage
    nq: int
    seed: np.ndarray | None
    length: float
    angle: float
    units: JointUnits
    pipeline: str

    def start(
        self,
        indices: list[int],
        targets: Any,
        rpys: Any,
        before: int,
        tried: dict[int, Target],
        write_plain: PlainWriter | None,
    ) -> Callable[[], dict[int, str]]:
        """Start the batch stage on one group of plain lines; what gives their encoded answers.

        ``targets`` and ``rpys`` (None for positions) as read (arrays, or the lists the json
        module gave), in the user's units; a line with a value not finite, or an angle beyond a
        turn without --deg, is left to the line-by-line path (its checks and warnings). The
        callable returned (:meth:`finish`) gives the answers by line index and adds to
        ``tried`` the lines the stage read and left, with their targets.
        """
        from dh2urdf.table_units import RADIAN_SUSPECT

        poses = rpys is not None
        try:
            with np.errstate(all="ignore"):
                given = np.array(targets, dtype=float)  # in --unit
                points = given * self.length
                angles = np.array(rpys, dtype=float) if poses else None
        except (TypeError, ValueError, OverflowError):
            return _no_answers
        if points.shape != (len(indices), 3) or (
            angles is not None and angles.shape != (len(indices), 3)
        ):
            return _no_answers
        keep = np.isfinite(points).all(axis=1)
        rotations = None
        if angles is not None:
            keep &= np.isfinite(angles).all(axis=1)
            if self.angle == 1.0:
                keep &= (np.abs(angles) <= RADIAN_SUSPECT).all(axis=1)
            # Reduced modulo a turn in the given unit first (angle_to_radians, vectorized).
            turns = np.fmod(np.where(keep[:, None], angles, 0.0), 2.0 * np.pi / self.angle)
            rotations = rpy_matrices(turns * self.angle)
        rows = np.flatnonzero(keep)
        if not rows.size:
            return _no_answers
        start = time.perf_counter()
        default = np.zeros(self.nq) if self.seed is None else self.seed
        seeds = np.broadcast_to(default, (rows.size, self.nq))
        try:
            result = self.batch(points[rows], None if rotations is None else rotations[rows], seeds)
        except Exception:  # noqa: BLE001 - the lines go the line-by-line way instead
            logger.debug("batch stage failed", exc_info=True)
            return _no_answers
        launch = time.perf_counter() - start
        return partial(
            self.finish, indices, given, angles, rows, result, launch, before, tried, write_plain
        )

    def finish(
        self,
        indices: list[int],
        given: np.ndarray,
        angles: np.ndarray | None,
        rows: np.ndarray,
        result: Callable[[], tuple[np.ndarray, np.ndarray, np.ndarray]],
        launch: float,
        before: int,
        tried: dict[int, Target],
        write_plain: PlainWriter | None,
    ) -> dict[int, str]:
        """The encoded answers of :meth:`start`'s lines, by line index.

        ``given``, ``angles``: their targets and rpy as read (in --unit, and radians or degrees);
        ``rows`` of them went to the batch stage: ``result`` gives its answer; ``launch`` [s]
        it took to start. ``time_s`` of an answer: the time spent starting and finishing the
        batch stage, per line (not the time other lines took in between).
        """
        start = time.perf_counter()
        try:
            q, position_error, rotation_error = result()
        except Exception:  # noqa: BLE001 - the lines go the line-by-line way instead
            logger.debug("batch stage failed", exc_info=True)
            return {}
        each = (launch + time.perf_counter() - start) / rows.size
        found = ~np.isnan(q).any(axis=1)
        for row in rows[~found].tolist():  # made as request() makes them, from the same numbers
            rpy = None if angles is None else angles[row].tolist()
            try:
                target, _ = build_target(
                    given[row].tolist(), rpy=rpy, length=self.length, angle=self.angle
                )
            except (KinError, ValueError):  # request() says what is wrong with the line
                continue
            tried[indices[row]] = target
        return encode_found(
            self.pipeline,
            self.units.si_labels,
            [indices[row] for row in rows[found].tolist()],
            q[found],
            position_error[found],
            None if angles is None else rotation_error[found],
            before + 1,  # the number of line index 0
            each,
            write_plain,
        )

    def solve_together(
        self,
        items: list[tuple[int, Target, np.ndarray | None]],
        before: int,
        solved: Callable[[int, Target, np.ndarray | None], dict[str, Any]],
    ) -> dict[int, dict[str, Any]]:
        """The answers of read lines the stage takes (poses and positions apart), by line index.

        ``items``: ``(index, target, seed)``; ``solved(number, target, seed)``: the answer of a
        line the stage leaves, by the solver alone.
        """
        records: dict[int, dict[str, Any]] = {}
        for poses in (True, False):
            group = [item for item in items if (item[1].__class__ is PoseTarget) == poses]
            if not group:
                continue
            start = time.perf_counter()
            points = np.array([target.position for _, target, _ in group])
            rotations = (
                np.array([target.rotation for _, target, _ in group])  # type: ignore[union-attr]
                if poses
                else None
            )
            default = np.zeros(self.nq) if self.seed is None else self.seed
            seeds = np.array([default if seed is None else seed for _, _, seed in group])
            try:
                q, position_error, rotation_error = self.batch(points, rotations, seeds)()
            except Exception:  # noqa: BLE001 - the lines go one by one instead
                logger.debug("batch stage failed", exc_info=True)
                q = np.full((len(group), self.nq), np.nan)
            each = (time.perf_counter() - start) / len(group)
            missing = np.asarray(np.isnan(q).any(axis=1))  # per line: the stage gave no answer
            for k, (index, target, seed) in enumerate(group):
                if missing[k]:
                    records[index] = solved(before + index + 1, target, seed)
                    continue
                rotation = float(rotation_error[k]) if poses else None
                records[index] = batch_record(
                    self.pipeline, q[k].tolist(), float(position_error[k]), rotation, each
                )
        return records
