"""The compiled twins of the 6R closed forms: their parameter blocks, solve and verify.

``kin/_native/ik/analytic/six_r/_three_parallel.c`` and ``_pieper_arms.c`` (optional extensions, built at install
when a C compiler is there) repeat, target by target, the NumPy algorithm of a family for all its
cases: the three-parallel family's (:mod:`.three_parallel_batch`; its UR case, axes 5 and 6
meeting, among them), Pieper's (:mod:`.pieper_batch`; its spherical wrist with parallel axes 2
and 3 among them); the NumPy forms are the reference and the fallback
(:class:`~.six_r_family.SixRFamily` chooses). Each twin also has ``verify``: the 8
branches of one target, each moved into the joint limits (the ``2 pi`` copy nearest the seed, as
:class:`~.closed_form.ClosedFormSolver` does) and measured by a plain DH product of the table as
written (either convention, its base and tool): an FK independent of the closed form's algebra,
and of Pinocchio (``tests/native/test_six_r_twins.py`` compares it with Pinocchio's).

A structure's parameters travel as one float64 vector in the order its twin declares
(``LAYOUT``, filled by field name with :func:`~.seven_dof.pack_params`); the table, the limits and
the tolerances as a second one (``CHECK_LAYOUT``, :func:`check_params`).
"""

from __future__ import annotations

import ctypes
import functools
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ..twin_support import chain_fields, pack_params

#: Status codes of ``verify``'s ``info[:, 0]``.
MISSING, VALID, OUTSIDE_LIMITS, OFF_TARGET = 0, 1, 2, 3


def frame_fields(T_base: np.ndarray, T_tool: np.ndarray) -> dict[str, tuple[float, ...]]:
    """The twin's frame fields (``FRAME_PARAMS``) of a 6R structure's base and tool (4x4) [m]."""
    eye = np.eye(4)
    return {
        "base_r": tuple(np.asarray(T_base, dtype=float)[:3, :3].ravel().tolist()),
        "base_t": tuple(np.asarray(T_base, dtype=float)[:3, 3].tolist()),
        "tool_r": tuple(np.asarray(T_tool, dtype=float)[:3, :3].ravel().tolist()),
        "tool_t": tuple(np.asarray(T_tool, dtype=float)[:3, 3].tolist()),
        "plain": (float(np.array_equal(T_base, eye)), float(np.array_equal(T_tool, eye))),
    }


@functools.cache
def _numpy_dgeev() -> tuple[int, bool]:
    """The address of the ``dgeev`` of the OpenBLAS NumPy's wheel bundles, and if it is ILP64.

    ``(0, False)`` when there is none to find (a NumPy built otherwise).
    """
    root = Path(np.__file__).parent
    for path in sorted(
        [*root.parent.glob("numpy.libs/*openblas*"), *root.glob(".dylibs/*openblas*")]
    ):
        try:
            library = ctypes.CDLL(str(path))
        except OSError:
            continue
        for name, ilp64 in (("scipy_dgeev_64_", True), ("scipy_dgeev_", False), ("dgeev_", False)):
            function = getattr(library, name, None)
            if function is not None:
                return ctypes.cast(function, ctypes.c_void_p).value or 0, ilp64
    return 0, False


def quartic_twin(twin: ModuleType | None) -> ModuleType | None:
    """A general family's twin with LAPACK's ``dgeev`` set for its quartic, or None.

    NumPy's own LAPACK first (the one its ``eigvals`` runs; no SciPy import), else SciPy's.

    Returns:
        None when the twin is not built or no LAPACK can be loaded.
    """
    if twin is None:
        return None
    try:
        twin.load_lapack(*_numpy_dgeev())
    except ImportError:
        return None
    return twin


def check_params(
    twin: ModuleType,
    table: DHTable,
    lower: Sequence[float],
    upper: Sequence[float],
    tolerance_position: float,
    tolerance_rotation: float,
) -> np.ndarray:
    """The ``check`` block of ``twin.verify``: the table's chain as written, limits, tolerances.

    Args:
        twin: A compiled 6R twin (its ``CHECK_LAYOUT``).
        table: The arm's DH table (6 revolute joints).
        lower: Lower joint limits [rad].
        upper: Upper joint limits [rad].
        tolerance_position: Largest position error of a valid solution [m].
        tolerance_rotation: Largest rotation error of a valid solution [rad].
    """
    chain = chain_fields(table)
    fields = {
        **chain,
        "lower": tuple(float(v) for v in lower),
        "upper": tuple(float(v) for v in upper),
        "tolerance": (float(tolerance_position), float(tolerance_rotation)),
        "has_offsets": (float(any(chain["theta"])),),
    }
    return pack_params(fields, twin.CHECK_LAYOUT)


class TwinVerifier:
    """``verify`` of one arm's twin: every branch of a target moved into the limits and measured.

    Args:
        twin: The compiled twin of the arm's structure.
        params: The structure's packed parameters (its ``c_params``).
        check: :func:`check_params` of the arm.
    """

    def __init__(self, twin: ModuleType, params: np.ndarray, check: np.ndarray):
        self._twin = twin
        self._verify = twin.verify
        self._params = params
        self._check = check

    def solutions(
        self, directions: np.ndarray | None, labels: Sequence[str], name: str
    ) -> Callable[[Any, npt.ArrayLike | None, float], Any]:
        """The twin's ``solutions`` of this arm: ``(target, seed, start)`` -> answer.

        The target: a :class:`~kin.ik.PoseTarget` (its packed values, or its ``position`` and
        ``rotation`` arrays, float64 C-contiguous).

        The work of :meth:`__call__`, then the answer as the closed-form solver returns it. When
        a branch is valid and none is off target, the :class:`~kin.ik.result.IKResult` itself
        (``time`` from ``start``, a ``time.perf_counter()`` [s]). Else ``(valid, rejected,
        off)``: the :class:`~kin.ik.result.IKSolution` of each branch inside the limits and on
        target, nearest the seed first; of each on target outside the limits; and ``(label,
        position error [m], rotation error [rad])`` of each off target. An int instead when
        there is no branch to return: -1 a target value that is not finite, 0 no branch, -2 a
        seed that is not 6 finite float64 values (for the caller to check and name).

        Args:
            directions: Per joint 1 or -1 (the arm's ``q = direction * q'`` of the table the
                twin solves: seeds mapped in, answers out), or None.
            labels: The 8 branch labels, in the twin's branch order.
            name: The solver's name (:attr:`IKResult.solver`).
        """
        from ...result import IKResult, IKSolution

        flips = None if directions is None else np.asarray(directions, dtype=float).tobytes()
        return functools.partial(
            self._twin.solutions,
            self._params.tobytes(),
            self._check.tobytes(),
            flips,
            IKSolution,
            tuple(labels),
            IKResult,
            name,
            tuple(f"{n} valid solution(s)" for n in range(1, 9)),
            time.perf_counter,
        )

    def __call__(
        self, position: np.ndarray, rotation: np.ndarray, seed: np.ndarray, free: float = 0.0
    ) -> tuple[int, np.ndarray, list[list[float]]]:
        """Branches of one target.

        Args:
            position: Tool position in the world frame [m], float64 (3,).
            rotation: ``R_world_tool``, float64 (3, 3), C-contiguous.
            seed: Joint vector [rad], float64 (6,): the ``2 pi`` copies and the distances.
            free: Value of the free joint at a singular wrist [rad].

        Returns:
            The number of branches that exist (0: out of reach; -1: a value of the target is not
            finite); the joint vectors (8, 6) [rad], read-only, NaN rows where no branch; per
            branch ``[status, position error [m], rotation error [rad], distance to the seed
            [rad]]``, status one of :data:`MISSING`, :data:`VALID`, :data:`OUTSIDE_LIMITS`,
            :data:`OFF_TARGET`.
        """
        q = np.empty((8, 6))
        info = np.empty((8, 4))
        found = self._verify(self._params, self._check, position, rotation, seed, free, q, info)
        q.flags.writeable = False
        return found, q, info.tolist()
