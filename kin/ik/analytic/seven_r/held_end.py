"""A 7R arm with an end joint held: the 6R arm left and the targets it must reach.

Holding joint 1 or joint 7 of a seven-joint revolute arm leaves a 6R arm whose rows do not depend
on the held value: only the target moves, ``T' = (B A_1(q_1))^-1 T`` (joint 1 held, ``B`` the
base) or ``T' = T (A_7(q_7) M)^-1`` (joint 7 held, ``M`` the tool), with ``A_i`` the row's DH
transform. :class:`HeldEnd` is that arm once its end is chosen
(:class:`~.general_7r.General7RIK`): the 6R closed form of the rest, the targets it sees at
given held values, its branches, and the 7R joint vectors they make. Lengths [m], angles [rad].
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from dh2urdf import DHTable

from ..closed_form_structure import ClosedFormStructure
from ..six_r._general_6r_chain import chain_transforms


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
    """Inverses of rigid transforms (..., 4, 4) [m]."""
    out = np.zeros_like(T)
    R = np.swapaxes(T[..., :3, :3], -1, -2)
    out[..., :3, :3] = R
    out[..., :3, 3] = -(R @ T[..., :3, 3:4])[..., 0]
    out[..., 3, 3] = 1.0
    return out


def six_r_table(table: DHTable, free: int) -> DHTable:
    """The 6R arm left when end joint ``free`` (0 or 6) is held: its rows do not depend on it."""
    eye = np.eye(4)
    if free == 6:
        return dataclasses.replace(table, rows=table.rows[:6], T_last_tool=eye, name=table.name)
    return dataclasses.replace(table, rows=table.rows[1:], T_world_base=eye, name=table.name)


@dataclasses.dataclass(frozen=True, eq=False)
class HeldEnd:
    """An end joint of a 7R arm held and the 6R closed form of the rest (:func:`held_end`).

    Attributes:
        table: The 7R arm's DH table (a forward table: every direction 1).
        free: The held joint (0-based: 0 or 6).
        structure: The 6R closed form of the arm left (:func:`six_r_table`).
        flips: Signs (6,) its branches are multiplied by (a turned family's), or None.
        others: The other six joints (0-based), in order.
        outer: ``T_world_base`` (joint 1 held) or ``T_last_tool`` (joint 7 held) (4, 4).
        chain: The 6R arm's constant transforms
            (:func:`~..six_r._general_6r_chain.chain_transforms`), as its polish reads them.
    """

    table: DHTable
    free: int
    structure: ClosedFormStructure
    flips: np.ndarray | None
    others: list[int]
    outer: np.ndarray
    chain: np.ndarray

    def targets(self, targets: np.ndarray, values: np.ndarray) -> np.ndarray:
        """The 6R arm's targets (n, 4, 4) for 7R targets (n, 4, 4) at held values (n,) [rad]."""
        held = dh_transforms(self.table, self.free, values)
        if self.free == 6:
            return targets @ _inverse(held @ self.outer)
        return _inverse(self.outer @ held) @ targets

    def six_r(self, sub: np.ndarray) -> np.ndarray:
        """The 6R closed form's branches (n, 16, 6) [rad] of its targets ``sub`` (n, 4, 4), NaN rows."""
        q6 = self.structure.solve_batch(sub[:, :3, 3], sub[:, :3, :3])
        return q6 if self.flips is None else q6 * self.flips

    def joint_vectors(self, q6: np.ndarray, values: np.ndarray) -> np.ndarray:
        """The 7R joint vectors (n, B, 7) [rad] of 6R branches (n, B, 6) at held values (n,)."""
        out = np.empty(q6.shape[:2] + (7,))
        out[..., self.others] = q6
        out[..., self.free] = values[:, None]
        return out


def held_end(
    table: DHTable, free: int, structure: ClosedFormStructure, flips: np.ndarray | None
) -> HeldEnd:
    """:class:`HeldEnd` of ``table`` with joint ``free`` (0 or 6) held, the rest ``structure``."""
    return HeldEnd(
        table=table,
        free=free,
        structure=structure,
        flips=flips,
        others=[i for i in range(7) if i != free],
        outer=table.T_world_base if free == 0 else table.T_last_tool,
        chain=chain_transforms(six_r_table(table, free))[0],
    )
