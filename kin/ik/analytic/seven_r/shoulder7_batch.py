"""The batched steps of :class:`~.spherical_shoulder7.SphericalShoulder7RIK`: N poses in NumPy.

The same arithmetic as :meth:`~.spherical_shoulder7.SphericalShoulder7RIK.branches` (elbow,
wrist, shoulder), array by array, for N targets at their joint-7 values (:class:`Shoulder7Batch`,
held by the solver, reads the arm's constants from its
:class:`~.shoulder7_frames.Shoulder7Frames`);
:meth:`Shoulder7Batch.solve_batch` of one pose equals
:meth:`~.spherical_shoulder7.SphericalShoulder7RIK.solve` (the tests hold them to it). Angles in
[rad], lengths in [m].
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from ...angles import wrap_array
from ...exceptions import TargetError
from .shoulder7_frames import Shoulder7Frames
from .subproblems import harmonic_roots_array, rotation_pair_array

#: Branches per joint-7 value: 2 elbows x 2 wrists x 2 shoulders.
BRANCHES = 8


class Shoulder7Batch:
    """:meth:`solve_batch` of a :class:`~.spherical_shoulder7.SphericalShoulder7RIK` (held by it).

    Args:
        frames: The arm's constants and frames (:class:`~.shoulder7_frames.Shoulder7Frames`).
    """

    def __init__(self, frames: Shoulder7Frames):
        self.frames = frames

    def solve_batch(
        self, positions: npt.ArrayLike, rotations: npt.ArrayLike, q7: npt.ArrayLike
    ) -> np.ndarray:
        """:meth:`solve` of N targets at once, in NumPy.

        Args:
            positions: Tool positions in the world frame [m], (N, 3).
            rotations: Tool rotations ``R_world_tool``, (N, 3, 3).
            q7: Joint-7 values [rad], (N,) (or one value for all).

        Returns:
            (N, 8, 7) joint vectors [rad], the rows of :meth:`solve`, NaN where no branch.

        Raises:
            TargetError: Shapes other than (N, 3), (N, 3, 3) and (N,).
        """
        p = np.asarray(positions, dtype=float)
        r = np.asarray(rotations, dtype=float)
        if p.ndim != 2 or p.shape[1] != 3 or r.shape != (p.shape[0], 3, 3):
            raise TargetError(
                f"positions must be (N, 3) and rotations (N, 3, 3), got {p.shape} and {r.shape}"
            )
        n = p.shape[0]
        q7 = np.broadcast_to(np.asarray(q7, dtype=float), (n,)) if np.ndim(q7) == 0 else q7
        q7 = np.asarray(q7, dtype=float)
        if q7.shape != (n,):
            raise TargetError(f"q7 must be ({n},), got {q7.shape}")
        frames = self.frames
        s, c, off = frames.sin, frames.cos, frames.offsets
        rk, e = frames.prepare_array(p, r)
        t7 = q7 + off[6]
        c7, s7 = np.cos(t7), np.sin(t7)
        rv = np.stack((c7 * e[:, 0] - s7 * e[:, 1], s7 * e[:, 0] + c7 * e[:, 1], e[:, 2]), 1)
        rv -= np.asarray(frames.c7)
        m7 = np.asarray(frames.m7_rot)
        v6 = rv @ m7.T
        z7 = np.zeros((n, 3, 3))
        z7[:, 0, 0], z7[:, 0, 1], z7[:, 1, 0], z7[:, 1, 1], z7[:, 2, 2] = c7, s7, -s7, c7, 1.0
        k6 = rk @ z7 @ m7.T  # R_K_J6 = R_K_J7 Rz(-t7) M_7^T
        distance2 = np.einsum("ni,ni->n", rv, rv)
        out = np.full((n, BRANCHES, 7), np.nan)
        out[:, :, 6] = q7[:, None]
        elbows = harmonic_roots_array(
            np.full(n, frames.p4), np.full(n, frames.q4), frames.k4 - 0.5 * distance2
        )
        u, w4 = np.asarray(frames.u), np.asarray(frames.w4)
        for ei in range(2):
            t4 = elbows[:, ei]
            c4, s4 = np.cos(t4), np.sin(t4)
            vx = c4 * u[0] + s4 * u[1] - w4[0]
            vy = c4 * u[1] - s4 * u[0] - w4[1]
            vz = np.full(n, u[2] - w4[2])
            d = np.stack((vx, c[5] * vy + s[5] * vz, c[5] * vz - s[5] * vy), 1)
            wrists = rotation_pair_array(s[6], c[6], v6, d)
            for wi in range(2):
                t5, t6 = wrists[:, wi, 0], wrists[:, wi, 1]
                turns = ((t4, s[5], c[5]), (t5, s[6], c[6]), (t6, 0.0, 1.0))
                z = _back_array(k6, turns, np.array([0.0, s[4], c[4]]))
                x = _back_array(k6, turns, np.array([1.0, 0.0, 0.0]))
                v3 = np.broadcast_to(np.array([0.0, -s[3], c[3]]), (n, 3))
                shoulders = rotation_pair_array(s[2], c[2], v3, z)
                for si in range(2):
                    t1, t2 = shoulders[:, si, 0], shoulders[:, si, 1]
                    ct, st = np.cos(t1), np.sin(t1)
                    nx, ny, nz = ct * x[:, 0] + st * x[:, 1], ct * x[:, 1] - st * x[:, 0], x[:, 2]
                    ny, nz = c[2] * ny + s[2] * nz, c[2] * nz - s[2] * ny
                    ct, st = np.cos(t2), np.sin(t2)
                    nx, ny = ct * nx + st * ny, ct * ny - st * nx
                    ny = c[3] * ny + s[3] * nz
                    t3 = np.arctan2(ny, nx)
                    slot = 4 * ei + 2 * wi + si
                    for j, t in enumerate((t1, t2, t3, t4, t5, t6)):
                        out[:, slot, j] = wrap_array(t - off[j])
        missing = np.isnan(out[:, :, :6]).any(axis=2)
        out[missing] = np.nan
        return out


def _back_array(
    k6: np.ndarray, turns: tuple[tuple[np.ndarray, float, float], ...], v: np.ndarray
) -> np.ndarray:
    """``R_K_J6 ... Rz(-t) Rx(alpha)^T ... v`` of N rotations ``k6`` (N, 3, 3): (N, 3).

    ``turns``: ``(t (N,), sin alpha, cos alpha)`` each, ``Rz(-t)`` then ``Rx(alpha)^T``.
    """
    x, y, z = (np.full(k6.shape[0], value) for value in v)
    for t, sa, ca in turns:
        ct, st = np.cos(t), np.sin(t)
        x, y = ct * x + st * y, ct * y - st * x
        y, z = ca * y + sa * z, ca * z - sa * y
    return np.einsum("nij,nj->ni", k6, np.stack((x, y, z), 1))
