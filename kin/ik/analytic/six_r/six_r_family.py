"""What the 6R closed-form families share: common fields, solve, and the compiled twin's use.

:class:`SixRFamily` is the base of :class:`~.three_parallel.ThreeParallel6R` and
:class:`~.pieper.Pieper6R`: one or N targets go to the family's compiled twin where it is built
and fits the arm (the UR case, the spherical wrist), else to the family's one NumPy algorithm
(one target is N = 1); the twin's parameter block and verifier (:mod:`.six_r_twin`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from types import ModuleType
from typing import ClassVar

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ...exceptions import TargetError
from ...targets.target import PoseTarget
from ..twin_support import pack_params
from ._six_r import BLOCK, TargetFrame, target_arrays
from .six_r_twin import TwinVerifier, check_params, frame_fields


@dataclass(frozen=True)
class SixRFamily:
    """A 6R family's arm: the fields every family has, and its solve of one or N targets.

    A family (a frozen dataclass subclass) adds its own fields, sets ``_k`` and ``_classic`` in
    its ``__post_init__`` (after this one's) and calls :meth:`_pack_twin` where its compiled twin
    fits the arm; it defines ``name``, :meth:`_solve_block` (its NumPy algorithm) and
    :meth:`_c_own` (its own fields of the twin's ``LAYOUT``).

    Attributes:
        robot: Robot name.
        family: The sub-family the table's geometry gives (see the family's module).
        offsets: Joint offsets ``theta1 .. theta6`` [rad] (DH angle = q + offset).
        T_base: World -> standard DH frame 0 (4x4) [m].
        T_tool: Standard frame 6 (``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
    """

    name: ClassVar[str]
    #: Six revolute joints; a full pose as the target.
    dof: ClassVar[int] = 6
    target_kinds: ClassVar[tuple[type, ...]] = (PoseTarget,)
    #: The family's compiled twin (for its special case), or None when it is not built.
    compiled_twin: ClassVar[ModuleType | None] = None
    #: The family's special cases (subclasses), asked first by the registry.
    cases: ClassVar[tuple[type[SixRFamily], ...]] = ()

    robot: str
    family: str
    offsets: tuple[float, ...]
    T_base: np.ndarray = field(repr=False)
    T_tool: np.ndarray = field(repr=False)
    _frame: TargetFrame = field(init=False, repr=False, compare=False)
    _k: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _classic: bool = field(init=False, repr=False, compare=False)
    _c_params: np.ndarray | None = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_frame", TargetFrame(self.T_base, self.T_tool))
        object.__setattr__(self, "_c_params", None)

    def _solve_block(self, positions: np.ndarray, rotations: np.ndarray, free: float) -> np.ndarray:
        raise NotImplementedError

    def _c_own(self) -> dict[str, tuple[float, ...]]:
        raise NotImplementedError

    def solve(
        self,
        position: npt.ArrayLike,
        rotation: npt.ArrayLike | None,
        free: float = 0.0,
        *,
        compiled: bool = True,
    ) -> np.ndarray:
        """The 8 branches reaching a tool pose: :meth:`solve_batch` of one target.

        Args:
            position: Tool position in the world frame [m], (3,).
            rotation: Tool rotation ``R_world_tool``, (3, 3).
            free: Value of the free joint [rad] where the wrist is singular (the family's).
            compiled: Run the compiled twin when it is built and fits the arm (False: NumPy).

        Returns:
            Joint vectors [rad] in (-pi, pi], (8, 6), one row per branch label; a row of NaN
            where that branch does not reach the target. Not verified, not wrapped into limits.

        Raises:
            TargetError: No rotation (a 6R closed form needs a full pose).
        """
        if rotation is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs a full pose")
        p1 = np.reshape(np.asarray(position, dtype=float), (1, 3))
        r1 = np.reshape(np.asarray(rotation, dtype=float), (1, 3, 3))
        return self.solve_batch(p1, r1, free, compiled=compiled)[0]

    def solve_batch(
        self,
        positions: npt.ArrayLike,
        rotations: npt.ArrayLike | None,
        free: float = 0.0,
        *,
        compiled: bool = True,
    ) -> np.ndarray:
        """The 8 branches of N tool poses: the compiled twin when it fits, else the NumPy form.

        Args:
            positions: Tool positions in the world frame [m], (N, 3).
            rotations: Tool rotations ``R_world_tool``, (N, 3, 3).
            free: Value of the free joint [rad] where the wrist is singular.
            compiled: Run the compiled twin when it is built and fits the arm (False: NumPy).

        Returns:
            Joint vectors [rad] in (-pi, pi], (N, 8, 6), NaN where a branch does not exist.

        Raises:
            TargetError: No rotations, or ``positions`` not (N, 3) or ``rotations`` not (N, 3, 3).
        """
        if rotations is None:
            raise TargetError(f"{self.name}: the closed form of a 6R arm needs full poses")
        p, r = target_arrays(positions, rotations)
        twin, params = self.compiled_twin, self._c_params
        if compiled and twin is not None and params is not None:
            out = np.empty((p.shape[0], 8, 6))
            twin.solve(params, p, r, float(free), out)
            return out
        # The twin's IEEE arithmetic: a degenerate pose (a wrist centre on an axis, 1e-300 m
        # away) gives inf or NaN, a branch that does not exist, as the C code does, not a warning.
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            if len(p) <= BLOCK:  # blocks of BLOCK targets: their arrays stay in the CPU cache
                return self._solve_block(p, r, free)
            blocks = range(0, len(p), BLOCK)
            return np.concatenate(
                [self._solve_block(p[i : i + BLOCK], r[i : i + BLOCK], free) for i in blocks]
            )

    def _pack_twin(self) -> None:
        twin = self.compiled_twin
        params = None if twin is None else pack_params(self.c_fields(), twin.LAYOUT)
        object.__setattr__(self, "_c_params", params)

    def c_fields(self) -> dict[str, tuple[float, ...]]:
        """The compiled twin's parameters by field name (its ``LAYOUT``; lengths [m], angles [rad])."""
        return {**frame_fields(self.T_base, self.T_tool), **self._c_own()}

    @property
    def c_params(self) -> np.ndarray:
        """:meth:`c_fields` packed in the order the compiled twin declares (its ``LAYOUT``).

        Raises:
            RuntimeError: The twin is not built.
        """
        if self._c_params is None:
            raise RuntimeError(f"the compiled twin of {self.name} is not built")
        return self._c_params

    def verifier(
        self,
        table: DHTable,
        lower: Sequence[float],
        upper: Sequence[float],
        tolerance_position: float,
        tolerance_rotation: float,
    ) -> TwinVerifier | None:
        """The compiled solve-and-verify of this arm (:class:`TwinVerifier`).

        Args:
            table: The table this structure was read from.
            lower: Lower joint limits [rad].
            upper: Upper joint limits [rad].
            tolerance_position: Largest position error of a valid solution [m].
            tolerance_rotation: Largest rotation error of a valid solution [rad].

        Returns:
            None when the twin is not built.
        """
        twin = self.compiled_twin
        if twin is None or self._c_params is None:
            return None
        check = check_params(twin, table, lower, upper, tolerance_position, tolerance_rotation)
        return TwinVerifier(twin, self._c_params, check)
