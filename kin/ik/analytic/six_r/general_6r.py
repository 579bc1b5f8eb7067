"""Closed-form IK of any revolute 6R arm: every isolated solution (up to 16), by elimination.

The families of :mod:`.ur_wrist`, :mod:`.spherical_wrist`, :mod:`.pieper`,
:mod:`.three_parallel` and :mod:`.reversed_chain` keep their arms (this structure is registered
last); the rest, e.g. the xArm6, Jaco 2, FANUC CRX or PiPER tables with their offsets, are solved
here instead of by the numeric solver.

Method: Raghavan and Roth's elimination, in the numerically stable form of Manocha and Canny
(M. Raghavan, B. Roth, "Inverse kinematics of the general 6R manipulator and related
linkages", ASME J. Mech. Des. 115(3):502-508, 1993; D. Manocha, J. F. Canny, "Efficient
inverse kinematics for general 6R manipulators", IEEE Trans. Robot. Autom. 10(5):648-657, 1994):
the 14 Raghavan-Roth equations of the loop give a 12x12 matrix quadratic in the half-angle
tangent of one joint, solved as a 24x24 eigenproblem (:mod:`._general_6r_elimination`). The
loop may be cut in six ways (joint 1, 2 or 3 as the eigenvalue, read from the base; joint 6, 5 or
4 read from the tool); an arm's special geometry (zero lengths, parallel or meeting axes) makes
some of them singular. :meth:`General6R.recognise` solves sampled poses of the arm with each and
keeps the one (or two, their answers merged) that recovers them all, the next ones as fallbacks.
A pose whose distinct branches are fewer than the real roots (solutions sharing the eliminated
joint's angle: a multiple root, common at symmetric poses) is solved again reading every
solution of a multiple root from its null space, then by the fallbacks, the answers merged;
such a pose is also solved at six nearby poses (:data:`NUDGES`, 1e-5 to 1e-3 away) by every cut,
where its roots are simple, each candidate polished back onto the pose: which eigenvalues of a
multiple root come out real depends on the LAPACK build (OpenBLAS picks its kernels by CPU), the
branches must not. Poses whose solutions are not isolated (singular ones) give some of them.

Every candidate is polished by Newton steps on the true chain (to about 1e-13 [m], [rad]),
kept only when on target to :data:`KEEP_TOL`, and duplicates are merged (:mod:`._general_6r_chain`);
the solvers' judge then verifies each branch as for any structure.

The eliminations run in the compiled twin ``kin/_native/ik/analytic/six_r/_general6r.c`` when it is built (LAPACK
through SciPy; the spurious roots deflated once per arm, :mod:`._general_6r_deflation`): the
first pass, and for a pose it does not solve cleanly the fallbacks and the nudged poses by every
cut (:mod:`._general_6r_compiled`). A pose the twin cannot answer (a singular pencil), or that
is still short of branches after them, takes the NumPy path above, which stays the reference.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable
from kin._native import twin

from ...exceptions import StructureError, TargetError
from ...targets.target import PoseTarget
from ..structure import Checker
from . import _general_6r_chain as _chain
from . import _general_6r_compiled as _compiled
from ._general_6r_chain import BRANCHES, chain_transforms, distinct, forward, polish
from ._general_6r_elimination import IMAG_TOL, Formulation
from ._stacked_transforms import inverse

#: A polished candidate is kept when its position [m] and rotation [rad] errors are below this.
KEEP_TOL = 1e-10
#: Eigenvalues this close to real (relative imaginary part) count as roots a pose must keep:
#: a pose with fewer branches is solved again (nearer ones are also polished, not counted).
ROOT_TOL = 1e-7
#: Poses solved together by :meth:`General6R.solve_batch` (more in chunks of this many: larger
#: stacks outgrow the CPU's caches, 10 to 20 % slower per pose measured at 10,000).
CHUNK = 1024
#: Further eliminations asked for a pose the first one does not solve cleanly, at most.
FALLBACKS = 2
#: Sampled poses per formulation when an arm is recognised, and the seed of their joints.
PROBES = 24
PROBE_SEED = 6


def _nudge(
    size: float, axis: tuple[float, float, float], shift: tuple[float, float, float]
) -> np.ndarray:
    """A rigid motion (4, 4) of ``size`` [rad] about ``axis`` and ``size`` [m] along ``shift``."""
    k = np.array(axis) / np.linalg.norm(axis)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    out = np.eye(4)
    out[:3, :3] += math.sin(size) * K + (1.0 - math.cos(size)) * K @ K
    out[:3, 3] = size * np.array(shift) / np.linalg.norm(shift)
    return out


#: Tool-frame motions to nearby poses (fixed, generic directions; 1e-5 to 1e-3 [m], [rad]): the
#: roots of a pose the elimination did not solve cleanly (a multiple root, a degenerate cut, a
#: cluster of close solutions) are also taken from these poses, where they are simple, and
#: polished back, so that no branch depends on the LAPACK build. Several sizes: a small nudge
#: leaves a multiple root ill-conditioned, a large one can carry Newton to a close neighbour.
NUDGES = tuple(
    _nudge(size, axis, shift)
    for size in (1e-5, 1e-4, 1e-3)
    for axis, shift in (
        ((0.31, -0.72, 0.62), (0.53, 0.27, -0.80)),
        ((-0.66, 0.14, 0.74), (-0.35, 0.88, 0.31)),
    )
)

#: The twin's nudges, one of each size: all six's branch counts (12,000 PiPER, M0609 poses).
TWIN_NUDGES = (NUDGES[0], NUDGES[3], NUDGES[4])


@dataclass(frozen=True, eq=False)
class General6R:
    """Any revolute 6R arm (16 branches), by Raghavan-Roth / Manocha-Canny elimination.

    Attributes:
        robot: Robot name.
        formulations: The eliminations used (one, or two whose answers are merged).
        F: The chain's constant transforms ``F0 .. F6`` (7, 4, 4) [m] (world to tool, see
            :func:`chain_transforms`).
        signs: The joints' directions (+-1): DH angle ``theta_i + s_i q_i``.
        fallbacks: Further eliminations, asked for the poses where the first leaves a real
            root unsolved (two solutions sharing the eliminated joint's angle, a root that does
            not polish onto the target, an odd count): their branches are merged.
        compiled: Run the first elimination's pass in the compiled twin
            (``kin/_native/ik/analytic/six_r/_general6r.c``) when it is built and one elimination is used; the
            NumPy path is the reference, the fallback and every later pass.
    """

    name: ClassVar[str] = "general_6r"
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    branch_labels: ClassVar[tuple[str, ...]] = tuple(
        f"branch {k} (joints ascending)" for k in range(1, BRANCHES + 1)
    )
    robot: str
    formulations: tuple[Formulation, ...]
    F: np.ndarray = field(repr=False)
    signs: np.ndarray = field(repr=False)
    fallbacks: tuple[Formulation, ...] = ()
    compiled: bool = field(default=True, repr=False)
    _F0_inv: np.ndarray = field(init=False, repr=False)
    _F6_inv: np.ndarray = field(init=False, repr=False)
    _cuts: tuple[Formulation, ...] = field(init=False, repr=False)
    _twin: tuple[Any, np.ndarray] | None = field(init=False, repr=False)
    _blocks: dict[str, tuple[np.ndarray, ...]] = field(init=False, repr=False, default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_F0_inv", inverse(self.F[0]))
        object.__setattr__(self, "_F6_inv", inverse(self.F[6]))
        known = {(f.reverse, f.start): f for f in self.formulations + self.fallbacks}
        cuts = tuple(
            known.get((reverse, start)) or Formulation(reverse, start, self.F)
            for reverse in (False, True)
            for start in range(3)
        )
        object.__setattr__(self, "_cuts", cuts)
        module = twin("_general6r") if self.compiled and len(self.formulations) == 1 else None
        block = None if module is None else self.formulations[0].twin_block()
        object.__setattr__(self, "_twin", None if module is None else (module, block))

    @classmethod
    def recognise(cls, table: DHTable, rivals: Sequence[Any] = ()) -> General6R:
        """Any 6R table whose sampled poses an elimination recovers.

        ``rivals``: the registered closed forms, in the order they are asked (the registry
        passes its own, :func:`.registry.recognise`; this module does not import it): a rounded
        table that one of the other 6R families fits once idealised is refused. None given: no
        such check (a direct call on a table the caller chose).

        Raises:
            StructureError: Not 6 revolute joints; or a rounded table that a special family
                fits once idealised (:mod:`.idealised`: that family answers); or no elimination
                recovers the sampled poses (the arm's solutions are not isolated, e.g. two
                axes are one line).
        """
        check = Checker(table, "general 6R")
        check.revolute(6)
        _refuse_idealised(table, rivals)
        F, signs = chain_transforms(table)
        rng = np.random.default_rng(PROBE_SEED)
        u = rng.uniform(-math.pi, math.pi, size=(PROBES, 6))
        T = forward(F, u)[0]
        scored = []
        for reverse in (False, True):
            for start in range(3):
                formulation = Formulation(reverse, start, F)
                found = _found(F, (formulation,), T, u)
                scored.append((found.sum(), formulation, found))
        scored.sort(key=lambda item: -item[0])
        best = scored[0]
        fallbacks = tuple(item[1] for item in scored[1:] if 2 * item[0] >= PROBES)[:FALLBACKS]
        if best[0] == PROBES:
            return cls(table.name, (best[1],), F, signs, fallbacks)
        for other in scored[1:]:
            if (best[2] | other[2]).all():
                rest = tuple(f for f in fallbacks if f is not other[1])
                return cls(table.name, (best[1], other[1]), F, signs, rest)
        raise check.fail(
            f"no elimination recovers the arm's sampled poses (best {best[0]} of {PROBES}): "
            "its solutions are not isolated or the elimination is singular"
        )

    def solve(self, position: npt.ArrayLike, rotation: npt.ArrayLike | None) -> np.ndarray:
        """Every branch reaching a tool pose.

        Args:
            position: Tool position in the world frame [m], (3,).
            rotation: Tool rotation ``R_world_tool``, (3, 3).

        Returns:
            Joint vectors ``q`` [rad] in [-pi, pi), (16, 6), distinct branches first (ordered by
            their joints), NaN rows after. Polished, not verified by the judge, not wrapped
            into limits.

        Raises:
            TargetError: No rotation.
        """
        if rotation is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs a full pose")
        if self._twin is not None:  # the short way: one pose the twin solves cleanly
            try:
                p = np.ascontiguousarray(position, dtype=float)
                r = np.ascontiguousarray(rotation, dtype=float)
            except (TypeError, ValueError):
                p = r = np.empty(0)  # not the short way's: solve_batch names what is wrong
            out = np.empty((BRANCHES, 6))
            if self._twin[0].solve_one(self._twin[1], p, r, self.signs, out):
                return out
        return self.solve_batch(np.reshape(position, (1, 3)), np.reshape(rotation, (1, 3, 3)))[0]

    def solve_batch(self, positions: npt.ArrayLike, rotations: npt.ArrayLike | None) -> np.ndarray:
        """:meth:`solve` of N tool poses at once: (N, 16, 6) [rad].

        Raises:
            TargetError: No rotations, or ``positions`` not (N, 3) / ``rotations`` not (N, 3, 3).
        """
        if rotations is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs full poses")
        p = np.asarray(positions, dtype=float)
        r = np.asarray(rotations, dtype=float)
        if p.ndim != 2 or p.shape[1] != 3 or r.shape != (p.shape[0], 3, 3):
            raise TargetError(
                f"{self.name}: positions must be (N, 3) and rotations (N, 3, 3), got "
                f"{p.shape} and {r.shape}"
            )
        if p.shape[0] > CHUNK:  # in chunks: the stacks of a chunk stay in the CPU's caches
            return np.concatenate(
                [
                    self.solve_batch(p[k : k + CHUNK], r[k : k + CHUNK])
                    for k in range(0, p.shape[0], CHUNK)
                ]
            )
        T = np.zeros((p.shape[0], 4, 4))
        T[:, :3, :3], T[:, :3, 3], T[:, 3, 3] = r, p, 1.0
        finite = np.asarray(np.isfinite(T).all(axis=(1, 2)))
        T = np.where(finite[:, None, None], T, np.eye(4))
        out = self._numpy_path(T, finite) if self._twin is None else self._compiled(T, finite)
        return out * self.signs

    def _compiled(self, T: np.ndarray, finite: np.ndarray) -> np.ndarray:
        """The branches (N, 16, 6) [rad] of poses ``T`` in the twin (:mod:`._general_6r_compiled`).

        The first pass of every pose (in threads from
        :data:`._general_6r_compiled.THREAD_ROWS` poses), the poses it leaves unclean solved
        again in the twin; a pose it cannot answer (a singular leading matrix) by the NumPy path,
        one still unclean (or at a multiple root) by the NumPy path too, the twin's branches kept.
        """
        assert self._twin is not None
        module, block = self._twin
        n = T.shape[0]
        T = np.ascontiguousarray(T)
        out, roots = np.empty((n, BRANCHES, 6)), np.empty(n)
        _compiled.in_threads(module.first_pass, block, T, out, roots)
        answered, refused = roots >= 0.0, roots == -1.0  # refused: out's rows are not answers
        again = np.nonzero(answered & finite & _compiled.unclean(out, roots))[0]
        if again.size:
            if "cuts" not in self._blocks:  # the arm's further blocks, made once
                self._blocks["fallbacks"] = tuple(f.twin_block() for f in self.fallbacks)
                self._blocks["cuts"] = tuple(f.twin_block() for f in self._cuts)
            more, more_roots = out[again], roots[again]
            blocks = self._blocks["fallbacks"], self._blocks["cuts"]
            _compiled.resolve(module.first_pass, T[again], more, more_roots, *blocks, TWIN_NUDGES)
            out[again] = more
            still = _compiled.unclean(more, more_roots) | (more_roots < 0.0)
            answered[again[still]] = False  # a multiple root, or still unclean: the NumPy path
        failed = np.nonzero(~answered & finite)[0]
        if failed.size:
            mine = np.where(refused[failed, None, None], np.nan, out[failed])
            found = self._numpy_path(T[failed], np.ones(failed.size, dtype=bool))
            out[failed] = _compiled.merged(found, mine)
        out[~finite] = np.nan
        return out

    def _numpy_path(self, T: np.ndarray, finite: np.ndarray) -> np.ndarray:
        """The branches (N, 16, 6) [rad] of poses ``T`` by the NumPy path alone (the reference)."""
        inverses = (self._F0_inv, self._F6_inv)
        n = T.shape[0]
        pose, u, roots = _candidates(self.F, self.formulations, T, *inverses)
        pose, u = pose[finite[pose]], u[finite[pose]]
        out = distinct(n, pose, u)
        doubtful = None  # the poses the first elimination did not solve cleanly
        for extra in self.formulations[:1] + self.fallbacks:
            found = (~np.isnan(out[..., 0])).sum(axis=1)
            again = np.nonzero(((found < roots) | (found % 2 == 1)) & finite)[0]
            if doubtful is None:
                doubtful = again
            if not again.size:
                break
            more_pose, more_u, more_roots = _candidates(
                self.F, (extra,), T[again], *inverses, careful=True
            )
            pose = np.concatenate((pose, again[more_pose]))
            u = np.concatenate((u, more_u))
            roots = np.zeros_like(roots)
            roots[again] = more_roots  # a pose asks the next elimination if this one failed too
            _chain.distinct_again(out, pose, u, again)
        if doubtful is not None and doubtful.size:
            # Near a multiple root, or where this cut of the loop degenerates, the eigenvalues
            # (and which of them LAPACK's build returns as real) are ill-conditioned: solve
            # nearby poses by every cut, and polish each candidate onto the pose itself (Newton
            # from about NUDGE away). The branches no longer depend on the LAPACK build.
            for nudge in NUDGES:
                with np.errstate(all="ignore"):  # a degenerate cut gives NaN rows (dropped)
                    more_pose, more_u, _ = _candidates(
                        self.F, self._cuts, T[doubtful], *inverses, solve_at=T[doubtful] @ nudge
                    )
                pose = np.concatenate((pose, doubtful[more_pose]))
                u = np.concatenate((u, more_u))
            _chain.distinct_again(out, pose, u, doubtful)
        return out


#: The twin's row blocks in threads (kept under this name: tests call it).
_in_threads = _compiled.in_threads


def _candidates(
    F: np.ndarray,
    formulations: tuple[Formulation, ...],
    T: np.ndarray,
    F0_inv: np.ndarray | None = None,
    F6_inv: np.ndarray | None = None,
    careful: bool = False,
    solve_at: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pose index (M,) and polished DH joint variables on target (M, 6) [rad] of poses ``T``.

    Every real root of every formulation, polished, kept when on target to :data:`KEEP_TOL`.
    The third array (N,) counts the real roots per pose (divided by the formulations): a pose
    with fewer distinct branches, or an odd number, lost one (ask another formulation).
    ``careful``: read every solution of a multiple root too (:meth:`Formulation.candidates`).
    ``solve_at``: poses (N, 4, 4) [m] whose roots are taken instead (nearby poses), each polished
    onto its pose of ``T``.
    """
    F0_inv = inverse(F[0]) if F0_inv is None else F0_inv
    F6_inv = inverse(F[6]) if F6_inv is None else F6_inv
    K = F0_inv @ (T if solve_at is None else solve_at) @ F6_inv
    n = T.shape[0]
    poses, rows = [], []
    roots = np.zeros(n)
    for formulation in formulations:
        u, imag = formulation.candidates(K, careful)
        finite = np.isfinite(u).all(axis=-1)
        pose, branch = np.nonzero((imag <= IMAG_TOL) & finite)
        poses.append(pose)
        rows.append(u[pose, branch])
        roots += ((imag <= ROOT_TOL) & finite).sum(axis=1)
    pose = np.concatenate(poses)
    polished, error = polish(F, np.concatenate(rows), T[pose])
    ok = error <= KEEP_TOL
    roots /= len(formulations)
    return pose[ok], polished[ok], roots


def _found(
    F: np.ndarray, formulations: tuple[Formulation, ...], T: np.ndarray, u: np.ndarray
) -> np.ndarray:
    """Whether the joint variables ``u`` (N, 6) that made poses ``T`` are among the branches."""
    with np.errstate(all="ignore"):
        pose, got, _ = _candidates(F, formulations, T)
    diff = np.abs(np.remainder(got - u[pose] + math.pi, 2.0 * math.pi) - math.pi).max(axis=1)
    found = np.zeros(len(u), dtype=bool)
    found[pose[diff < 1e-6]] = True
    return found


def _refuse_idealised(table: DHTable, rivals: Sequence[Any]) -> None:
    """Raise when the table, idealised (:mod:`.idealised`), fits one of the special families."""
    from ..idealised import idealise

    ideal = idealise(table)
    if ideal is None:
        return
    for structure in rivals:
        if structure is General6R or structure.dof != 6:
            continue
        try:
            structure.recognise(ideal.table)
        except StructureError:
            continue
        raise StructureError(
            table.name,
            "general 6R",
            f"the table fits {structure.name} once rounded values are snapped "
            f"({'; '.join(ideal.changes)}): that closed form answers, polished",
        )
