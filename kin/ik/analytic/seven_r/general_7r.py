"""Closed form of any 7R arm for chosen values of a free end joint, over the 6R closed forms.

Holding joint 1 or joint 7 of a seven-joint revolute arm leaves a 6R arm whose rows do not depend
on the held value: only the target moves, ``T' = (B A_1(q_1))^-1 T`` (joint 1 held, ``B`` the
base) or ``T' = T (A_7(q_7) M)^-1`` (joint 7 held, ``M`` the tool), with ``A_i`` the row's DH
transform. That 6R arm is recognised once by the closed-form registry
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
and a scan of the free joint is one batched solve of its values (nearest to the start first).
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ...exceptions import StructureError
from ...limit_rule import nearest_copies
from ..closed_form_structure import ClosedFormStructure
from ..registry import recognise_turned
from ..six_r._general_6r_chain import BRANCHES, chain_transforms, polish
from ..six_r.general_6r import KEEP_TOL, General6R
from .ideal_7r import ideal_form
from .seven_dof import SevenDofIK

#: Sampled joint vectors by which the free joint is chosen, and their seed.
PROBES = 16
PROBE_SEED = 3
#: The coarsest scan step [rad]: a finer one repeats a scan at this step value for value, each a
#: 6R solve, so it is not run (the first free-joint scan of a call is at this step or coarser).
SCAN_STEP = 0.05
#: Values of a scan solved in the first batch after the start's own (the nearest ones).
NEAR_VALUES = 16
#: A held value where an equation of the snapped arm (:attr:`General7RIK.ideal`) is nearer a
#: double root than this times its deviation [1/m] (:func:`~.subproblems.fold_distance`) is
#: solved by the 6R closed form (Kinova Gen3: deviation 0.35 mm, branches lost up to 0.0034).
FOLD_PER_METER = 60.0
_TWO_PI = 2.0 * math.pi


def dh_transforms(table: DHTable, row: int, values: np.ndarray) -> np.ndarray:
    """The DH transforms (n, 4, 4) of one row (0-based) at joint values ``values`` (n,) [rad]."""
    r = table.rows[row]
    theta = r.theta + np.asarray(values, dtype=float)
    ct, st = np.cos(theta), np.sin(theta)
    ca, sa = math.cos(r.alpha), math.sin(r.alpha)
    out = np.zeros((theta.size, 4, 4))
    out[:, 3, 3] = 1.0
    if table.convention == "standard":  # Rz(theta) Tz(d) Tx(a) Rx(alpha)
        out[:, 0, 0], out[:, 0, 1], out[:, 0, 2], out[:, 0, 3] = ct, -st * ca, st * sa, r.a * ct
        out[:, 1, 0], out[:, 1, 1], out[:, 1, 2], out[:, 1, 3] = st, ct * ca, -ct * sa, r.a * st
        out[:, 2, 1], out[:, 2, 2], out[:, 2, 3] = sa, ca, r.d
    else:  # Rx(alpha) Tx(a) Rz(theta) Tz(d)
        out[:, 0, 0], out[:, 0, 1], out[:, 0, 3] = ct, -st, r.a
        out[:, 1, 0], out[:, 1, 1], out[:, 1, 2], out[:, 1, 3] = st * ca, ct * ca, -sa, -r.d * sa
        out[:, 2, 0], out[:, 2, 1], out[:, 2, 2], out[:, 2, 3] = st * sa, ct * sa, ca, r.d * ca
    return out


def _inverse(T: np.ndarray) -> np.ndarray:
    """Inverses of rigid transforms (..., 4, 4)."""
    out = np.zeros_like(T)
    R = np.swapaxes(T[..., :3, :3], -1, -2)
    out[..., :3, :3] = R
    out[..., :3, 3] = -(R @ T[..., :3, 3:4])[..., 0]
    out[..., 3, 3] = 1.0
    return out


def _six_r_table(table: DHTable, free: int) -> DHTable:
    """The 6R arm left when end joint ``free`` (0 or 6) is held: its rows do not depend on it."""
    import dataclasses

    eye = np.eye(4)
    if free == 6:
        return dataclasses.replace(table, rows=table.rows[:6], T_last_tool=eye, name=table.name)
    return dataclasses.replace(table, rows=table.rows[1:], T_world_base=eye, name=table.name)


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
        ideal: The snapped arm's form (:mod:`.ideal_7r`) whose branches, polished with joint 1
            held, answer in place of ``structure`` (joint 1 is then the held one), or None.
        fold_margin: Within this of a double root of ``ideal`` (its
            :func:`~.subproblems.fold_distance`), ``structure`` answers the value.

    Raises:
        StructureError: Not seven revolute joints, or no 6R closed form fits the arm left by
            holding joint 1 or joint 7.
    """

    #: No compiled twin: the 6R closed forms it calls are batched in NumPy (or compiled).
    compiled_twin: ClassVar[bool] = False

    def __init__(self, table: DHTable, lower: npt.ArrayLike, upper: npt.ArrayLike):
        if table.dof != 7 or any(row.joint_type != "revolute" for row in table.rows):
            raise StructureError(table.name, "general 7R", "it needs seven revolute joints")
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
        fits = {}
        self.ideal: SevenDofIK | None = None
        self.fold_margin = 0.0
        for free in (6, 0):
            try:
                structure, _, flips = recognise_turned(_six_r_table(table, free))
            except StructureError as err:
                failures.append(err.mismatch)
                continue
            fits[free] = structure, flips
            self._use(free, structure, flips)
            found = self.branches(poses, probes[:, free])
            gap = np.abs(np.remainder(found - probes[:, None, :] + math.pi, _TWO_PI) - math.pi)
            recovered = int((np.nan_to_num(gap, nan=np.inf).max(axis=2).min(axis=1) < 1e-6).sum())
            score = (not isinstance(structure, General6R), recovered, free == 6)
            if best is None or score > best[0]:
                best = (score, free, structure, flips)
        if best is None:
            raise StructureError(table.name, "general 7R", "; ".join(failures))
        self._use(*best[1:])
        snapped = ideal_form(table, self.lower.tolist(), self.upper.tolist())
        if snapped is not None and 0 in fits:  # the snapped arm's form, if it recovers
            kept = self.free, self.structure, self._flips
            self._use(0, *fits[0])
            self.ideal, self.fold_margin = snapped[0], FOLD_PER_METER * snapped[1]
            found = self.branches(poses, probes[:, 0])
            gap = np.abs(np.remainder(found - probes[:, None, :] + math.pi, _TWO_PI) - math.pi)
            if not (np.nan_to_num(gap, nan=np.inf).max(axis=2).min(axis=1) < 1e-6).all():
                self.ideal = None
                self._use(*kept)

    def _use(self, free: int, structure: ClosedFormStructure, flips: np.ndarray | None) -> None:
        self.free = free
        self.structure = structure
        self._flips = flips
        self._others = [i for i in range(7) if i != free]
        table = self.table
        self._outer = table.T_world_base if free == 0 else table.T_last_tool
        self._chain = chain_transforms(_six_r_table(table, free))[0]

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
        held = dh_transforms(self.table, self.free, values)
        if self.free == 6:
            sub = targets @ _inverse(held @ self._outer)
        else:
            sub = _inverse(self._outer @ held) @ targets
        if self.ideal is not None and not exact:
            q6 = self._held(targets, np.asarray(values, dtype=float), sub)
        else:
            q6 = self._six_r(sub)
        out = np.empty(q6.shape[:2] + (7,))
        out[..., self._others] = q6
        out[..., self.free] = np.asarray(values, dtype=float)[:, None]
        return out

    def _held(self, targets: np.ndarray, values: np.ndarray, sub: np.ndarray) -> np.ndarray:
        """The snapped arm's branches (n, 16, 6) [rad] polished with the free joint held, NaN rows.

        Its branches at each target's value (:attr:`ideal`, limits ignored), the other six
        joints moved onto the 6R left (targets ``sub`` (n, 4, 4): :meth:`branches`) by
        :func:`~..six_r._general_6r_chain.polish`, kept within :data:`KEEP_TOL`, in their order.
        A value where one of the snapped arm's equations is within :attr:`fold_margin` of a
        double root (:func:`~.subproblems.fold_distance`: the true arm may have a pair of
        branches more or fewer there) is solved by the 6R closed form instead.
        """
        assert self.ideal is not None
        n = values.shape[0]
        folds = np.full(n, np.inf)
        found = np.full((n, BRANCHES, 7), np.nan)
        for k, T in enumerate(targets):
            at = self.ideal.branches_at(T[:3, 3], T[:3, :3], values[k : k + 1], folds[k : k + 1])
            assert at is not None  # a full pose
            found[k, :8] = at[0]
        doubt = folds < self.fold_margin
        found[doubt] = np.nan
        pose, branch = np.nonzero(np.isfinite(found).all(axis=2))
        u, error = polish(self._chain, found[pose, branch][:, self._others], sub[pose])
        keep = error <= KEEP_TOL
        out = np.full((n, BRANCHES, 6), np.nan)
        pose, u = pose[keep], u[keep]
        slot = np.zeros(pose.size, dtype=int)  # each kept row's place among its pose's
        if pose.size:
            start = np.flatnonzero(np.r_[True, pose[1:] != pose[:-1]])
            slot = np.arange(pose.size) - np.repeat(start, np.diff(np.r_[start, pose.size]))
        out[pose, slot] = u
        if doubt.any():
            out[doubt] = self._six_r(sub[doubt])
        return out

    def _six_r(self, sub: np.ndarray) -> np.ndarray:
        """The 6R closed form's branches (n, 16, 6) [rad] of targets ``sub`` (n, 4, 4), NaN rows."""
        q6 = self.structure.solve_batch(sub[:, :3, 3], sub[:, :3, :3])
        return q6 if self._flips is None else q6 * self._flips

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

    def _nearest_inside(self, branches: np.ndarray, start: np.ndarray) -> np.ndarray | None:
        """The branch (7,) inside the limits nearest ``start``, or None.

        Each joint goes to its 2 pi copy inside the limits nearest the start's value (the limit
        rule, :func:`kin.ik.limit_rule.nearest_copies`).
        """
        chosen, inside = nearest_copies(branches, start, self.lower, self.upper)
        ok = inside.all(axis=-1)
        if not ok.any():
            return None
        rows = chosen[ok]
        return rows[((rows - start) ** 2).sum(axis=1).argmin()]

    def first_each(self, targets: np.ndarray, starts: np.ndarray) -> np.ndarray:
        """Per target its start's branch, at the start's free value, inside the limits (no scan).

        The batched :meth:`first` of one start per target: one 6R solve of all N targets.

        Args:
            targets: ``T_world_tool`` (N, 4, 4).
            starts: One start joint vector per target [rad] (N, 7).

        Returns:
            (N, 7) [rad]: the branch nearest each start, NaN rows where there is none (or the
            start is not finite).
        """
        starts = np.asarray(starts, dtype=float).reshape(-1, 7)
        out = np.full(starts.shape, np.nan)
        rows = np.flatnonzero(np.isfinite(starts).all(axis=1) & np.isfinite(targets).all((1, 2)))
        if not rows.size:
            return out
        clipped = np.clip(starts[rows], self.lower, self.upper)
        branches = self.branches(targets[rows], clipped[:, self.free])
        for k, row in enumerate(rows.tolist()):
            found = self._nearest_inside(branches[k], clipped[k])
            if found is not None:
                out[row] = found
        return out

    def first(
        self,
        target: np.ndarray | None,
        starts: np.ndarray,
        out: np.ndarray,
        step: float = 0.0,
        compiled: bool = True,
    ) -> int:
        """The first start from which a branch inside the limits reaches the target.

        A start keeps its free joint's value (clipped into its limits); with ``step > 0`` and no
        branch there, the free joint is scanned outward, ``v +- step``, ``v +- 2 step``, ...,
        inside its limits, solved in batches (the nearest :data:`NEAR_VALUES` first), and the
        nearest value with a branch is taken. A step finer than :data:`SCAN_STEP` scans nothing.

        Args:
            target: :meth:`prepare` of the target (None: no start reaches it).
            starts: Start joint vectors [rad] (k, 7); a row with a value that is not finite is
                skipped.
            out: Receives the branch nearest that start [rad] (7,).
            step: Free-joint scan step [rad] (0: no scan).
            compiled: Unused (no compiled twin).

        Returns:
            The index of that start, or -1 (``out`` untouched).
        """
        if target is None:
            return -1
        starts = np.asarray(starts, dtype=float).reshape(-1, 7)
        finite = np.isfinite(starts).all(axis=1)
        clipped = np.clip(starts, self.lower, self.upper)
        if not step > 0.0:  # every start at its own free value: one batched solve
            rows = np.flatnonzero(finite)
            if not rows.size:
                return -1
            targets = np.broadcast_to(target, (rows.size, 4, 4))
            branches = self.branches(targets, clipped[rows, self.free])
            for k, row in enumerate(rows.tolist()):
                found = self._nearest_inside(branches[k], clipped[row])
                if found is not None:
                    out[:] = found
                    return row
            return -1
        if step < SCAN_STEP:
            return -1
        for row in np.flatnonzero(finite).tolist():
            found = self._scan(target, clipped[row], step)
            if found is not None:
                out[:] = found
                return row
        return -1

    def _scan(self, target: np.ndarray, start: np.ndarray, step: float) -> np.ndarray | None:
        """The branch nearest ``start`` at the free value nearest its own that has one, or None."""
        low, high = self.lower[self.free], self.upper[self.free]
        value = start[self.free]
        count = int(max(value - low, high - value) // step)
        ring = np.arange(1, count + 1) * step
        values = np.concatenate(([value], np.stack((value + ring, value - ring), 1).ravel()))
        values = values[(values >= low) & (values <= high)]
        for chunk in (values[:1], values[1 : NEAR_VALUES + 1], values[NEAR_VALUES + 1 :]):
            if not chunk.size:
                continue
            branches = self.branches(np.broadcast_to(target, (chunk.size, 4, 4)), chunk)
            for k in range(chunk.size):
                found = self._nearest_inside(branches[k], start)
                if found is not None:
                    return found
        return None
