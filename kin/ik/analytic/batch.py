"""Batched closed-form IK: N targets at once, every branch, vectorized with NumPy over N.

The same formulas as the scalar solvers (:mod:`ik.planar2r`, :mod:`ik.offset3r`,
:mod:`ik.five_dof`), on arrays. Verification uses a vectorized NumPy forward kinematics of the same
DH table (:func:`dh_forward_kinematics`: ``T_world_base`` then the standard DH product then
``T_last_tool``), not Pinocchio: the per-call API (:class:`~ik.closed_form.ClosedFormSolver`)
verifies with Pinocchio, and the tests check that this NumPy FK agrees with it.

Branches come in a fixed order, :attr:`BatchResult.branch_names`: base angle 1 (towards the
target) and 2, each with the elbow angle's sine positive then negative. A free joint at a
singularity is set to 0; angles are wrapped to ``(-pi, pi]`` then moved by ``2 pi`` into the limits
when that helps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable
from kin import RobotModel, batch_forward_kinematics

from ..exceptions import TargetError
from ..judge import batch_axis_errors, batch_pose_errors
from .branches import REACH_TOL
from .planar2r import MERGE_COS
from .structure import FiveDof, Link, Offset3R, Planar2R, recognise


def _fk_columns(table: DHTable, q: np.ndarray) -> tuple[list[np.ndarray], np.ndarray]:
    """Tool rotation columns (three (3, M) arrays) and position (3, M) of ``q`` (M, nq)."""
    m = q.shape[0]
    base = np.asarray(table.T_world_base, dtype=float)
    qt = np.ascontiguousarray((q + np.array([row.theta for row in table.rows])).T)
    cosines, sines = np.cos(qt), np.sin(qt)
    ones = np.ones(m)
    cols = [base[:3, j][:, None] * ones for j in range(3)]
    p = base[:3, 3][:, None] * ones
    identity = np.array_equal(base, np.eye(4))
    for i, row in enumerate(table.rows):
        ct, st = cosines[i], sines[i]
        ca, sa = round(math.cos(row.alpha), 15), round(math.sin(row.alpha), 15)
        if i == 0 and identity:
            zero = np.zeros(m)
            cols = [
                np.stack([ct, st, zero]),
                np.stack([-st * ca, ct * ca, sa * ones]),
                np.stack([st * sa, -ct * sa, ca * ones]),
            ]
            p = np.stack([row.a * ct, row.a * st, row.d * ones])
            continue
        c0, c1, c2 = cols
        new0 = c0 * ct + c1 * st
        other = c1 * ct - c0 * st
        new1 = other * ca if sa == 0.0 else other * ca + c2 * sa
        new2 = c2 * ca if sa == 0.0 else c2 * ca - other * sa
        if row.a != 0.0:
            p = p + row.a * new0
        if row.d != 0.0:
            p = p + row.d * c2
        cols = [new0, new1, new2]
    tool = np.asarray(table.T_last_tool, dtype=float)
    if not np.array_equal(tool, np.eye(4)):
        p = p + sum(cols[k] * tool[k, 3] for k in range(3))
        cols = [sum(cols[k] * tool[k, j] for k in range(3)) for j in range(3)]
    return cols, p


def dh_forward_kinematics(table: DHTable, q: npt.ArrayLike) -> np.ndarray:
    """Tool poses ``T_world_tool`` (M, 4, 4) of joint vectors ``q`` (M, nq), standard DH, NumPy.

    ``T_world_base``, then ``Rz(q + theta) Tz(d) Tx(a) Rx(alpha)`` per row, then ``T_last_tool``;
    computed column by column on arrays of length M.
    """
    q = np.asarray(q, dtype=float).reshape(-1, table.dof)
    cols, p = _fk_columns(table, q)
    out = np.zeros((q.shape[0], 4, 4))
    for j in range(3):
        out[:, :3, j] = cols[j].T
    out[:, :3, 3] = p.T
    out[:, 3, 3] = 1.0
    return out


@dataclass(frozen=True, eq=False)
class BatchResult:
    """All branches of N targets.

    Attributes:
        branch_names: Meaning of each of the B branch columns.
        q: Joint vectors (N, B, nq) [rad]; NaN where a branch does not exist.
        reached: (N, B) the branch exists and FK reproduces the target within the tolerances.
        within_limits: (N, B) the joint vector is inside the limits.
        elbow_up: (N, B) the elbow is above the line from shoulder to wrist (world z); for the
            planar arm, on the counter-clockwise side of the line from base to target.
        position_error: (N, B) [m], NumPy FK.
        rotation_error: (N, B) [rad] (pose: angle of ``R_fk^T R``; pitch: between approach axes).
    """

    branch_names: tuple[str, ...]
    q: np.ndarray
    reached: np.ndarray
    within_limits: np.ndarray
    elbow_up: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """(N, B) reached and within limits."""
        return self.reached & self.within_limits


def _two_link(x: np.ndarray, y: np.ndarray, link1: Link, link2: Link) -> tuple[np.ndarray, ...]:
    """Vectorized :func:`ik.planar2r.two_link`: (t1, t2, sin_b2, exists) of shape (N, 2)."""
    l1, l2 = link1.length, link2.length
    r = np.hypot(x, y)
    exists = np.maximum(r - (l1 + l2), abs(l1 - l2) - r) <= REACH_TOL
    cos_b2 = np.clip((x * x + y * y - l1 * l1 - l2 * l2) / (2.0 * l1 * l2), -1.0, 1.0)
    cos_b2 = np.where(np.abs(cos_b2) >= MERGE_COS, np.sign(cos_b2), cos_b2)
    sin_abs = np.sqrt(np.maximum(0.0, 1.0 - cos_b2 * cos_b2))
    sin_b2 = np.stack([sin_abs, -sin_abs], axis=-1)
    cos_b2 = cos_b2[..., None]
    b2 = np.arctan2(sin_b2, cos_b2)
    b1 = np.arctan2(y, x)[..., None] - np.arctan2(l2 * sin_b2, l1 + l2 * cos_b2)
    t1 = b1 - link1.angle
    t2 = b2 - link2.angle + link1.angle
    return t1, t2, sin_b2, np.broadcast_to(exists[..., None], t1.shape)


#: Targets per vectorized chunk (arrays stay in cache).
CHUNK = 8192


def _chunked(solve, n: int, *arrays: np.ndarray) -> BatchResult:  # noqa: ANN001
    """Run ``solve`` on slices of at most :data:`CHUNK` targets and join the results."""
    if n <= CHUNK:
        return solve(*arrays)
    parts = [solve(*(a[i : i + CHUNK] for a in arrays)) for i in range(0, n, CHUNK)]
    first = parts[0]
    return BatchResult(
        first.branch_names,
        *(
            np.concatenate([getattr(r, f) for r in parts])
            for f in (
                "q",
                "reached",
                "within_limits",
                "elbow_up",
                "position_error",
                "rotation_error",
            )
        ),
    )


class BatchSolver:
    """Vectorized closed-form IK of one small arm.

    Args:
        robot: The loaded robot.
        tolerance_position: Largest position error of a reached branch [m].
        tolerance_rotation: Largest rotation error of a reached branch [rad].

    Raises:
        StructureError: The table fits no closed form.
    """

    def __init__(
        self, robot: RobotModel, tolerance_position: float = 1e-9, tolerance_rotation: float = 1e-9
    ):
        self.robot = robot
        self.table = robot.table
        self.structure = recognise(robot.table)
        self.tolerance_position = tolerance_position
        self.tolerance_rotation = tolerance_rotation
        self._offsets = np.array([row.theta for row in robot.table.rows])
        self._lower, self._upper = robot.lower, robot.upper
        base = np.asarray(robot.table.T_world_base, dtype=float)
        self._base_inv = np.linalg.inv(base)
        self._base_identity = bool(np.array_equal(base, np.eye(4)))
        self._tool_identity = isinstance(self.structure, FiveDof) and bool(
            np.array_equal(self.structure.R_roll_tool, np.eye(3))
        )

    def _to_frame0(self, positions: np.ndarray) -> np.ndarray:
        if self._base_identity:
            return positions
        return positions @ self._base_inv[:3, :3].T + self._base_inv[:3, 3]

    def _wrap(self, thetas: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        q = thetas - self._offsets
        q -= (2 * np.pi) * np.rint(q / (2 * np.pi))
        inside = np.ones(q.shape[:-1], dtype=bool)
        for i in range(q.shape[-1]):
            lo, hi = self._lower[i] - 1e-10, self._upper[i] + 1e-10
            column = q[..., i]
            ok = (column >= lo) & (column <= hi)
            if hi > np.pi or lo < -np.pi:
                for shift in (2 * np.pi, -2 * np.pi):
                    moved = column + shift
                    better = ~ok & (moved >= lo) & (moved <= hi)
                    column = np.where(better, moved, column)
                    ok |= better
                q[..., i] = column
            inside &= ok
        return q, inside

    def solve_positions(self, positions: npt.ArrayLike) -> BatchResult:
        """All branches for N tool points (N, 3) [m] of a planar 2R or offset 3R arm."""
        p = np.asarray(positions, dtype=float).reshape(-1, 3)
        if p.shape[0] > CHUNK:
            return _chunked(self.solve_positions, p.shape[0], p)
        s = self.structure
        p0 = self._to_frame0(p)
        if isinstance(s, Planar2R):
            t1, t2, sin_b, exists = _two_link(p0[:, 0], p0[:, 1], s.link1, s.link2)
            exists = exists & (np.abs(p0[:, 2] - s.height) <= REACH_TOL)[:, None]
            thetas = np.stack([t1, t2], axis=-1)
            return self._finish(("elbow +", "elbow -"), thetas, exists, sin_b < 0, p, None, None)
        if isinstance(s, Offset3R):
            rho = np.hypot(p0[:, 0], p0[:, 1])
            phi = np.arctan2(p0[:, 1], p0[:, 0])
            with np.errstate(divide="ignore", invalid="ignore"):
                delta = np.arcsin(np.clip(s.sign1 * s.lateral / rho, -1.0, 1.0))
            reach = np.sqrt(np.maximum(0.0, rho * rho - s.lateral**2))
            v = s.sign1 * (p0[:, 2] - s.d1)
            columns = []
            for base, radial in ((phi + delta, reach), (phi + np.pi - delta, -reach)):
                u = radial - s.a1
                t2, t3, sin_b, exists = _two_link(u, v, s.link2, s.link3)
                exists = exists & (rho >= abs(s.lateral) - REACH_TOL)[:, None]
                up = s.sign1 * np.where(u >= 0, 1.0, -1.0)[:, None] * sin_b < 0
                columns.append(
                    (np.stack([np.broadcast_to(base[:, None], t2.shape), t2, t3], -1), exists, up)
                )
            thetas = np.concatenate([c[0] for c in columns], axis=1)
            exists = np.concatenate([c[1] for c in columns], axis=1)
            up = np.concatenate([c[2] for c in columns], axis=1)
            names = ("base 1, elbow +", "base 1, elbow -", "base 2, elbow +", "base 2, elbow -")
            return self._finish(names, thetas, exists, up, p, None, None)
        raise TargetError(
            f"'{self.robot.name}' is a five-joint arm: use solve_poses or solve_pitch"
        )

    def _five(self, p0: np.ndarray, a0: np.ndarray, base1: np.ndarray) -> tuple[np.ndarray, ...]:
        s = self.structure
        assert isinstance(s, FiveDof)
        columns = []
        for base in (base1, base1 + np.pi):
            c1, n1 = np.cos(base), np.sin(base)
            a_r = a0[:, 0] * c1 + a0[:, 1] * n1
            sin_psi = s.sign1 * a0[:, 2]
            cos_phi, sin_phi = -s.sign4 * sin_psi, s.sign4 * a_r
            phi = np.arctan2(sin_phi, cos_phi)
            p_r = p0[:, 0] * c1 + p0[:, 1] * n1
            u = p_r - s.reach * a_r - s.a4 * cos_phi - s.a1
            v = s.sign1 * (p0[:, 2] - s.d1) - s.reach * sin_psi - s.a4 * sin_phi
            t2, t3, sin_b, exists = _two_link(u, v, s.link2, s.link3)
            up = s.sign1 * np.where(u >= 0, 1.0, -1.0)[:, None] * sin_b < 0
            t1 = np.broadcast_to(base[:, None], t2.shape)
            t4 = phi[:, None] - t2 - t3
            columns.append((np.stack([t1, t2, t3, t4, np.zeros_like(t2)], -1), exists, up))
        thetas = np.concatenate([c[0] for c in columns], axis=1)
        exists = np.concatenate([c[1] for c in columns], axis=1)
        up = np.concatenate([c[2] for c in columns], axis=1)
        return thetas, exists, up

    _FIVE_NAMES = (
        "shoulder 1, elbow +",
        "shoulder 1, elbow -",
        "shoulder 2, elbow +",
        "shoulder 2, elbow -",
    )

    def solve_poses(self, poses: npt.ArrayLike) -> BatchResult:
        """All branches for N tool poses ``T_world_tool`` (N, 4, 4) of a five-joint arm."""
        s = self.structure
        if not isinstance(s, FiveDof):
            raise TargetError(f"'{self.robot.name}' takes positions: use solve_positions")
        T = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
        if T.shape[0] > CHUNK:
            return _chunked(self.solve_poses, T.shape[0], T)
        T0 = T if self._base_identity else self._base_inv @ T
        p0 = T0[:, :3, 3]
        r5 = T0[:, :3, :3] if self._tool_identity else T0[:, :3, :3] @ s.R_roll_tool.T
        a0 = r5[:, :, 2]
        use_p = np.hypot(p0[:, 0], p0[:, 1]) >= np.hypot(a0[:, 0], a0[:, 1]) * (
            s.link2.length + s.link3.length
        )
        base1 = np.where(use_p, np.arctan2(p0[:, 1], p0[:, 0]), np.arctan2(a0[:, 1], a0[:, 0]))
        normal = np.stack([np.sin(base1), -np.cos(base1)], -1)
        in_plane = (np.abs((a0[:, :2] * normal).sum(-1)) <= 1e-9) & (
            np.abs((p0[:, :2] * normal).sum(-1)) <= 1e-9
        )
        thetas, exists, up = self._five(p0, a0, base1)
        exists = exists & in_plane[:, None]
        # wrist roll: angle from x4 to the roll frame's x axis about the approach axis
        t1, phi = thetas[..., 0], thetas[..., 1] + thetas[..., 2] + thetas[..., 3]
        c1, n1, cp, sp = np.cos(t1), np.sin(t1), np.cos(phi), np.sin(phi)
        x4 = (cp * c1, cp * n1, s.sign1 * sp)
        z4 = (s.sign4 * sp * c1, s.sign4 * sp * n1, -s.sign1 * s.sign4 * cp)
        y4 = (
            z4[1] * x4[2] - z4[2] * x4[1],
            z4[2] * x4[0] - z4[0] * x4[2],
            z4[0] * x4[1] - z4[1] * x4[0],
        )
        x5 = [r5[:, k, 0][:, None] for k in range(3)]
        thetas[..., 4] = np.arctan2(
            y4[0] * x5[0] + y4[1] * x5[1] + y4[2] * x5[2],
            x4[0] * x5[0] + x4[1] * x5[1] + x4[2] * x5[2],
        )
        return self._finish(self._FIVE_NAMES, thetas, exists, up, T[:, :3, 3], T[:, :3, :3], None)

    def solve_pitch(
        self, positions: npt.ArrayLike, pitch: npt.ArrayLike, roll: npt.ArrayLike = 0.0
    ) -> BatchResult:
        """All branches for N tool points (N, 3) with approach pitch [rad] and wrist roll q5 [rad]."""
        s = self.structure
        if not isinstance(s, FiveDof):
            raise TargetError(f"'{self.robot.name}' takes positions: use solve_positions")
        p = np.asarray(positions, dtype=float).reshape(-1, 3)
        n = p.shape[0]
        pitch = np.broadcast_to(np.asarray(pitch, dtype=float), (n,))
        roll = np.broadcast_to(np.asarray(roll, dtype=float), (n,))
        if n > CHUNK:
            return _chunked(self.solve_pitch, n, p, pitch, roll)
        p0 = self._to_frame0(p)
        h = np.arctan2(p0[:, 1], p0[:, 0])
        a0 = np.stack([np.cos(pitch) * np.cos(h), np.cos(pitch) * np.sin(h), -np.sin(pitch)], -1)
        thetas, exists, up = self._five(p0, a0, h)
        thetas[..., 4] = (roll + self._offsets[4])[:, None]
        approach = a0 @ self._base_inv[:3, :3]  # back to world: R_wb a0
        return self._finish(self._FIVE_NAMES, thetas, exists, up, p, None, approach)

    def _finish(self, names, thetas, exists, up, p, rotation, approach) -> BatchResult:  # noqa: ANN001
        n, b, nq = thetas.shape
        q, inside = self._wrap(thetas)
        poses = batch_forward_kinematics(self.table, q.reshape(-1, nq))
        positions = np.repeat(p, b, axis=0)
        rotations = None if rotation is None else np.repeat(rotation, b, axis=0)
        position_error, rotation_error = batch_pose_errors(poses, positions, rotations)
        if rotation_error is None and approach is not None:
            assert isinstance(self.structure, FiveDof)  # a pitch target: five-joint arms only
            axes = poses[:, :3, :3] @ self.structure.R_roll_tool[2, :]
            rotation_error = batch_axis_errors(axes, np.repeat(approach, b, axis=0))
        position_error = position_error.reshape(n, b)
        if rotation_error is None:
            rotation_error = np.zeros((n, b))
        else:
            rotation_error = rotation_error.reshape(n, b)
        reached = (
            exists
            & np.isfinite(position_error)
            & (position_error <= self.tolerance_position)
            & (rotation_error <= self.tolerance_rotation)
        )
        q = np.where(exists[..., None], q, np.nan)
        return BatchResult(
            tuple(names), q, reached, inside & exists, up, position_error, rotation_error
        )
