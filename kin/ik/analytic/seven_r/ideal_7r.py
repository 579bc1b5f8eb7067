"""A special 7R closed form near a general 7R arm: the candidates of :class:`.general_7r.General7RIK`.

Makers' URDFs round and drift: Kinova's Gen3 writes 1.5708 for pi/2 and puts its wrist axes
0.35 mm apart, so no special form fits it and each free-joint value costs a general 6R
elimination (:mod:`..six_r.general_6r`). Snapped (:func:`ideal_form`: the twists and tiny lengths
of :func:`~kin.ik.analytic.idealised.idealise`, then every length below :data:`IDEAL_LENGTH`),
the arm may be humanoid7's (:class:`~.seven_dof.SevenDofIK`, joint 1 free), whose branches at a
free value are closed form (and compiled: ``held_rows``, ``kin/_native/ik/analytic/seven_r/_held7.h``,
bound by :func:`held_twin`; :func:`held_rows_at` answers a target at many values through it).
:class:`~.general_7r.General7RIK` then holds joint 1 and polishes each of those branches onto the
true arm with joint 1 fixed (:func:`held_branches`: Newton on the 6R left,
:func:`~kin.ik.analytic.six_r._general_6r_chain.polish`), as ssik's ``srs_polished`` does for such
arms; a value where the snapped arm is near a double root (within a margin proportional to the
deviation: a pair of branches the true arm has there may be missing) is solved by the 6R
elimination instead. It keeps this route only when it recovers the arm's sampled joint vectors
from their poses (:meth:`~.general_7r.General7RIK.__init__`); the tests hold its branches to the
elimination's at every value (tests/ik/analytic/seven_r/test_ik_ideal_7r.py). Lengths [m], angles [rad].
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np

from dh2urdf import DHTable
from kin.batch_fk import batch_forward_kinematics

from ...exceptions import StructureError
from ..idealised import FK_TOLERANCE, idealise
from ..six_r._general_6r_chain import BRANCHES, polish
from ..six_r.general_6r import KEEP_TOL
from ..structure import seven_dof
from ..twin_support import chain_block
from .held_end import HeldEnd
from .seven_dof import SevenDofIK

#: Largest ``|a|`` or ``|d|`` snapped to zero [m] (the tool then strays at most
#: :data:`~kin.ik.analytic.idealised.FK_TOLERANCE` over sampled joint vectors, or no form).
IDEAL_LENGTH = 1e-3
#: Sampled joint vectors of the tool's deviation check, and their seed.
SAMPLES = 256
SAMPLE_SEED = 0
#: A held value where an equation of the snapped arm is nearer a double root than this times its
#: deviation [1/m] (:func:`~.subproblems.fold_distance`) is solved by the 6R closed form (Kinova
#: Gen3: deviation 0.35 mm, branches lost up to 0.0034).
FOLD_PER_METER = 60.0


def ideal_table(table: DHTable) -> tuple[DHTable, float] | None:
    """The table with its twists and lengths below :data:`IDEAL_LENGTH` snapped, and its deviation.

    The deviation [m]: the largest distance between the two tools over sampled joint vectors.
    None when nothing is snapped, or the deviation exceeds
    :data:`~kin.ik.analytic.idealised.FK_TOLERANCE`.
    """
    snapped = idealise(table)
    start = table if snapped is None else snapped.table
    rows = tuple(
        dataclasses.replace(
            row,
            a=0.0 if abs(row.a) < IDEAL_LENGTH else row.a,
            d=0.0 if row.joint_type == "revolute" and abs(row.d) < IDEAL_LENGTH else row.d,
        )
        for row in start.rows
    )
    if snapped is None and rows == table.rows:
        return None
    ideal = dataclasses.replace(start, rows=rows)
    rng = np.random.default_rng(SAMPLE_SEED)
    q = rng.uniform(np.maximum(table.lower, -np.pi), np.minimum(table.upper, np.pi),
                    (SAMPLES, table.dof))  # fmt: skip
    true = batch_forward_kinematics(table, q)[:, :3, 3]
    near = batch_forward_kinematics(ideal, q)[:, :3, 3]
    deviation = float(np.linalg.norm(true - near, axis=1).max())
    return (ideal, deviation) if deviation <= FK_TOLERANCE else None


def ideal_form(
    table: DHTable, lower: Sequence[float], upper: Sequence[float]
) -> tuple[SevenDofIK, float] | None:
    """humanoid7's form of the snapped table (:func:`ideal_table`) and its deviation [m], or None.

    Args:
        table: A forward 7R table (every direction 1) that no special form fits as it is.
        lower: Lower joint limits [rad] (7).
        upper: Upper joint limits [rad] (7).
    """
    if table.dof != 7 or any(row.joint_type != "revolute" for row in table.rows):
        return None
    snapped = ideal_table(table)
    if snapped is None:
        return None
    try:
        return SevenDofIK(seven_dof(snapped[0]), lower, upper), snapped[1]
    except StructureError:
        return None


def held_branches(
    ideal: SevenDofIK,
    fold_margin: float,
    end: HeldEnd,
    targets: np.ndarray,
    values: np.ndarray,
    sub: np.ndarray,
) -> np.ndarray:
    """The snapped arm's branches (n, 16, 6) [rad] polished with joint 1 held, NaN rows.

    The branches of ``ideal`` (:func:`ideal_form`, limits ignored) at each target's value, the
    other six joints moved onto the true arm's 6R left (``end``, joint 1 held) by
    :func:`~..six_r._general_6r_chain.polish`, kept within
    :data:`~..six_r.general_6r.KEEP_TOL`, in their order. A value where one of the snapped
    arm's equations is within ``fold_margin`` [m] of a double root
    (:func:`~.subproblems.fold_distance`: the true arm may have a pair of branches more or
    fewer there) is solved by the 6R closed form (:meth:`~.held_end.HeldEnd.six_r`) instead.

    Args:
        ideal: The snapped arm's form.
        fold_margin: :data:`FOLD_PER_METER` times the snapped arm's deviation [m].
        end: The true arm with joint 1 held.
        targets: ``T_world_tool`` (n, 4, 4).
        values: Joint-1 values [rad] (n,).
        sub: ``end``'s targets (:meth:`~.held_end.HeldEnd.targets`) (n, 4, 4).
    """
    n = values.shape[0]
    folds = np.full(n, np.inf)
    found = np.full((n, BRANCHES, 7), np.nan)
    if n and (targets == targets[0]).all():  # one target at many values (a scan): one frame
        at = ideal.branches_at(targets[0, :3, 3], targets[0, :3, :3], values, folds)
        assert at is not None  # a full pose
        found[:, :8] = at
    else:
        for k, T in enumerate(targets):
            at = ideal.branches_at(T[:3, 3], T[:3, :3], values[k : k + 1], folds[k : k + 1])
            assert at is not None  # a full pose
            found[k, :8] = at[0]
    doubt = folds < fold_margin
    found[doubt] = np.nan
    pose, branch = np.nonzero(np.isfinite(found).all(axis=2))
    u, error = polish(end.chain, found[pose, branch][:, end.others], sub[pose])
    keep = error <= KEEP_TOL
    out = np.full((n, BRANCHES, 6), np.nan)
    pose, u = pose[keep], u[keep]
    slot = np.zeros(pose.size, dtype=int)  # each kept row's place among its pose's
    if pose.size:
        start = np.flatnonzero(np.r_[True, pose[1:] != pose[:-1]])
        slot = np.arange(pose.size) - np.repeat(start, np.diff(np.r_[start, pose.size]))
    out[pose, slot] = u
    if doubt.any():
        out[doubt] = end.six_r(sub[doubt])
    return out


@dataclasses.dataclass(frozen=True)
class HeldTwin:
    """The twin's ``held_rows`` bound to a snapped arm on its true table (:func:`held_twin`).

    Attributes:
        call: ``held_rows`` of ``kin/_native/ik/analytic/seven_r/_held7.h``.
        params: The snapped form's parameters without limits (joints in ``[-pi, pi]``).
        frames: A Seed block of the true table with the snapped form's frames (its targets).
        chain: A Seed block of the true table alone (the polish's chain).
    """

    call: Callable[..., int]
    params: bytes
    frames: bytes
    chain: bytes


@dataclasses.dataclass(frozen=True)
class _Packed:
    """A pose as the twins read it: position [m] then ``R_world_tool`` row-major, 12 float64."""

    _packed: bytes


def held_twin(ideal: SevenDofIK, table: DHTable) -> HeldTwin | None:
    """``held_rows`` bound to ``ideal`` (:func:`ideal_form`) on ``table``, or None (no twin).

    Args:
        ideal: The snapped arm's form.
        table: The true arm's forward table (every direction 1), the general form's.
    """
    twin = ideal.twin
    if twin is None or not hasattr(twin, "held_rows"):
        return None
    frames = chain_block(table, twin, ideal.seed_frames())
    chain = chain_block(table, twin)
    if frames is None or chain is None:
        return None
    unlimited = SevenDofIK(ideal.structure, [-math.pi] * 7, [math.pi] * 7)
    return HeldTwin(twin.held_rows, unlimited.c_params.tobytes(), frames, chain)


def held_rows_at(
    twin: HeldTwin, fold_margin: float, end: HeldEnd, target: np.ndarray, values: np.ndarray
) -> np.ndarray | None:
    """The branches (n, 16, 7) [rad] of one target at joint-1 values (n,), NaN rows, compiled.

    What :func:`held_branches` then :meth:`~.held_end.HeldEnd.joint_vectors` give for the
    target repeated at every value (the rows of a value in the same order; the polish in C,
    equal up to rounding): the twin polishes the snapped arm's branches; a value it leaves (near
    a double root: count -1) is solved by the 6R closed form, as there. None when the target is
    not a finite pose.

    Args:
        twin: :func:`held_twin` of the snapped arm.
        fold_margin: :data:`FOLD_PER_METER` times the snapped arm's deviation [m].
        end: The true arm with joint 1 held.
        target: ``T_world_tool`` (4, 4).
        values: Joint-1 values [rad] (n,).
    """
    values = np.ascontiguousarray(values, dtype=float)
    g = values.shape[0]
    rows, counts = np.empty((g * 8, 7)), np.empty(g)
    pose = _Packed(np.concatenate((target[:3, 3], target[:3, :3].ravel())).tobytes())
    total = twin.call(twin.params, twin.frames, twin.chain, pose, values, 0, KEEP_TOL, fold_margin,
                      rows, counts)  # fmt: skip
    if total < 0:
        return None
    each = counts.astype(int)
    kept = np.maximum(each, 0)
    out = np.full((g, BRANCHES, 7), np.nan)
    out[..., 0] = values[:, None]  # every slot holds its value, a row without branch too
    slot = np.arange(total) - np.repeat(np.cumsum(kept) - kept, kept)  # a row's place at its value
    out[np.repeat(np.arange(g), kept), slot] = rows[:total]
    doubt = each < 0
    if doubt.any():
        held = values[doubt]
        sub = end.targets(np.broadcast_to(target, (held.size, 4, 4)), held)
        out[doubt] = end.joint_vectors(end.six_r(sub), held)
    return out
