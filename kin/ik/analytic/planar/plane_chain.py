"""A chain of parallel joint axes in its plane: the geometry and the two-link solves.

Every revolute axis and every prismatic direction is parallel to one unit vector ``n`` (the
first joint's axis). In 2D coordinates of a basis ``e1, e2`` normal to ``n``, with the revolute
joints ``r1, r2, (r3)`` and the link vectors ``L_k`` between their axes (the last one to the tool
point) read at ``q = 0``: ``P = c1 + Rot(phi1) L1 + Rot(phi2) L2 (+ Rot(phi3) L3)``, where
``phi_k = sum_{j <= k} s_j q_rj`` and ``s_j = +-1`` says whether axis ``rj`` points along ``n``
or against it; along ``n`` the slide moves the tool, ``(p - c1) . n = h0 + s_p q_p``; the tool
turns about ``n`` only: ``R = Rot(n, phi_last) R0``.

:class:`PlaneChain` holds what depends on the chain alone (as arrays and as plain floats, read
once when it is built) and solves it: the two elbow branches of a tool point with the last
link's angle ``psi`` given (three revolute joints: the wrist point ``W = P - Rot(psi) L3``), one
``psi`` in plain floats (:meth:`~PlaneChain.solve_angle`, the single-target path) or many in
NumPy (:func:`solve_angles`, the sweeps). The closed-form structures hold one:
:class:`~.parallel_axes.ParallelAxes` (the whole arm) and the ``yaw_planar`` arms (their pitch chain).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable
from dh2urdf.dh_table import dh_link_transform

from ...exceptions import StructureError
from .free_angle import Row

#: Largest ``|u_i x n|`` of an axis taken as parallel to ``n``.
PARALLEL_TOL = 1e-9


def joint_axes(table: DHTable) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Per joint its axis direction and a point on it (world, ``q = 0``), and ``T_world_tool``."""
    frame = np.asarray(table.T_world_base, dtype=float)
    directions, points = [], []
    for row in table.rows:
        if table.convention == "standard":
            axis_frame = frame
            frame = frame @ dh_link_transform(
                "standard", row.a, row.alpha, row.d, row.theta, row.beta
            )
        else:
            axis_frame = frame @ dh_link_transform("modified", row.a, row.alpha, 0.0, 0.0, row.beta)
            frame = frame @ dh_link_transform(
                "modified", row.a, row.alpha, row.d, row.theta, row.beta
            )
        directions.append(axis_frame[:3, 2].copy())
        points.append(axis_frame[:3, 3].copy())
    return directions, points, frame @ np.asarray(table.T_last_tool, dtype=float)


#: A turn [rad].
_TURN = 2.0 * math.pi


def _wrapped(angle: float) -> float:
    """``angle`` [rad] in ``[-pi, pi)``."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class PlaneChain:
    """Two or three parallel revolute joints and at most one slide (see the module).

    Attributes:
        n: The common axis direction in the world frame (the first joint's); ``e1, e2`` the
            plane's basis.
        signs: Per revolute joint (in order), +1 or -1: its axis along ``n`` or against it.
        links: The link vectors ``L_k`` (2,) [m] in the plane at ``q = 0``.
        origin: The first revolute axis in the plane [m]; ``base_point`` a point on it (world).
        height: The tool point's height [m] along ``n`` from ``base_point`` at ``q = 0``.
        tool_rotation: ``R_world_tool`` at ``q = 0``.
    """

    name: ClassVar[str] = "parallel_axes"

    def __init__(
        self,
        name: str,
        directions: list[np.ndarray],
        points: list[np.ndarray],
        tool: np.ndarray,
        kinds: list[str],
    ):
        """The chain given by its joint axes (world, at ``q = 0``) and tool pose.

        Args:
            name: The arm's name (for errors).
            directions: Per joint its axis direction, world, at ``q = 0``.
            points: Per joint a point on its axis [m].
            tool: ``T_world_tool`` at ``q = 0``.
            kinds: Per joint ``"revolute"`` or ``"prismatic"``.

        Raises:
            StructureError: The axes are not all parallel, or the joint counts do not fit.
        """
        n = directions[0] / np.linalg.norm(directions[0])
        for i, u in enumerate(directions):
            if np.linalg.norm(np.cross(u, n)) > PARALLEL_TOL:
                raise StructureError(
                    name,
                    self.name,
                    f"{len(kinds)} joints whose axes are not all parallel (joint {i + 1}'s is not "
                    "parallel to joint 1's)",
                )
        self.revolute = [i for i, kind in enumerate(kinds) if kind == "revolute"]
        self.prismatic = [i for i, kind in enumerate(kinds) if kind == "prismatic"]
        if len(self.revolute) not in (2, 3) or len(self.prismatic) > 1:
            raise StructureError(
                name,
                self.name,
                f"{len(self.revolute)} revolute and {len(self.prismatic)} prismatic joints "
                "(parallel axes: 2 or 3 revolute, at most 1 prismatic)",
            )
        self.n = n
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        self.e1 = np.cross(n, helper)
        self.e1 /= np.linalg.norm(self.e1)
        self.e2 = np.cross(n, self.e1)
        self.signs = [float(np.sign(directions[i] @ n)) for i in self.revolute]
        centres = [self._plane(points[i]) for i in self.revolute] + [self._plane(tool[:3, 3])]
        self.origin = centres[0]
        self.links = [centres[k + 1] - centres[k] for k in range(len(self.revolute))]
        self.height = float((tool[:3, 3] - points[self.revolute[0]]) @ n)
        self.base_point = points[self.revolute[0]]
        self.prismatic_sign = (
            float(np.sign(directions[self.prismatic[0]] @ n)) if self.prismatic else 0.0
        )
        self.tool_rotation = tool[:3, :3]
        self.nq = len(kinds)
        self.tool_on_axis = len(self.links) == 3 and float(self.links[2] @ self.links[2]) < 1e-24
        # Plain floats of the single-target path, read once: the plane's basis, the base point,
        # the links, and the elbow's constants (``a``, ``b`` of the two links, their spread).
        self._basis = (tuple(self.e1.tolist()), tuple(self.e2.tolist()), tuple(self.n.tolist()))
        self._base = tuple(self.base_point.tolist())
        self._origin = (float(self.origin[0]), float(self.origin[1]))
        self._links = tuple(tuple(link.tolist()) for link in self.links)
        (l1x, l1y), (l2x, l2y) = self._links[:2]
        a, b = l1x * l2x + l1y * l2y, l1y * l2x - l1x * l2y
        self._elbow = (
            math.hypot(a, b),
            math.atan2(b, a),
            l1x * l1x + l1y * l1y + l2x * l2x + l2y * l2y,
        )
        # ``e_i . R R0^T e_j`` = ``e_i . R (R0^T e_j)``: the yaw of a rotation (:meth:`yaw`)
        self._yaw_columns = tuple(
            tuple((self.tool_rotation.T @ e).tolist()) for e in (self.e1, self.e2)
        )
        self._joint_order = tuple(zip(self.revolute, self.signs))

    def _plane(self, point: np.ndarray) -> np.ndarray:
        return np.array([point @ self.e1, point @ self.e2])

    def along(self, point: np.ndarray) -> float:
        """The point's height [m] along ``n`` from the first revolute axis's point."""
        return float((point - self.base_point) @ self.n)

    def yaw(self, rotation: np.ndarray | list[list[float]]) -> float:
        """The angle [rad] about ``n`` of the rotation about ``n`` nearest ``R R0^T``.

        ``rotation``: ``R`` as an array or as rows of plain floats.
        """
        rows = rotation.tolist() if isinstance(rotation, np.ndarray) else rotation
        (r0, r1, r2) = rows
        e1, e2, _ = self._basis
        turned = []
        for c in self._yaw_columns:  # R R0^T e_j, in the world
            turned.append(
                (
                    r0[0] * c[0] + r0[1] * c[1] + r0[2] * c[2],
                    r1[0] * c[0] + r1[1] * c[1] + r1[2] * c[2],
                    r2[0] * c[0] + r2[1] * c[1] + r2[2] * c[2],
                )
            )
        (u1, u2) = turned
        m11 = e1[0] * u1[0] + e1[1] * u1[1] + e1[2] * u1[2]
        m21 = e2[0] * u1[0] + e2[1] * u1[1] + e2[2] * u1[2]
        m12 = e1[0] * u2[0] + e1[1] * u2[1] + e1[2] * u2[2]
        m22 = e2[0] * u2[0] + e2[1] * u2[1] + e2[2] * u2[2]
        return math.atan2(m21 - m12, m11 + m22)

    def last_angle(self, q: np.ndarray | list[float] | tuple[float, ...]) -> float:
        """The last link's angle ``psi`` [rad] about ``n`` at the joint vector ``q``."""
        return float(sum(sign * q[i] for i, sign in zip(self.revolute, self.signs)))

    def in_plane(self, position: tuple[float, float, float] | list[float]) -> tuple[float, float]:
        """A world point [m] in the plane's coordinates from the first revolute axis [m]."""
        (e1, e2, _), (ox, oy) = self._basis, self._origin
        x, y, z = position
        return x * e1[0] + y * e1[1] + z * e1[2] - ox, x * e2[0] + y * e2[1] + z * e2[2] - oy

    def slide(self, position: tuple[float, float, float] | list[float]) -> float | None:
        """The slide [m] putting the tool at the point's height along ``n`` (None: no slide)."""
        if not self.prismatic:
            return None
        n, base = self._basis[2], self._base
        along = (position[0] - base[0]) * n[0] + (position[1] - base[1]) * n[1]
        return self.prismatic_sign * (along + (position[2] - base[2]) * n[2] - self.height)

    def walk_data(self, lower: Sequence[float], upper: Sequence[float]) -> tuple[float, ...] | None:
        """The chain as the compiled walk takes it (:func:`.free_angle.compiled_walk`).

        ``lower``, ``upper``: the three revolute joints' limits [rad]. None: not three revolute
        joints alone (the walk in Python).
        """
        if len(self.revolute) != 3 or self.prismatic:
            return None
        links = tuple(value for link in self._links for value in link)
        return links + self._elbow + tuple(self.signs) + tuple(lower) + tuple(upper)

    def elbows(self, wx: float, wy: float, slide: float | None, psi: float | None) -> list[Row]:
        """The two branches ``q`` [rad, m] putting the end of link 2 at ``(wx, wy)`` [m].

        In the plane's coordinates from the first revolute axis; with three revolute joints the
        last link at the angle ``psi`` [rad] about ``n``. Two all-NaN rows: out of reach.
        """
        rho, centre, lengths = self._elbow
        if rho < 1e-15 or not (abs(wx) < 1e150 and abs(wy) < 1e150):
            return [(math.nan,) * self.nq] * 2
        cosine = (wx * wx + wy * wy - lengths) / (2.0 * rho)
        if abs(cosine) > 1.0 + 1e-12:
            return [(math.nan,) * self.nq] * 2
        spread = math.acos(max(-1.0, min(1.0, cosine)))
        (l1x, l1y), (l2x, l2y) = self._links[:2]
        toward = math.atan2(wy, wx)
        rows = []
        for beta in (centre + spread, centre - spread):
            cb, sb = math.cos(beta), math.sin(beta)
            phi1 = toward - math.atan2(l1y + sb * l2x + cb * l2y, l1x + cb * l2x - sb * l2y)
            phis = (phi1, phi1 + beta) if psi is None else (phi1, phi1 + beta, psi)
            row = [math.nan] * self.nq
            previous = 0.0
            for phi, (i, sign) in zip(phis, self._joint_order):
                row[i] = (sign * (phi - previous) + math.pi) % _TURN - math.pi  # wrapped
                previous = phi
            if slide is not None:
                row[self.prismatic[0]] = slide
            rows.append(tuple(row))
        return rows

    def solve_angle(self, position: tuple[float, float, float], psi: float) -> list[Row]:
        """:func:`solve_angles` at one ``psi`` [rad] in plain floats: the two branches.

        Args:
            position: Tool point in the world [m].
            psi: The last link's angle about ``n`` [rad].

        Returns:
            Two rows ``q`` [rad, m] (all NaN: none), as :func:`solve_angles` ``[0]``.
        """
        tx, ty = self.in_plane(position)
        l3x, l3y = self._links[2]
        c, s = math.cos(psi), math.sin(psi)
        return self.elbows(
            tx - (c * l3x - s * l3y), ty - (s * l3x + c * l3y), self.slide(position), psi
        )

    def solve_chain(
        self,
        position: np.ndarray | tuple[float, float, float],
        rotation: np.ndarray | list[list[float]] | None,
    ) -> list[Row]:
        """The two branches ``q`` [rad, m] of a pose's projection (all NaN: none).

        Three revolute joints: the last link at the rotation's yaw (a rotation needed). Two: the
        position's two elbows; the tool on the last axis (no second link in the plane): the
        position fixes the first link's angle, the rotation's yaw the last one's, one branch.
        """
        point = (float(position[0]), float(position[1]), float(position[2]))
        if len(self.links) == 3:
            assert rotation is not None
            return self.solve_angle(point, self.yaw(rotation))
        if self._elbow[0] >= 1e-15:
            wx, wy = self.in_plane(point)
            return self.elbows(wx, wy, self.slide(point), None)
        none = [(math.nan,) * self.nq] * 2
        (l1x, l1y), (l2x, l2y) = self._links
        wx, wy = self.in_plane(point)
        if rotation is None or not (l2x * l2x + l2y * l2y < 1e-24 < l1x * l1x + l1y * l1y):
            return none
        if not (abs(wx) < 1e150 and abs(wy) < 1e150) or wx * wx + wy * wy < 1e-24:
            return none  # too far for any arm; or on the first axis: the first angle is free
        phi1 = math.atan2(wy, wx) - math.atan2(l1y, l1x)
        row = self.branch([phi1, self.yaw(rotation)], point)
        wrapped = tuple(_wrapped(v) if i in self.revolute else v for i, v in enumerate(row))
        return [wrapped, none[1]]

    def branch(self, phis: list[float], position: tuple[float, float, float]) -> Row:
        """One branch ``q`` from the links' absolute angles ``phis`` [rad] (not wrapped).

        Each joint angle is the change from the previous link's angle about ``n``, times its
        axis' sign; the slide [m] puts the tool at the position's height along ``n``.
        """
        row = [math.nan] * self.nq
        previous = 0.0
        for phi, (i, sign) in zip(phis, self._joint_order):
            row[i] = sign * (phi - previous)
            previous = phi
        slide = self.slide(position)
        if slide is not None:
            row[self.prismatic[0]] = slide
        return tuple(row)


def solve_angles(chain: PlaneChain, position: np.ndarray, psis: np.ndarray) -> np.ndarray:
    """Both branches (K, 2, dof) ``q`` [rad, m] of a position with the last link at ``psis``.

    Three revolute joints: the wrist point ``W = P - Rot(psi) L3`` is a two-link problem per
    ``psi`` [rad] (K,); NaN where it is out of reach (or the chain has no second link).
    """
    k = len(psis)
    out = np.full((k, 2, chain.nq), np.nan)
    l1, l2, l3 = chain.links
    rho, centre, lengths = chain._elbow
    target = chain._plane(np.asarray(position, dtype=float)) - chain.origin
    if rho < 1e-15 or not float(np.abs(target).max()) < 1e150:
        return out
    c, s = np.cos(psis), np.sin(psis)
    wx = target[0] - (c * l3[0] - s * l3[1])
    wy = target[1] - (s * l3[0] + c * l3[1])
    cosine = (wx * wx + wy * wy - lengths) / (2.0 * rho)
    spread = np.arccos(np.clip(cosine, -1.0, 1.0))
    beta = centre + np.stack([spread, -spread], axis=1)  # (K, 2)
    cb, sb = np.cos(beta), np.sin(beta)
    vx = l1[0] + cb * l2[0] - sb * l2[1]
    vy = l1[1] + sb * l2[0] + cb * l2[1]
    phi1 = np.arctan2(wy, wx)[:, None] - np.arctan2(vy, vx)
    phis = (phi1, phi1 + beta, np.broadcast_to(psis[:, None], phi1.shape))
    previous: np.ndarray | float = 0.0
    for phi, i, sign in zip(phis, chain.revolute, chain.signs):
        angle = sign * (phi - previous)
        out[:, :, i] = np.remainder(angle + math.pi, 2.0 * math.pi) - math.pi
        previous = phi
    if chain.prismatic:
        along = chain.along(np.asarray(position, dtype=float))
        out[:, :, chain.prismatic[0]] = chain.prismatic_sign * (along - chain.height)
    out[np.abs(cosine) > 1.0 + 1e-12] = np.nan
    return out
