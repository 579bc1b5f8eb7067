"""Shared reading of a 6R table for the closed forms of :mod:`.pieper` and :mod:`.three_parallel`.

Both solvers work on the *standard* DH chain ``T_world_base Rz Tz Tx Rx ... Rz(t6) Tz(d6) T_tool``.
A table in either convention is brought to that form exactly, without rounding any number:

- standard: row 6's ``Tx(a6) Rx(alpha6)`` commutes into the tool: ``T_tool = Tx(a6) Rx(alpha6)
  T_last_tool``;
- modified (Craig): ``Rx(alpha_0) Tx(a_0)`` of row 1 goes into the base, and the ``(a, alpha)`` of
  row ``i + 1`` is the standard ``(a_i, alpha_i)`` of joint ``i``; joint 6 then ends with
  ``Rz(t6) Tz(d6)`` and the tool is the table's.

:class:`SixRChecker` keeps, for every standard parameter, the table row and field it comes from, so
that a :class:`~kin.ik.exceptions.StructureError` names the row and the parameter of the file.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from ...angles import SLACK, clip_cosines, clip_unit, wrap, wrap_array  # noqa: F401  (the family's names)
from ...exceptions import StructureError, TargetError
from ..structure import Checker

#: Tolerance on DH twists [rad] when a structure needs an exact value (0.1 deg is far outside).
ANGLE_TOL = 1e-9
#: Tolerance on DH lengths [m] that the structure needs to be exactly zero.
LENGTH_TOL = 1e-12
#: Below this ``|sin|`` of the wrist angle a joint is free (singular wrist) [-].
SINGULAR = 1e-12

#: Targets per block of the batched solvers (the block's arrays stay in the CPU cache).
BLOCK = 4096

_TWO_PI = 2.0 * math.pi


def _deg(value: float) -> str:
    return f"{math.degrees(value):.6g} deg"


def _hom(rotation: np.ndarray, x: float = 0.0) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rotation
    out[0, 3] = x
    return out


def _rot_x(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


class SixRChecker:
    """A 6R table as a standard chain, with the source row and field of every parameter.

    Attributes:
        a, alpha, d, theta: Standard DH parameters of joints 1..6 (0-based lists) [m], [rad];
            ``a[5] = alpha[5] = 0`` (moved into :attr:`T_tool`).
        T_base: Fixed transform world -> standard frame 0 (4x4) [m].
        T_tool: Fixed transform standard frame 6 (after ``Rz(t6) Tz(d6)``) -> tool (4x4) [m].
    """

    def __init__(self, table: DHTable, solver: str):
        self.table = table
        self.solver = solver
        Checker(table, solver).revolute(6)
        rows = table.rows
        self.d = [row.d for row in rows]
        self.theta = [row.theta for row in rows]
        base = np.array(table.T_world_base, dtype=float)
        tool = np.array(table.T_last_tool, dtype=float)
        if table.convention == "modified":
            self._source = [rows[i + 1] for i in range(5)]
            self.a = [row.a for row in self._source] + [0.0]
            self.alpha = [row.alpha for row in self._source] + [0.0]
            base = base @ _hom(_rot_x(rows[0].alpha), rows[0].a)
        else:
            self._source = list(rows[:5])
            self.a = [row.a for row in rows[:5]] + [0.0]
            self.alpha = [row.alpha for row in rows[:5]] + [0.0]
            tool = _hom(_rot_x(rows[5].alpha), rows[5].a) @ tool
        self.T_base = base
        self.T_tool = tool

    def fail(self, mismatch: str) -> StructureError:
        """The error naming this table and solver."""
        return StructureError(self.table.name, self.solver, mismatch)

    def where(self, joint: int, field: str) -> str:
        """``row k ('name'): field`` of the table row holding joint ``joint``'s (0-based) value."""
        row = self._source[joint] if field in ("a", "alpha") else self.table.rows[joint]
        note = ""
        if self.table.convention == "modified" and field in ("a", "alpha"):
            note = f" (modified convention: {field}_{joint + 1} of joint {joint + 1})"
        return f"row {row.index} ('{row.name}'): {field}{note}"

    def zero(self, joint: int, field: str, why: str) -> None:
        """Raise unless the length ``field`` (``"a"`` or ``"d"``) of ``joint`` is 0."""
        value = getattr(self, field)[joint]
        if abs(value) > LENGTH_TOL:
            raise self.fail(f"{self.where(joint, field)} = {value:g} m, expected 0 ({why})")

    def nonzero(self, joint: int, field: str, why: str) -> float:
        """The length ``field`` of ``joint``, raising when it is 0."""
        value = getattr(self, field)[joint]
        if abs(value) <= LENGTH_TOL:
            raise self.fail(f"{self.where(joint, field)} = {value:g} m, expected non-zero ({why})")
        return float(value)

    def twist(self, joint: int, choices: tuple[float, ...], why: str) -> float:
        """The twist of ``joint`` among ``choices`` [rad] (within :data:`ANGLE_TOL`), or raise."""
        value = self.alpha[joint]
        for choice in choices:
            if abs(math.remainder(value - choice, _TWO_PI)) <= ANGLE_TOL:
                return choice
        wanted = " or ".join(_deg(v) for v in choices)
        raise self.fail(f"{self.where(joint, 'alpha')} = {_deg(value)}, expected {wanted} ({why})")

    def skew(self, joint: int, why: str) -> float:
        """The twist of ``joint``, raising when it is 0 or 180 deg (parallel axes)."""
        value = self.alpha[joint]
        if abs(math.sin(value)) <= ANGLE_TOL:
            raise self.fail(
                f"{self.where(joint, 'alpha')} = {_deg(value)}, expected an angle other than "
                f"0 or 180 deg ({why})"
            )
        return float(value)


class TargetFrame:
    """Maps a world tool pose to the pose of standard frame 6 in frame 0, scalar and batched.

    Args:
        T_base: World -> standard frame 0 (4x4) [m].
        T_tool: Standard frame 6 -> tool (4x4) [m].
    """

    def __init__(self, T_base: np.ndarray, T_tool: np.ndarray):
        eye = np.eye(4)
        self.base_r = np.array(T_base[:3, :3], dtype=float)
        self.base_t = np.array(T_base[:3, 3], dtype=float)
        self.tool_r = np.array(T_tool[:3, :3], dtype=float)
        self.tool_t = np.array(T_tool[:3, 3], dtype=float)
        self._plain_base = bool(np.array_equal(T_base, eye))
        self._plain_tool = bool(np.array_equal(T_tool, eye))
        self._rb = tuple(tuple(r) for r in self.base_r.tolist())
        self._tb = tuple(self.base_t.tolist())
        self._rt = tuple(tuple(r) for r in self.tool_r.tolist())
        self._tt = tuple(self.tool_t.tolist())

    def scalar(
        self, position: np.ndarray, rotation: np.ndarray
    ) -> tuple[list[float], list[list[float]]]:
        """``p_0_6`` [m] and ``R_0_6`` (rows) of a tool pose ``position``, ``rotation`` (world)."""
        p = [float(v) for v in np.asarray(position, dtype=float).reshape(3)]
        r = np.asarray(rotation, dtype=float).reshape(3, 3).tolist()
        if not self._plain_tool:  # R r_t^T, p - R r_t^T t_t
            rt, tt = self._rt, self._tt
            r = [[row[0] * t[0] + row[1] * t[1] + row[2] * t[2] for t in rt] for row in r]
            p = [p[i] - (r[i][0] * tt[0] + r[i][1] * tt[1] + r[i][2] * tt[2]) for i in range(3)]
        if not self._plain_base:  # R_b^T R, R_b^T (p - t_b)
            rb, tb = self._rb, self._tb
            q = [p[0] - tb[0], p[1] - tb[1], p[2] - tb[2]]
            p = [rb[0][j] * q[0] + rb[1][j] * q[1] + rb[2][j] * q[2] for j in range(3)]
            r = [
                [rb[0][j] * r[0][k] + rb[1][j] * r[1][k] + rb[2][j] * r[2][k] for k in range(3)]
                for j in range(3)
            ]
        return p, r

    def batch(self, positions: np.ndarray, rotations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``p_0_6`` (N, 3) [m] and ``R_0_6`` (N, 3, 3) of tool poses in the world."""
        p = np.asarray(positions, dtype=float).reshape(-1, 3)
        r = np.asarray(rotations, dtype=float).reshape(-1, 3, 3)
        # The same sums in the same order as :meth:`scalar` (so both give the same numbers).
        if not self._plain_tool:
            rt, tt = self._rt, self._tt
            r = np.stack(
                [r[:, :, 0] * t[0] + r[:, :, 1] * t[1] + r[:, :, 2] * t[2] for t in rt], axis=2
            )
            p = p - (r[:, :, 0] * tt[0] + r[:, :, 1] * tt[1] + r[:, :, 2] * tt[2])
        if not self._plain_base:
            rb, tb = self._rb, self._tb
            q = p - np.array(tb)
            p = np.stack(
                [rb[0][j] * q[:, 0] + rb[1][j] * q[:, 1] + rb[2][j] * q[:, 2] for j in range(3)],
                axis=1,
            )
            r = np.stack(
                [
                    rb[0][j] * r[:, 0, :] + rb[1][j] * r[:, 1, :] + rb[2][j] * r[:, 2, :]
                    for j in range(3)
                ],
                axis=1,
            )
        return p, r


#: The candidate row of a branch that does not exist.
NAN_ROW = (math.nan,) * 6


def sin_cos(angle: float) -> tuple[float, float]:
    """``sin``, ``cos`` of a twist [rad], a cosine below 1e-15 set to 0 (90 deg exactly)."""
    s, c = math.sin(angle), math.cos(angle)
    return s, (0.0 if abs(c) < 1e-15 else c)


def target_arrays(
    positions: npt.ArrayLike, rotations: npt.ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """N tool positions (N, 3) [m] and rotations (N, 3, 3) as C-contiguous float64 arrays.

    Raises:
        TargetError: ``positions`` is not (N, 3) or ``rotations`` not (N, 3, 3).
    """
    p = np.ascontiguousarray(positions, dtype=float)
    r = np.ascontiguousarray(rotations, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3 or r.shape != (p.shape[0], 3, 3):
        raise TargetError(
            f"positions must be (N, 3) and rotations (N, 3, 3), got {p.shape} and {r.shape}"
        )
    return p, r
