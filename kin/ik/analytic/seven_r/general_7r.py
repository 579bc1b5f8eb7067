"""Closed form of any 7R arm for chosen values of a free end joint, over the 6R closed forms.

Holding joint 1 or joint 7 of a seven-joint revolute arm leaves a 6R arm whose rows do not depend
on the held value: only the target moves (:mod:`.held_end`). That 6R arm is recognised once by the closed-form registry
(:func:`~kin.ik.analytic.registry.recognise_turned`): a special family where one fits (every
branch in closed form), else the general elimination of :mod:`..six_r.general_6r`
(Raghavan-Roth / Manocha-Canny). So every 7R table the humanoid7 and spherical-shoulder forms do
not fit (a Kinova Gen3, a 7R with offsets everywhere) gets every branch for each value of its free
joint: the self-motion parametrised by one joint angle, as IKFast's and IK-Geo's redundant-arm
solvers do (R. Diankov, "Automated Construction of Robotic Manipulation Programs", PhD thesis,
CMU, 2010, ch. 4; A. J. Elias, J. T. Wen, "IK-Geo", Mechanism and Machine Theory 2025).

Which end joint is held: the one whose 6R arm a special family fits; between two alike, the one
whose closed form recovers more of :data:`PROBES` sampled joint vectors from their tool poses
(the better conditioned); then joint 7. The numeric solver's first stage
(:mod:`kin.ik.numeric.free_joint`) asks :meth:`General7RIK.first` as it asks the other free-joint
forms when the 6R left is a special family's (tens of microseconds a solve); when it takes the
general elimination (about 1 ms a solve, :attr:`General7RIK.costly`), after the seed-table
stage, whose damped Newton answers such arms in a fraction of that. Starts are solved together
and a scan of the free joint is one batched solve of its values, nearest to the start first
(:mod:`.free_value_scan`). An arm a snapped special form fits takes that form's branches,
polished onto the arm (:mod:`.ideal_7r`).
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ...exceptions import StructureError
from ..registry import recognise_turned
from ..six_r.general_6r import General6R
from ..structure import refuse_tilts
from . import free_value_scan
from .held_end import HeldEnd, held_end, six_r_table
from .ideal_7r import FOLD_PER_METER, HeldTwin, held_branches, held_rows_at, held_twin, ideal_form
from .seven_dof import SevenDofIK

#: Sampled joint vectors by which the free joint is chosen, and their seed.
PROBES = 16
PROBE_SEED = 3
_TWO_PI = 2.0 * math.pi


class General7RIK:
    """Every branch of a 7R arm at chosen values of its free end joint (joint 1 or 7).

    Args:
        table: The arm's DH table: seven revolute rows, every direction 1 (a forward table,
            :func:`~kin.ik.analytic.joint_directions.forward_table`).
        lower: Lower joint limits [rad] (7).
        upper: Upper joint limits [rad] (7).

    Attributes:
        free: The held joint (0-based: 0 or 6).
        structure: The 6R closed form of the rest of the arm.
        end: The arm with that joint held (:class:`~.held_end.HeldEnd`).
        ideal: The snapped arm's form (:mod:`.ideal_7r`) whose branches, polished with joint 1
            held, answer in place of ``structure`` (joint 1 is then the held one), or None.
        fold_margin: Within this of a double root of ``ideal`` (its
            :func:`~.subproblems.fold_distance`), ``structure`` answers the value [m].

    Raises:
        StructureError: Not seven revolute joints, or no 6R closed form fits the arm left by
            holding joint 1 or joint 7.
    """

    #: No compiled twin: the 6R closed forms it calls are batched in NumPy (or compiled).
    compiled_twin: ClassVar[bool] = False

    def __init__(self, table: DHTable, lower: npt.ArrayLike, upper: npt.ArrayLike):
        if table.dof != 7 or any(row.joint_type != "revolute" for row in table.rows):
            raise StructureError(table.name, "general 7R", "it needs seven revolute joints")
        refuse_tilts(table, "general 7R")  # the held joint's transform is a plain DH one
        self.table = table
        self.lower = np.asarray(lower, dtype=float)
        self.upper = np.asarray(upper, dtype=float)
        rng = np.random.default_rng(PROBE_SEED)
        probes = rng.uniform(np.maximum(self.lower, -math.pi), np.minimum(self.upper, math.pi),
                             (PROBES, 7))  # fmt: skip
        from kin.batch_fk import batch_forward_kinematics

        poses = batch_forward_kinematics(table, probes)
        best: tuple | None = None
        failures = []
        ends = {}
        self.ideal: SevenDofIK | None = None
        self.fold_margin = 0.0
        self._held: HeldTwin | None | bool = False  # not yet made (:meth:`_held_twin`)
        for free in (6, 0):
            try:
                structure, _, flips = recognise_turned(six_r_table(table, free))
            except StructureError as err:
                failures.append(err.mismatch)
                continue
            ends[free] = held_end(table, free, structure, flips)
            self._use(ends[free])
            recovered = self._recovered(poses, probes)
            score = (not isinstance(structure, General6R), recovered, free == 6)
            if best is None or score > best[0]:
                best = (score, ends[free])
        if best is None:
            raise StructureError(table.name, "general 7R", "; ".join(failures))
        self._use(best[1])
        snapped = ideal_form(table, self.lower.tolist(), self.upper.tolist())
        if snapped is not None and 0 in ends:  # the snapped arm's form, if it recovers
            self._use(ends[0])
            self.ideal, self.fold_margin = snapped[0], FOLD_PER_METER * snapped[1]
            if self._recovered(poses, probes) < PROBES:
                self.ideal = None
                self._use(best[1])

    def _use(self, end: HeldEnd) -> None:
        self.end = end
        self.free = end.free
        self.structure = end.structure

    def _recovered(self, poses: np.ndarray, probes: np.ndarray) -> int:
        """How many joint vectors ``probes`` (k, 7) [rad] are among their poses' branches."""
        found = self.branches(poses, probes[:, self.free])
        gap = np.abs(np.remainder(found - probes[:, None, :] + math.pi, _TWO_PI) - math.pi)
        return int((np.nan_to_num(gap, nan=np.inf).max(axis=2).min(axis=1) < 1e-6).sum())

    @property
    def costly(self) -> bool:
        """Whether a solve takes the general elimination (about 1 ms) rather than a family's.

        The numeric pipeline then asks this form after its seed-table stage, not first
        (damped Newton answers such arms in a fraction of that), and ``solve_batch`` leaves it
        to the solver's stages.
        """
        return isinstance(self.structure, General6R)

    def prepare(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray | None:
        """The target as ``T_world_tool`` (4, 4), or None for a position (full poses only)."""
        if rotation is None:
            return None
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = rotation, position
        return T

    def branches(self, targets: np.ndarray, values: np.ndarray, exact: bool = False) -> np.ndarray:
        """Every branch (n, B, 7) [rad] of targets (n, 4, 4) at free-joint values (n,), NaN rows.

        ``exact``: by the 6R closed form (:attr:`structure`) even where :attr:`ideal` answers.
        """
        values = np.asarray(values, dtype=float)
        if self.ideal is not None and not exact and values.shape[0]:
            if (targets == targets[0]).all():  # one target at many values (a scan): compiled
                twin = self._held_twin()
                found = (
                    None
                    if twin is None
                    else held_rows_at(twin, self.fold_margin, self.end, targets[0], values)
                )
                if found is not None:
                    return found
        sub = self.end.targets(targets, values)
        if self.ideal is not None and not exact:
            q6 = held_branches(self.ideal, self.fold_margin, self.end, targets, values, sub)
        else:
            q6 = self.end.six_r(sub)
        return self.end.joint_vectors(q6, values)

    def _held_twin(self) -> HeldTwin | None:
        """:func:`~.ideal_7r.held_twin` of :attr:`ideal` on this table, made on first use."""
        if self._held is False:
            assert self.ideal is not None
            self._held = held_twin(self.ideal, self.table)
        return self._held  # type: ignore[return-value]

    def branches_at(
        self,
        position: np.ndarray,
        rotation: np.ndarray | None,
        values: np.ndarray,
        exact: bool = False,
    ) -> np.ndarray | None:
        """Every branch (G, B, 7) [rad] of a tool pose at free-joint values (G,), NaN rows.

        Limits ignored; None for a position (full poses only). ``exact``: as :meth:`branches`.
        """
        target = self.prepare(position, rotation)
        if target is None:
            return None
        return self.branches(np.broadcast_to(target, (values.shape[0], 4, 4)), values, exact)

    def first_each(self, targets: np.ndarray, starts: np.ndarray) -> np.ndarray:
        """Per target its start's branch, at the start's free value, inside the limits (no scan).

        One 6R solve of all N targets: :func:`.free_value_scan.first_each`.

        Args:
            targets: ``T_world_tool`` (N, 4, 4).
            starts: One start joint vector per target [rad] (N, 7).

        Returns:
            (N, 7) [rad]: the branch nearest each start, NaN rows where there is none (or the
            start is not finite).
        """
        return free_value_scan.first_each(self, targets, starts)

    def first(
        self,
        target: np.ndarray | None,
        starts: np.ndarray,
        out: np.ndarray,
        step: float = 0.0,
        compiled: bool = True,
    ) -> int:
        """The first start from which a branch inside the limits reaches the target.

        Each start at its own free value, or scanned outward from there by ``step``
        (:func:`.free_value_scan.first`).

        Args:
            target: :meth:`prepare` of the target (None: no start reaches it).
            starts: Start joint vectors [rad] (k, 7); a row with a value that is not finite is
                skipped.
            out: Receives the branch nearest that start [rad] (7,).
            step: Free-joint scan step [rad] (0: no scan; finer than
                :data:`~.free_value_scan.SCAN_STEP`: nothing).
            compiled: Unused (no compiled twin).

        Returns:
            The index of that start, or -1 (``out`` untouched).
        """
        if target is None:
            return -1
        return free_value_scan.first(self, target, starts, out, step)
