"""Arms whose joint axes are all parallel: SCARA (RRPR, RRRP), planar 3R, planar 2R with a slide.

Every revolute axis and every prismatic direction is parallel to one unit vector ``n`` (the
first joint's axis). Then the tool moves in the plane normal to ``n`` by the revolute joints,
along ``n`` by the prismatic one, and turns about ``n`` only:

- in the plane (2D coordinates in a basis ``e1, e2`` normal to ``n``), with the revolute joints
  ``r1, r2, (r3)`` and the link vectors ``L_k`` between their axes (the last one to the tool
  point) read at ``q = 0``: ``P = c1 + Rot(phi1) L1 + Rot(phi2) L2 (+ Rot(phi3) L3)``, where
  ``phi_k = sum_{j <= k} s_j q_rj`` and ``s_j = +-1`` says whether axis ``rj`` points along
  ``n`` or against it;
- along ``n``: ``(p - c1) . n = h0 + s_p q_p`` for the prismatic joint;
- the tool rotation: ``R = Rot(n, phi_last) R0``.

Given a pose, the yaw ``psi`` is the angle of ``R_target R0^T`` about ``n`` (the nearest rotation
about ``n`` when the target is tilted: the arm cannot tilt its tool); with three revolute joints
``phi3 = psi`` and the wrist point ``W = P - Rot(psi) L3`` is a two-link problem, two branches
(the elbow's two sides); with two, the position alone gives the two branches. The candidates are
the projection of the target on what the arm reaches; the partial-pose solver
(:mod:`kin.ik.partial_pose`) measures them on the target's constrained components and reports
the nearest pose when they miss.

A position leaves the yaw free (:meth:`ParallelAxes.free_branches`): with the tool on the last
axis (a SCARA's RRPR) the last joint keeps the seed's value; else (a planar 3R, a tool off the
last axis) the yaw is the seed's ``psi``, or, when no branch there is inside the joint limits,
the nearest one of a 1-degree sweep away from it (:func:`sweep_angles`) that has one. The
branches are exact at that yaw: the stated value of the free angle.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import ClassVar

import numpy as np

from dh2urdf import DHTable
from dh2urdf.dh_table import dh_link_transform

from ...exceptions import StructureError
from ...target import PoseTarget, PositionTarget, Target
from ..branches import REACH_TOL, Branches
from ..closed_form_structure import BatchBranches, candidate_branches

#: Largest ``|u_i x n|`` of an axis taken as parallel to ``n``.
PARALLEL_TOL = 1e-9
#: Steps of the sweep of a free angle over a turn (:func:`sweep_angles`): 1 degree.
SWEEP_STEPS = 360
#: Steps of the first, coarse sweep: 10 degrees (:func:`free_angle_branches`).
COARSE_STEPS = 36
#: Slack on the joint limits [rad] or [m] of the sweep's choice (the judge decides after).
LIMIT_SLACK = 1e-10


def sweep_angles(start: float, steps: int = SWEEP_STEPS) -> np.ndarray:
    """Angles [rad] of a turn in ``steps`` equal steps from ``start``, nearest it first.

    ``start + d, start - d, start + 2 d, ...`` with ``d = 2 pi / steps`` (``start`` itself not
    included), ``steps - 1`` values.
    """
    k = np.arange(1, steps // 2 + 1)
    order = np.stack([k, -k], axis=1).reshape(-1)[: steps - 1]
    return start + order * (2.0 * math.pi / steps)


def inside_limits(
    q: np.ndarray, lower: np.ndarray, upper: np.ndarray, revolute: np.ndarray
) -> np.ndarray:
    """Whether each joint vector of ``q`` (..., nq) has every value inside the limits.

    A revolute angle [rad] counts as inside when a ``2 pi`` copy of it is; a slide [m] must be.
    NaN rows are outside.
    """
    copy = np.where(revolute, lower + np.remainder(q - lower, 2.0 * math.pi), q)
    with np.errstate(invalid="ignore"):
        ok = (copy >= lower - LIMIT_SLACK) & (copy <= upper + LIMIT_SLACK)
    return np.asarray(ok.all(axis=-1))


#: One branch ``q`` [rad, m] as plain floats (all NaN: none), the single-target path.
Row = tuple[float, ...]


def row_inside(
    row: Row, limits: tuple[tuple[float, ...], tuple[float, ...], tuple[bool, ...]]
) -> bool:
    """:func:`inside_limits` of one branch in plain floats (``limits`` as tuples)."""
    for value, lower, upper, revolute in zip(row, *limits):
        copy = lower + (value - lower) % (2.0 * math.pi) if revolute else value
        if not lower - LIMIT_SLACK <= copy <= upper + LIMIT_SLACK:
            return False
    return True


def first_inside(
    candidates: np.ndarray, lower: np.ndarray, upper: np.ndarray, revolute: np.ndarray
) -> int | None:
    """Index of the first of K candidate sets (K, B, nq) with a branch inside the limits.

    Else the first with a branch at all (it is reachable, only outside the limits), else None.
    """
    inside = inside_limits(candidates, lower, upper, revolute).any(axis=1)
    if inside.any():
        return int(inside.argmax())
    exists = (~np.isnan(candidates).any(axis=-1)).any(axis=1)
    return int(exists.argmax()) if exists.any() else None


def _axes(table: DHTable) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """Per joint its axis direction and a point on it (world, ``q = 0``), and ``T_world_tool``."""
    frame = np.asarray(table.T_world_base, dtype=float)
    directions, points = [], []
    for row in table.rows:
        if table.convention == "standard":
            axis_frame = frame
            frame = frame @ dh_link_transform("standard", row.a, row.alpha, row.d, row.theta)
        else:
            axis_frame = frame @ dh_link_transform("modified", row.a, row.alpha, 0.0, 0.0)
            frame = frame @ dh_link_transform("modified", row.a, row.alpha, row.d, row.theta)
        directions.append(axis_frame[:3, 2].copy())
        points.append(axis_frame[:3, 3].copy())
    return directions, points, frame @ np.asarray(table.T_last_tool, dtype=float)


def free_angle_branches(
    solve_at: Callable[[np.ndarray], np.ndarray],
    start: float,
    limits: tuple[np.ndarray, np.ndarray, np.ndarray],
    solve_one: Callable[[float], list[Row]] | None = None,
) -> tuple[np.ndarray, float, bool]:
    """The branches of a position at a stated value of the free angle that the position leaves.

    The seed's value ``start`` when a branch there is inside the limits; else the nearest it
    with a branch inside them on a 10-degree sweep refined in 1-degree steps, or on a 1-degree
    sweep when the coarse one has none (else a value with a branch at all).

    Args:
        solve_at: The branches (K, B, nq) [rad, m] at K values of the free angle [rad].
        start: The seed's value of the free angle [rad].
        limits: ``(lower, upper, revolute)`` per joint: limits [rad] or [m], and which are
            revolute (:func:`inside_limits`).
        solve_one: ``solve_at`` of the seed's value alone in plain floats (the same branches,
            faster than NumPy on one value), or None: ``solve_at``.

    Returns:
        The branches (B, nq) (NaN rows: none), the free angle's value [rad] and whether it
        was swept to (not the seed's).
    """
    if solve_one is not None:
        rows = solve_one(start)
        q = np.array(rows, dtype=float)[None]
        bounds = (tuple(limits[0].tolist()), tuple(limits[1].tolist()), tuple(limits[2].tolist()))
        if any(row_inside(row, bounds) for row in rows):
            return q[0], start, False
    else:
        q = solve_at(np.array([start]))
        if inside_limits(q, *limits).any():
            return q[0], start, False
    # 10-degree steps first; a hit is brought nearer the seed's value in 1-degree steps over the
    # 10 degrees before it (either side); no hit: every 1-degree step.
    coarse = sweep_angles(start, COARSE_STEPS)
    swept = solve_at(coarse)
    hits = inside_limits(swept, *limits).any(axis=1)
    if hits.any():
        k = int(hits.argmax())
        reach = round(abs(coarse[k] - start) / (2.0 * math.pi) * SWEEP_STEPS)
        ring = np.arange(max(reach - SWEEP_STEPS // COARSE_STEPS + 1, 1), reach)
        if ring.size:
            offsets = np.stack([ring, -ring], axis=1).reshape(-1) * (2.0 * math.pi / SWEEP_STEPS)
            fine = solve_at(start + offsets)
            near = inside_limits(fine, *limits).any(axis=1)
            if near.any():
                j = int(near.argmax())
                return fine[j], float(start + offsets[j]), True
        return swept[k], float(coarse[k]), True
    angles = sweep_angles(start)
    swept = solve_at(angles)
    found = first_inside(swept, *limits)
    if found is not None and (inside_limits(swept[found], *limits).any() or np.isnan(q).all()):
        return swept[found], float(angles[found]), True
    return q[0], start, False


def free_label(word: str, angle: float, swept: bool) -> str:
    """What a free angle [rad] was set to, for the branch labels."""
    if not swept:
        return f"{word} free: the seed's"
    value = math.degrees(math.remainder(angle, 2.0 * math.pi))
    return f"{word} free: {value:.4g} deg, the nearest the seed's with a branch inside the limits"


class ParallelAxes:
    """The closed form of an arm with every joint axis parallel (see the module).

    Attributes:
        n: The common axis direction in the world frame (the first joint's).
        signs: Per revolute joint (in order), +1 or -1: its axis along ``n`` or against it.
        offsets: DH angle offsets ``theta`` [rad] of the table (zeros for :meth:`from_axes`).
        lower, upper: Joint limits [rad] or [m] (infinite for :meth:`from_axes` without them).
        tool_on_axis: Three revolute joints and the tool point on the last one's axis: a
            position leaves that joint free.
    """

    name: ClassVar[str] = "parallel_axes"
    dof: ClassVar[int] = 4
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget, PoseTarget)
    branch_labels: tuple[str, ...] = ("elbow left", "elbow right")
    #: The candidates are the projection of a pose on what the arm reaches: the partial-pose
    #: solver measures them (a full pose on this arm goes there, see ``ClosedFormSolver``).
    projects: ClassVar[bool] = True

    def __init__(self, table: DHTable):
        directions, points, tool = _axes(table)
        kinds: list[str] = [row.joint_type for row in table.rows]
        limits = (
            np.array([row.lower for row in table.rows]),
            np.array([row.upper for row in table.rows]),
        )
        self._build(table.name, directions, points, tool, kinds, limits)
        self.offsets = tuple(row.theta for row in table.rows)

    @classmethod
    def from_axes(
        cls,
        name: str,
        directions: list[np.ndarray],
        points: list[np.ndarray],
        tool: np.ndarray,
        kinds: list[str],
        limits: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> ParallelAxes:
        """The structure of a chain given by its joint axes (world, at ``q = 0``) and tool pose.

        Args:
            name: The arm's name (for errors).
            directions: Per joint its axis direction, world, at ``q = 0``.
            points: Per joint a point on its axis [m].
            tool: ``T_world_tool`` at ``q = 0``.
            kinds: Per joint ``"revolute"`` or ``"prismatic"``.
            limits: The joints' ``(lower, upper)`` [rad] or [m], or None: none.

        Raises:
            StructureError: The axes are not all parallel, or the joint counts do not fit.
        """
        chain = cls.__new__(cls)
        chain._build(name, directions, points, tool, kinds, limits)
        chain.offsets = (0.0,) * len(kinds)
        return chain

    def _build(
        self,
        name: str,
        directions: list[np.ndarray],
        points: list[np.ndarray],
        tool: np.ndarray,
        kinds: list[str],
        limits: tuple[np.ndarray, np.ndarray] | None,
    ) -> None:
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
        if limits is None:
            limits = (np.full(self.nq, -np.inf), np.full(self.nq, np.inf))
        self.lower, self.upper = (np.asarray(v, dtype=float) for v in limits)
        self.is_revolute = np.array([kind == "revolute" for kind in kinds])
        self.tool_on_axis = len(self.links) == 3 and float(self.links[2] @ self.links[2]) < 1e-24
        # plain floats of the single-target path (:meth:`solve_angle`)
        self._basis = (tuple(self.e1.tolist()), tuple(self.e2.tolist()), tuple(self.n.tolist()))
        self._base = tuple(self.base_point.tolist())
        self._links = tuple(tuple(link.tolist()) for link in self.links)

    def _plane(self, point: np.ndarray) -> np.ndarray:
        return np.array([point @ self.e1, point @ self.e2])

    def _along(self, point: np.ndarray) -> float:
        """The point's height [m] along ``n`` from the first revolute axis's point."""
        return float((point - self.base_point) @ self.n)

    @classmethod
    def recognise(cls, table: DHTable) -> ParallelAxes:
        """This structure when every axis of the table is parallel (see the module).

        Raises:
            StructureError: An axis not parallel to the first, or a joint count it does not take.
        """
        if table.dof != cls.dof:
            raise StructureError(table.name, cls.name, f"{table.dof} joints, not {cls.dof}")
        return cls(table)

    def yaw(self, rotation: np.ndarray) -> float:
        """The angle [rad] about ``n`` of the rotation about ``n`` nearest ``R R0^T``."""
        m = rotation @ self.tool_rotation.T
        e1, e2 = self.e1, self.e2
        return math.atan2(e2 @ m @ e1 - e1 @ m @ e2, e1 @ m @ e1 + e2 @ m @ e2)

    def last_angle(self, q: np.ndarray | list[float]) -> float:
        """The last link's angle ``psi`` [rad] about ``n`` at the joint vector ``q``."""
        return float(sum(sign * q[i] for i, sign in zip(self.revolute, self.signs)))

    def solve(self, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
        """The two branches (2, dof) ``q`` [rad, m] of the target's projection (NaN: none).

        A position (``rotation`` None) on three revolute joints: :meth:`free_branches` from
        ``q = 0``.
        """
        if rotation is None and len(self.links) == 3:
            return self.free_branches(position, np.zeros(self.nq))[0]
        links = self.links
        if len(links) == 3:
            assert rotation is not None
            point = (float(position[0]), float(position[1]), float(position[2]))
            return np.array(self.solve_angle(point, self.yaw(np.asarray(rotation))))
        out = np.full((2, self.nq), np.nan)
        w = self._plane(np.asarray(position, dtype=float)) - self.origin
        l1, l2 = links[0], links[1]
        if not float(np.abs(w).max()) < 1e150:  # no arm reaches that far (and no overflow)
            return out
        a = float(l1 @ l2)
        b = float(l1[1] * l2[0] - l1[0] * l2[1])
        rho = math.hypot(a, b)
        if rho < 1e-15:
            # The tool on the last joint's axis (no second link in the plane): the position
            # fixes the first link's angle (its projection on the circle the tool goes round),
            # the yaw the last one's; one branch, of a full pose only.
            if rotation is None or not (float(l2 @ l2) < 1e-24 < float(l1 @ l1)):
                return out
            if float(w @ w) < 1e-24:  # on the first axis: the first angle is free
                return out
            phi1 = math.atan2(w[1], w[0]) - math.atan2(l1[1], l1[0])
            self._fill(out[0], [phi1, self.yaw(np.asarray(rotation, dtype=float))], position)
        else:
            cosine = (float(w @ w) - float(l1 @ l1) - float(l2 @ l2)) / (2.0 * rho)
            if abs(cosine) > 1.0 + 1e-12:
                return out
            spread = math.acos(max(-1.0, min(1.0, cosine)))
            centre = math.atan2(b, a)
            for k, beta in enumerate((centre + spread, centre - spread)):
                cb, sb = math.cos(beta), math.sin(beta)
                v = l1 + np.array([cb * l2[0] - sb * l2[1], sb * l2[0] + cb * l2[1]])
                phi1 = math.atan2(w[1], w[0]) - math.atan2(v[1], v[0])
                self._fill(out[k], [phi1, phi1 + beta], position)
        for i in self.revolute:
            out[:, i] = np.remainder(out[:, i] + math.pi, 2.0 * math.pi) - math.pi
        return out

    def solve_angle(self, position: tuple[float, float, float], psi: float) -> list[Row]:
        """:meth:`solve_angles` at one ``psi`` [rad] in plain floats: the two branches.

        Args:
            position: Tool point in the world [m].
            psi: The last link's angle about ``n`` [rad].

        Returns:
            Two rows ``q`` [rad, m] (all NaN: none), as :meth:`solve_angles` ``[0]``.
        """
        none = (math.nan,) * self.nq
        (l1x, l1y), (l2x, l2y), (l3x, l3y) = self._links
        a = l1x * l2x + l1y * l2y
        b = l1y * l2x - l1x * l2y
        rho = math.hypot(a, b)
        e1, e2, n = self._basis
        x, y, z = position
        tx = x * e1[0] + y * e1[1] + z * e1[2] - float(self.origin[0])
        ty = x * e2[0] + y * e2[1] + z * e2[2] - float(self.origin[1])
        if rho < 1e-15 or not (abs(tx) < 1e150 and abs(ty) < 1e150):
            return [none, none]
        c, s = math.cos(psi), math.sin(psi)
        wx = tx - (c * l3x - s * l3y)
        wy = ty - (s * l3x + c * l3y)
        cosine = (wx * wx + wy * wy - (l1x * l1x + l1y * l1y) - (l2x * l2x + l2y * l2y)) / (
            2.0 * rho
        )
        if abs(cosine) > 1.0 + 1e-12:
            return [none, none]
        spread = math.acos(max(-1.0, min(1.0, cosine)))
        centre = math.atan2(b, a)
        slide = None
        if self.prismatic:
            along = (x - self._base[0]) * n[0] + (y - self._base[1]) * n[1]
            slide = self.prismatic_sign * (along + (z - self._base[2]) * n[2] - self.height)
        rows = []
        for beta in (centre + spread, centre - spread):
            cb, sb = math.cos(beta), math.sin(beta)
            vx = l1x + cb * l2x - sb * l2y
            vy = l1y + sb * l2x + cb * l2y
            phi1 = math.atan2(wy, wx) - math.atan2(vy, vx)
            row = [math.nan] * self.nq
            previous = 0.0
            for phi, i, sign in zip((phi1, phi1 + beta, psi), self.revolute, self.signs):
                row[i] = (sign * (phi - previous) + math.pi) % (2.0 * math.pi) - math.pi
                previous = phi
            if slide is not None:
                row[self.prismatic[0]] = slide
            rows.append(tuple(row))
        return rows

    def solve_angles(self, position: np.ndarray, psis: np.ndarray) -> np.ndarray:
        """Both branches (K, 2, dof) ``q`` [rad, m] of a position with the last link at ``psis``.

        Three revolute joints: the wrist point ``W = P - Rot(psi) L3`` is a two-link problem per
        ``psi`` [rad] (K,); NaN where it is out of reach (or the chain has no second link).
        """
        k = len(psis)
        out = np.full((k, 2, self.nq), np.nan)
        l1, l2, l3 = self.links
        a = float(l1 @ l2)
        b = float(l1[1] * l2[0] - l1[0] * l2[1])
        rho = math.hypot(a, b)
        target = self._plane(np.asarray(position, dtype=float)) - self.origin
        if rho < 1e-15 or not float(np.abs(target).max()) < 1e150:
            return out
        c, s = np.cos(psis), np.sin(psis)
        wx = target[0] - (c * l3[0] - s * l3[1])
        wy = target[1] - (s * l3[0] + c * l3[1])
        cosine = (wx * wx + wy * wy - float(l1 @ l1) - float(l2 @ l2)) / (2.0 * rho)
        spread = np.arccos(np.clip(cosine, -1.0, 1.0))
        beta = math.atan2(b, a) + np.stack([spread, -spread], axis=1)  # (K, 2)
        cb, sb = np.cos(beta), np.sin(beta)
        vx = l1[0] + cb * l2[0] - sb * l2[1]
        vy = l1[1] + sb * l2[0] + cb * l2[1]
        phi1 = np.arctan2(wy, wx)[:, None] - np.arctan2(vy, vx)
        phis = (phi1, phi1 + beta, np.broadcast_to(psis[:, None], phi1.shape))
        previous: np.ndarray | float = 0.0
        for phi, i, sign in zip(phis, self.revolute, self.signs):
            angle = sign * (phi - previous)
            out[:, :, i] = np.remainder(angle + math.pi, 2.0 * math.pi) - math.pi
            previous = phi
        if self.prismatic:
            along = self._along(np.asarray(position, dtype=float))
            out[:, :, self.prismatic[0]] = self.prismatic_sign * (along - self.height)
        out[np.abs(cosine) > 1.0 + 1e-12] = np.nan
        return out

    def free_branches(self, position: np.ndarray, seed: np.ndarray) -> tuple[np.ndarray, str]:
        """Both branches (2, dof) of a position, the free yaw stated (see the module).

        Args:
            position: Tool point in the world [m].
            seed: The joint vector [rad, m] whose yaw (or last joint) is kept.

        Returns:
            The branches ``q`` (NaN: none) and what the free angle is (``""``: none is free).
        """
        last = self.revolute[-1]
        position = np.asarray(position, dtype=float)
        if not self.prismatic and abs(self._along(position) - self.height) > REACH_TOL:
            return np.full((2, self.nq), np.nan), ""  # off the plane the tool moves in
        if len(self.links) == 2:
            l1, l2 = self.links
            if not float(l2 @ l2) < 1e-24 < float(l1 @ l1):
                return self.solve(position, None), ""
            # The tool on the last axis: the first angle puts it on its circle, the last is free.
            q = np.full((2, self.nq), np.nan)
            w = self._plane(position) - self.origin
            if abs(math.hypot(w[0], w[1]) - math.sqrt(float(l1 @ l1))) <= REACH_TOL:
                phi1 = math.atan2(w[1], w[0]) - math.atan2(l1[1], l1[0])
                self._fill(q[0], [phi1, phi1], position)
                q[0, last] = seed[last]
                q[0, self.revolute[0]] = math.remainder(q[0, self.revolute[0]], 2.0 * math.pi)
            return q, f"joint {last + 1} free: the seed's value"
        if self.tool_on_axis:  # the last joint does not move the tool point: the seed's
            q = self.solve_angles(position, np.zeros(1))[0]
            q[:, last] = np.where(np.isnan(q[:, last]), np.nan, seed[last])
            return q, f"joint {last + 1} free: the seed's value"
        point = (float(position[0]), float(position[1]), float(position[2]))
        q, angle, swept = free_angle_branches(
            lambda psis: self.solve_angles(position, psis),
            self.last_angle(seed),
            (self.lower, self.upper, self.is_revolute),
            lambda psi: self.solve_angle(point, psi),
        )
        return q, free_label("yaw", angle, swept)

    def branches(self, target: Target, seed: list[float]) -> Branches:
        """The branches (DH angles) of a position (the yaw stated) or of a pose's projection."""
        if isinstance(target, PoseTarget):
            q = self.solve(target.position, target.rotation)
            return candidate_branches(self, q, self.offsets)
        q, free = self.free_branches(target.position, np.asarray(seed, dtype=float))
        branches = candidate_branches(self, q, self.offsets)
        if free:
            branches.thetas = [(t, f"{label}, {free}") for t, label in branches.thetas]
        return branches

    def batch_branches(self, positions: np.ndarray, rotations: np.ndarray | None) -> BatchBranches:
        """:meth:`solve_batch` (a free yaw from ``q = 0``); no elbow side (all False)."""
        q = self.solve_batch(positions, rotations)
        return BatchBranches(q, np.zeros(q.shape[:2], dtype=bool))

    def _fill(self, row: np.ndarray, phis: list[float], position: np.ndarray) -> None:
        """One branch ``q`` into ``row`` from the links' absolute angles ``phis`` [rad].

        Each joint angle is the change from the previous link's angle about ``n``, times its
        axis' sign; the slide [m] puts the tool at the position's height along ``n``.
        """
        previous = 0.0
        for j, (i, sign) in enumerate(zip(self.revolute, self.signs)):
            row[i] = sign * (phis[j] - previous)
            previous = phis[j]
        if self.prismatic:
            along = float((np.asarray(position) - self.base_point) @ self.n)
            row[self.prismatic[0]] = self.prismatic_sign * (along - self.height)

    def solve_batch(self, positions: np.ndarray, rotations: np.ndarray | None) -> np.ndarray:
        """:meth:`solve` of N targets: (N, 2, dof)."""
        return np.array(
            [
                self.solve(p, None if rotations is None else r)
                for p, r in zip(positions, rotations if rotations is not None else positions)
            ]
        )


class ParallelAxes3(ParallelAxes):
    """:class:`ParallelAxes` of three joints (planar 3R, planar 2R with a slide)."""

    dof: ClassVar[int] = 3


class ParallelAxes2(ParallelAxes):
    """:class:`ParallelAxes` of two joints (a planar 2R that the planar 2R form does not take)."""

    dof: ClassVar[int] = 2
