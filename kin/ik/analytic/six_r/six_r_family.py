"""What the 6R closed-form families share: their solve of one or N targets, and their twin's use.

:class:`~.three_parallel.ThreeParallel6R` and :class:`~.pieper.Pieper6R` each hold a
:class:`SixRFamily`: one or N targets go to the family's compiled twin where it is built and fits
the arm (the UR case, the spherical wrist), else to the family's one NumPy algorithm (one target
is N = 1, in blocks of :data:`~._six_r.BLOCK`); the twin's parameter block and verifier
(:mod:`.six_r_twin`). Angles in [rad], lengths in [m].
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from types import ModuleType

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ...exceptions import TargetError
from ..twin_support import pack_params
from ._six_r import BLOCK, target_arrays
from .six_r_twin import TwinVerifier, check_params

#: A family's NumPy algorithm: ``(positions (N, 3) [m], rotations (N, 3, 3), free [rad])`` in the
#: world frame -> the 8 branches (N, 8, 6) [rad], NaN where a branch does not exist.
SolveBlock = Callable[[np.ndarray, np.ndarray, float], np.ndarray]


@dataclass(frozen=True)
class SixRFamily:
    """A 6R family's solve of one or N targets: its compiled twin where it fits, else NumPy.

    Held by the family's arm, which reads the table and builds its algorithm (:meth:`of`).

    Attributes:
        name: The family's solver name (in messages).
        block: The family's NumPy algorithm of up to :data:`~._six_r.BLOCK` targets.
        twin: The family's compiled twin, or None when it is not built.
        params: The twin's parameters packed in its ``LAYOUT``, or None when the twin is not built
            or does not fit the arm.
    """

    name: str
    block: SolveBlock = field(repr=False)
    twin: ModuleType | None = field(default=None, repr=False)
    params: np.ndarray | None = field(default=None, repr=False)

    @classmethod
    def of(
        cls,
        name: str,
        block: SolveBlock,
        twin: ModuleType | None,
        fields: Callable[[], dict[str, tuple[float, ...]]] | None,
    ) -> SixRFamily:
        """The solve of an arm by its algorithm ``block`` and its family's ``twin``.

        ``fields`` (the twin's parameters by field name) are packed in the twin's ``LAYOUT`` when
        the twin is built and ``fields`` is given (None: the twin does not fit the arm).
        """
        params = None if twin is None or fields is None else pack_params(fields(), twin.LAYOUT)
        return cls(name, block, twin, params)

    def hand_to(self, arm: object) -> None:
        """Make this the solve of ``arm``, a frozen family dataclass that holds it.

        ``arm._solve`` is this object; ``arm.solve``, ``arm.solve_batch`` and ``arm.verifier``
        are its bound methods (no call in between).
        """
        for name, value in (
            ("_solve", self),
            ("solve", self.solve),
            ("solve_batch", self.solve_batch),
            ("verifier", self.verifier),
        ):
            object.__setattr__(arm, name, value)

    def solve(
        self,
        position: npt.ArrayLike,
        rotation: npt.ArrayLike | None,
        free: float = 0.0,
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
        return self.solve_batch(p1, r1, free, compiled)[0]

    def solve_batch(
        self,
        positions: npt.ArrayLike,
        rotations: npt.ArrayLike | None,
        free: float = 0.0,
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
        twin, params = self.twin, self.params
        if compiled and twin is not None and params is not None:
            out = np.empty((p.shape[0], 8, 6))
            twin.solve(params, p, r, float(free), out)
            return out
        # The twin's IEEE arithmetic: a degenerate pose (a wrist centre on an axis, 1e-300 m
        # away) gives inf or NaN, a branch that does not exist, as the C code does, not a warning.
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            if len(p) <= BLOCK:  # blocks of BLOCK targets: their arrays stay in the CPU cache
                return self.block(p, r, free)
            blocks = range(0, len(p), BLOCK)
            return np.concatenate(
                [self.block(p[i : i + BLOCK], r[i : i + BLOCK], free) for i in blocks]
            )

    @property
    def c_params(self) -> np.ndarray:
        """The compiled twin's parameters packed in its ``LAYOUT``.

        Raises:
            RuntimeError: The twin is not built.
        """
        if self.params is None:
            raise RuntimeError(f"the compiled twin of {self.name} is not built")
        return self.params

    def verifier(
        self,
        table: DHTable,
        lower: Sequence[float],
        upper: Sequence[float],
        tolerance_position: float,
        tolerance_rotation: float,
    ) -> TwinVerifier | None:
        """The compiled solve-and-verify of the arm (:class:`TwinVerifier`).

        Args:
            table: The table the arm was read from.
            lower: Lower joint limits [rad].
            upper: Upper joint limits [rad].
            tolerance_position: Largest position error of a valid solution [m].
            tolerance_rotation: Largest rotation error of a valid solution [rad].

        Returns:
            None when the twin is not built.
        """
        twin = self.twin
        if twin is None or self.params is None:
            return None
        check = check_params(twin, table, lower, upper, tolerance_position, tolerance_rotation)
        return TwinVerifier(twin, self.params, check)
