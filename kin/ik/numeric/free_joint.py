"""Stage 0 of the numeric pipeline: the closed form with a free joint, when the arm has one.

:func:`free_joint_closed_form` (:mod:`.free_joint_form`) picks the arm's closed form, first that fits:
:class:`~kin.ik.analytic.seven_r.seven_dof.SevenDofIK` (humanoid7's structure: joint 1 free, full poses
and positions) and :class:`~kin.ik.analytic.seven_r.spherical_shoulder7.SphericalShoulder7RIK` (axes 1-3
and 5-6 meeting: Panda, xArm7; joint 7 free, full poses only), then
:class:`~kin.ik.analytic.seven_r.general_7r.General7RIK` (any other 7R arm: joint 1 or 7 held,
the 6R closed forms, the general elimination among them, for the rest; full poses only). All
three meet :class:`FreeJointClosedForm`:
the free joint from a start, the other joints in closed form, the branch nearest the start.
Starts: the caller's seed, then the seed-table samples near the target. When a start's free joint
gives no branch inside the limits, the seed and the first sample scan it outward from there
(coarse to fine): the answer keeps the start's free joint as nearly as the target allows. The
judge (:mod:`kin.ik.judge`) measures every answer. Most targets end here, in tens of microseconds.

With ``NumericIK.near_seed``, a seed whose tool is near the target (:func:`.starts.seed_leash`: one
forward kinematics) expects
the answer near it, and keeping its free joint may not give that: at that value the branch near
the seed can be outside a limit, or far (the other joints make up for the free joint's share of
the move). Its closed-form branch is taken when within ``seed_near`` of it; else damped Newton
runs from the seed first, moving every joint, and the nearer verified answer is returned.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable, Iterator, Sequence
from operator import le, sub
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from dh2urdf import DHTable

from ..analytic.idealised import polish
from ..analytic.seven_r.seven_dof import SevenDofIK
from ..analytic.seven_r.spherical_shoulder7 import SphericalShoulder7RIK
from ..analytic.twin_support import ScanJob, call_first_many, chain_block
from ..result import IKResult, IKSolution
from .free_joint_form import FreeJointClosedForm as FreeJointClosedForm
from .free_joint_form import free_joint_closed_form as free_joint_closed_form
from .seed_table import nearest_first
from .starts import DAMPED_NEWTON, seed_leash

if TYPE_CHECKING:
    from .context import NumericContext
    from .search import Search

#: :attr:`IKResult.method` of this stage.
METHOD = "closed_form_free_joint"

#: Label of the caller's seed in the messages.
SEED = "the given seed"
#: Message of an answer of the closed form with the seed's free joints.
FROM_SEED = f"closed form with the free joints of {SEED}"


def compiled_seeded(
    closed: FreeJointClosedForm | None,
    table: DHTable,
    base_origin: Sequence[float],
    reach: float,
    steps: Sequence[float],
    name: str,
) -> Callable[..., Any] | None:
    """This stage from the caller's seed in one compiled call, or None where it does not apply.

    The twin's ``seeded`` (``kin/_native/ik/analytic/seven_r/_seeded7.h``) does what
    :func:`solve_free_joint` does with the seed: the target brought to the structure's frames,
    the closed form from the seed for each scan step in turn, each answer measured by the
    table's DH product (not Pinocchio's FK: the same chain, compared with it in the tests), the
    first within the tolerances taken. Bound to the arm's blocks, it is called as
    ``(target, seed, position_tol, rotation_tol, start, out)`` (the target's packed values, or
    its ``position`` and ``rotation``: None for a position) and returns
    the :class:`~kin.ik.result.IKResult` this stage would (its solution's ``q`` is ``out``, a
    float64 (7,); ``time`` from ``start``, a ``time.perf_counter()`` [s]), False (none: go on
    from the samples, :attr:`.search.Search.seed_scanned`) or None (not taken: the pipeline
    from its start).

    Applies to the two special 7R forms with their twin built (humanoid7's, the spherical
    shoulder's) on a table of forward-turning revolute rows; not to an idealised table (its
    answers need a polish), a table with reversed joints or the general 7R form.

    Args:
        closed: The arm's free-joint closed form (on ``table`` itself), or None.
        table: The arm's DH table.
        base_origin: The table's base origin in the world [m]: with ``reach``, a target farther
            than ``reach`` [m] from it is not taken.
        reach: Bound of the tool's distance from the base origin [m].
        steps: The free joint's scan steps [rad], coarse to fine.
        name: The pipeline's name (:attr:`IKResult.solver`).
    """
    block = seed_block(closed, table, base_origin, reach)
    if block is None:
        return None
    closed = cast("SevenDofIK | SphericalShoulder7RIK", closed)
    steps = tuple(float(step) for step in steps)
    return functools.partial(
        closed.twin.seeded,
        closed.c_params.tobytes(),
        block,
        steps,
        IKSolution,
        IKResult,
        name,
        FROM_SEED,
        METHOD,
        time.perf_counter,
    )


def seed_block(
    closed: FreeJointClosedForm | None,
    table: DHTable,
    base_origin: Sequence[float],
    reach: float,
) -> bytes | None:
    """The twin's Seed block (``SEED_LAYOUT``) of ``closed`` on ``table``, or None.

    None where the compiled seeded calls do not apply (see :func:`compiled_seeded`).
    """
    if not isinstance(closed, (SevenDofIK, SphericalShoulder7RIK)) or closed.twin is None:
        return None
    return chain_block(table, closed.twin, closed.seed_frames(), base_origin, reach)


class SeededMany:
    """The batch's closed-form stage in compiled code: N world targets, each from its own start.

    The twin's ``seeded_many`` (``kin/_native/ik/analytic/seven_r/_seeded7.h``) brings each target to
    the structure's frames, takes the first scan step whose closed form from the start gives a
    branch, measures it with the table's DH product (as :func:`compiled_seeded`) and keeps it
    when within the tolerances and inside the limits; in threads, without the interpreter lock
    (:func:`~kin.ik.analytic.seven_r.subproblems.call_first_many`). Built by
    :func:`compiled_seeded_many`.
    """

    def __init__(
        self, twin: Any, params: bytes, block: bytes, lower: np.ndarray, upper: np.ndarray
    ):
        self._call = twin.seeded_many
        self._head = (params, block, np.concatenate((lower, upper)).astype(float))

    def start(
        self,
        positions: np.ndarray,
        rotations: np.ndarray | None,
        starts: np.ndarray,
        steps: Sequence[float],
        tolerance: float,
    ) -> ScanJob:
        """Start the stage on targets (N, 3) [m] with rotations (N, 3, 3) or None (points).

        Returns:
            The job; its ``result()`` is (N, 9): per row q (7) [rad], the position error [m]
            and the rotation error [rad] (NaN for a point), or NaN where no branch was kept
            (none, off by ``tolerance`` [m] / [rad] or more, or outside the limits).
        """
        n = positions.shape[0]
        mode, targets = 1, positions
        if rotations is not None:
            mode, targets = 0, np.concatenate((positions, rotations.reshape(n, 9)), 1)
        head = (*self._head, mode, np.array([tolerance, tolerance]))
        job = call_first_many(self._call, head, targets, starts, steps, later=True, width=9)
        return cast("ScanJob", job)


def compiled_seeded_many(
    closed: FreeJointClosedForm | None,
    table: DHTable,
    lower: np.ndarray,
    upper: np.ndarray,
    base_origin: Sequence[float] = (0.0, 0.0, 0.0),
    reach: float = math.inf,
) -> SeededMany | None:
    """The batch's closed-form stage in compiled code (:class:`SeededMany`), or None.

    None where it does not apply (as :func:`compiled_seeded`). The joint limits ``lower``,
    ``upper`` [rad] are the judge's; a target farther than ``reach`` [m] from ``base_origin``
    (the world frame) gets no answer there, without a scan.
    """
    block = seed_block(closed, table, base_origin, reach)
    twin = getattr(closed, "twin", None)
    if block is None or not hasattr(twin, "seeded_many"):
        return None
    params = cast("SevenDofIK | SphericalShoulder7RIK", closed).c_params.tobytes()
    return SeededMany(twin, params, block, lower, upper)


def solve_free_joint(ik: NumericContext, search: Search) -> IKResult | None:
    """The closed form from the caller's seed, then from seed-table samples; None if none verifies.

    With ``near_seed`` (settings), a seed whose tool is near the target (:func:`.starts.seed_leash`)
    expects the answer near it: :func:`_near_seed` first. A target with a posture preference
    skips this stage (the closed form does not weigh it).
    """
    closed = ik.closed_form
    target = search.target
    if closed is None or target.posture is not None:
        return None
    prepared = closed.prepare(target.position, target.rotation)
    if prepared is None:  # a target this closed form does not take
        return None
    position = target.position.tolist()
    rotation = None if target.rotation is None else target.rotation.ravel().tolist()
    out = np.empty(7)
    seed = search.seed
    if seed is not None and not search.seed_scanned:
        leash = seed_leash(ik, search, seed) if ik.settings.near_seed else None
        if leash is not None:
            done = _near_seed(ik, search, closed, prepared, seed, leash, out, position, rotation)
            if done is not None:
                return done
        # The seed's free joints, scanned outward (coarse, then fine) when they give no branch.
        starts = seed[None]
        for step in ik.settings.closed_form_steps:
            if closed.first(prepared, starts, out, step, ik.compiled) == 0:
                errors = _verified(ik, search, out, position, rotation)
                if errors is not None:
                    solution = IKSolution(out, "", True, *errors)
                    return search.success(solution, METHOD, FROM_SEED, 0)
    for starts, indices, step in _sample_starts(ik, search):
        index = closed.first(prepared, starts, out, step, ik.compiled)
        offset = 0
        while index >= 0:
            offset += index + 1
            errors = _verified(ik, search, out, position, rotation)
            if errors is not None:
                solution = IKSolution(out, "", True, *errors)
                label = f"seed-table sample {int(indices[offset - 1])}"
                return search.success(
                    solution, METHOD, f"closed form with the free joints of {label}", 0
                )
            if offset >= len(starts):
                break
            index = closed.first(prepared, starts[offset:], out, step, ik.compiled)
    return None


def _near_seed(
    ik: NumericContext,
    search: Search,
    closed: FreeJointClosedForm,
    prepared: Any,
    seed: np.ndarray,
    leash: float,
    out: np.ndarray,
    position: list[float],
    rotation: list[float] | None,
) -> IKResult | None:
    """The answer near a seed whose tool is near the target, or None (the scan and samples next).

    The closed form with the seed's own free joints (no scan) when its branch is within
    ``settings.seed_near`` of the seed; else damped Newton from the seed (``leash``: see
    :func:`.starts.seed_leash`), whose steps move every joint, the free one too; the nearer of
    the two verified answers. Keeping the free joint can put the branch far: the near branch
    outside a limit at that free-joint value, or moved a long way by it.
    """
    kept: IKSolution | None = None
    moved = math.inf
    if closed.first(prepared, seed[None], out, 0.0, ik.compiled) == 0:
        errors = _verified(ik, search, out, position, rotation)
        if errors is not None:
            moved = _moved(out, seed)
            kept = IKSolution(out.copy(), "", True, *errors)
            if moved <= ik.settings.seed_near:
                return search.success(kept, METHOD, FROM_SEED, 0)
    search.seed_tried = True
    outcome = (
        search.newton(seed, None)
        if leash == math.inf
        else search.newton(seed, ik.settings.patience, leash)
    )
    if kept is None or (outcome.converged and _moved(outcome.q, seed) < moved):
        done = search.accept(
            outcome, DAMPED_NEWTON, f"damped Newton from {SEED}, {outcome.iterations} steps"
        )
        if done is not None or kept is None:
            return done
    # The closed form's answer: 0 iterations, as every closed form reports.
    message = f"{FROM_SEED} (damped Newton from it: {outcome.iterations} steps, no nearer answer)"
    return search.success(kept, METHOD, message, 0)


def _verified(
    ik: NumericContext,
    search: Search,
    q: np.ndarray,
    position: list[float],
    rotation: list[float] | None,
) -> tuple[float, float | None] | None:
    """The judge's errors of a closed-form answer when within the tolerances, else None.

    The limits are the closed form's business, except after a polish: the answer of an idealised
    table (``ik.idealised``) is first moved onto the true chain (:func:`.idealised.polish`, in
    place), then checked against the limits too.
    """
    if ik.idealised is not None:
        judge = ik.judge
        target = search.target
        q[:] = polish(
            judge.model,
            judge.data,
            judge.frame_id,
            q,
            target.position,
            target.rotation,
            ik.compiled_step,
        )
        values = q.tolist()
        if not (all(map(le, ik.lows, values)) and all(map(le, values, ik.highs))):
            return None
    position_error, rotation_error = ik.judge.errors(q, position, rotation)
    if position_error < search.position_tol and (
        rotation_error is None or rotation_error < search.rotation_tol
    ):
        return position_error, rotation_error
    return None


def _moved(q: np.ndarray, seed: np.ndarray) -> float:
    """Largest joint change from ``seed`` to ``q`` [rad]."""
    return max(map(abs, map(sub, q.tolist(), seed.tolist())))


def _sample_starts(
    ik: NumericContext, search: Search
) -> Iterator[tuple[np.ndarray, np.ndarray, float]]:
    """Blocks of closed-form starts after the caller's seed: ``(starts, sample indices, step)``.

    The seed-table sample nearest the target (scanned, coarse then fine; for a full pose by pose
    distance, for a position the nearest to the target's grid cell centre); the next
    ``closed_form_starts`` samples (not scanned). Looked up lazily: most targets need the caller's
    seed only.
    """
    steps = ik.settings.closed_form_steps
    target = search.target
    table = search.table
    if table is None:
        return
    position, rotation = target.position, target.rotation
    if rotation is None:
        candidates = table.cell_samples(position)
        if candidates is None:
            return
        for step in steps:
            yield table.q[candidates[:1]], candidates, step
        rest = candidates[1 : ik.settings.closed_form_starts]
    else:
        found = table.ranked(position, rotation)
        if found is None or not found[0].size:
            return
        candidates, distances = found
        first = int(distances.argmin())
        for step in steps:
            yield table.q[candidates[first : first + 1]], candidates[first:], step
        order = nearest_first(distances, ik.settings.closed_form_starts)
        rest = candidates[order[order != first]]
    if rest.size:
        yield table.q[rest], rest, 0.0
