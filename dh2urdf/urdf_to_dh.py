"""A DH table from a URDF: the joint axes of its chain at q = 0, read as DH rows.

The rows follow from the axis lines alone (:mod:`.urdf_chain` gives them, in the base link's
frame); ``[base]`` and ``[tool]`` carry what rows cannot (where DH frame 0 sits in the base link,
where the tip link sits in the last DH frame). Each DH ``z`` axis points along its URDF joint
axis, so q keeps its sign (a URDF axis ``0 0 -1`` needs no reversed joint) and q = 0 is the URDF's
q = 0 (the ``theta`` offsets, and ``d`` offsets of prismatic joints, hold the difference).

Where DH leaves a choice free, the canonical one (both conventions):

- common normal of two skew axes: from the earlier axis to the later one (``a >= 0``);
- intersecting axes: ``x`` along ``z_prev x z_next`` (``0 < alpha < pi``), the origin at the
  intersection;
- parallel axes: the common normal through the previous origin (``d = 0`` there); coincident
  axes keep the previous ``x``;
- standard DH: frame 0 on joint 1's axis at the point nearest the base link's origin, with
  ``x_0 = x_1`` (``theta_1`` offset 0 unless the URDF's q = 0 says otherwise); the last frame on
  the last axis at the point nearest the tip's origin, ``z_n = z_{n-1}``, ``x_n = x_{n-1}``;
- modified DH (Craig): frame 0 is frame 1 at q = 0; the last frame has ``d_n = 0``.

:func:`table_from_urdf` checks its own answer: the table's DH product equals Pinocchio's FK of
the URDF's chain at random joint vectors to 1e-9 m and rad, else :class:`UrdfChainError` says so
(a bug, not the user's). The tests hold it to 1e-12 over 1000 joint vectors on every serial arm
of example-robot-data.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .dh_table import Convention, DHRow, DHTable
from .table_rows import DEFAULT_EFFORT, DEFAULT_VELOCITY
from .table_units import LIMIT_SUSPECT
from .table_values import MAX_LENGTH
from .urdf_chain import ChainJoint, UrdfChain, UrdfChainError, read_chain

__all__ = ["chain_table", "check_table", "table_from_chain", "table_from_urdf"]

#: Below this, two axes are parallel (|sin| of their angle) [1].
PARALLEL = 1e-9
#: Below this, two axes meet (distance between their lines) [m]: the intersection is then taken
#: as the midpoint of the two feet, which moves the model by at most half of it.
MEETING = 1e-13
#: Values below this are written as 0 (round-off of the construction) [m, rad].
ROUND_OFF = 1e-14


def table_from_urdf(
    path: str | Path,
    base: str | None = None,
    tip: str | None = None,
    convention: Convention = "standard",
) -> DHTable:
    """The DH table of the chain from ``base`` to ``tip`` of a URDF (SI units).

    Args:
        path: A ``.urdf`` (or ``.xacro``) file.
        base: Base link (default: the URDF's root link).
        tip: Tip link (default: the single leaf below the last moving joint).
        convention: ``"standard"`` or ``"modified"`` DH.

    Raises:
        UrdfChainError: The URDF cannot give a serial chain (see :func:`read_chain`), or a
            mimic joint on it follows another (a table's rows move independently).
    """
    return chain_table(path, base, tip, convention)[1]


def chain_table(
    path: str | Path,
    base: str | None = None,
    tip: str | None = None,
    convention: Convention = "standard",
) -> tuple[UrdfChain, DHTable]:
    """The chain of a URDF and its DH table, checked (:func:`table_from_urdf`)."""
    chain = read_chain(path, base, tip)
    for joint in chain.joints:
        if joint.mimic is not None:
            raise UrdfChainError(
                chain.path,
                f"joint {joint.name!r} follows {joint.mimic.leader!r} (mimic): a DH table has "
                "one independent joint per row; choose a --tip before it "
                "(kin.mimic.arm reads the coupled chain)",
            )
    table = table_from_chain(chain, convention)
    check_table(chain, table)
    return chain, table


def table_from_chain(chain: UrdfChain, convention: Convention = "standard") -> DHTable:
    """The DH table of a :class:`UrdfChain` (no check; see :func:`table_from_urdf`)."""
    if convention not in ("standard", "modified"):
        raise UrdfChainError(
            chain.path, f"unknown DH convention {convention!r}: standard or modified"
        )
    lines = [(joint.origin, joint.axis) for joint in chain.joints]
    tip_point = chain.tip_frame[:3, 3]
    if convention == "standard":
        frames = _standard_frames(lines, tip_point)
        rows_of = _standard_row
    else:
        frames = _modified_frames(lines)
        rows_of = _modified_row
    rows = []
    for i, joint in enumerate(chain.joints, start=1):
        a, alpha, d, theta = rows_of(frames, i)
        lower, upper, continuous = _limits(chain.path, joint)
        rows.append(
            DHRow(
                index=i,
                name=joint.name,
                joint_type=joint.joint_type,  # type: ignore[arg-type]
                a=_clean(a),
                alpha=_clean(alpha),
                d=_clean(d),
                theta=_clean(theta),
                lower=lower,
                upper=upper,
                velocity=joint.velocity or DEFAULT_VELOCITY[joint.joint_type],
                effort=joint.effort or DEFAULT_EFFORT[joint.joint_type],
                continuous=continuous,
            )
        )
    base_frame = frames[0]
    tool = np.linalg.inv(frames[-1]) @ chain.tip_frame
    return DHTable(
        name=_name(chain),
        description=f"{chain.name}: {chain.base} to {chain.tip}, read from {Path(chain.path).name}",
        source=f"{Path(chain.path).name} (URDF), chain {chain.base} -> {chain.tip}",
        convention=convention,
        rows=tuple(rows),
        T_world_base=_clean_matrix(base_frame),
        T_last_tool=_clean_matrix(tool),
        path=chain.path,
    )


def _limits(path: str, joint: ChainJoint) -> tuple[float, float, bool]:
    """``(lower, upper, continuous)`` of a chain joint as a table row carries them.

    A revolute joint whose limits reach beyond :data:`~dh2urdf.table_units.LIMIT_SUSPECT` (four
    turns; URDFs write 1e16 or 1e308 for "no limits") is read as continuous: limits [-pi, pi],
    every angle having a copy there.

    Raises:
        UrdfChainError: Lower above upper, or a prismatic limit beyond ``MAX_LENGTH`` (1e6 m).
    """
    lower, upper = joint.lower, joint.upper
    if not lower <= upper:
        raise UrdfChainError(
            path, f"joint {joint.name!r}: limit lower {lower:g} is above upper {upper:g}; swap them"
        )
    largest = max(abs(lower), abs(upper))
    if joint.joint_type == "revolute" and largest > LIMIT_SUSPECT:
        return -math.pi, math.pi, True
    if joint.joint_type == "prismatic" and largest > MAX_LENGTH:
        raise UrdfChainError(
            path,
            f"joint {joint.name!r}: limit {largest:g} m is beyond {MAX_LENGTH:g} m, the longest "
            "travel a table may give; write the joint's real travel",
        )
    return lower, upper, joint.continuous


def _name(chain: UrdfChain) -> str:
    name = "".join(c if c.isalnum() or c in "_-" else "_" for c in chain.name)
    return name or Path(chain.path).stem


def _clean(value: float) -> float:
    return 0.0 if abs(value) < ROUND_OFF else float(value)


def _clean_matrix(matrix: np.ndarray) -> np.ndarray:
    out = np.array(matrix, dtype=float)
    out[np.abs(out) < ROUND_OFF] = 0.0
    out[3] = (0.0, 0.0, 0.0, 1.0)
    return out


def _frame(origin: np.ndarray, x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The 4x4 frame with origin ``origin`` and axes ``x``, ``z x x``, ``z``."""
    z = z / np.linalg.norm(z)
    x = x - (x @ z) * z
    x = x / np.linalg.norm(x)
    out = np.eye(4)
    out[:3, 0] = x
    out[:3, 1] = np.cross(z, x)
    out[:3, 2] = z
    out[:3, 3] = origin
    return out


def _foot(point: np.ndarray, line: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """The point of ``line`` (origin, unit direction) nearest ``point``."""
    origin, direction = line
    return origin + ((point - origin) @ direction) * direction


def _any_normal(z: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to ``z`` (the world axis least aligned with it)."""
    axis = np.eye(3)[int(np.argmin(np.abs(z)))]
    x = axis - (axis @ z) * z
    return x / np.linalg.norm(x)


def _normal(
    first: tuple[np.ndarray, np.ndarray],
    second: tuple[np.ndarray, np.ndarray],
    origin: np.ndarray,
    x_previous: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The common normal of two axis lines: ``(foot on first, foot on second, unit x)``.

    Skew: the shortest segment, ``x`` from the first to the second. Meeting: the intersection,
    ``x = z1 x z2``. Parallel: the normal through ``origin`` (a point of ``first``); coincident
    lines keep ``x_previous``.
    """
    p1, z1 = first
    p2, z2 = second
    cross = np.cross(z1, z2)
    sine = float(np.linalg.norm(cross))
    if sine > PARALLEL:
        # Closest points of the two lines: p1 + s z1 and p2 + t z2.
        w = p1 - p2
        b = float(z1 @ z2)
        d, e = float(z1 @ w), float(z2 @ w)
        denominator = sine * sine  # = 1 - b^2, without its cancellation for near-parallel axes
        s = (b * e - d) / denominator
        t = (e - b * d) / denominator
        f1, f2 = p1 + s * z1, p2 + t * z2
        # The normal's direction is that of z1 x z2 (well conditioned however short the gap);
        # the gap gives its sign and length only.
        x = cross / sine
        distance = float((f2 - f1) @ x)
        if abs(distance) > MEETING:
            if distance < 0.0:
                x, distance = -x, -distance
            return f1, f1 + distance * x, x
        middle = 0.5 * (f1 + f2)
        return middle, middle, x
    foot = _foot(origin, second)
    gap = foot - origin
    # Perpendicular to both directions (they differ by less than PARALLEL): the mean one.
    mean = z1 + z2 if float(z1 @ z2) > 0.0 else z1 - z2
    mean = mean / np.linalg.norm(mean)
    gap = gap - (gap @ mean) * mean
    distance = float(np.linalg.norm(gap))
    if distance > MEETING:
        return origin, origin + gap, gap / distance
    x = x_previous - (x_previous @ z1) * z1
    if np.linalg.norm(x) < 1e-6:
        x = _any_normal(z1)
    return origin, foot, x / np.linalg.norm(x)


def _standard_frames(
    lines: list[tuple[np.ndarray, np.ndarray]], tip: np.ndarray
) -> list[np.ndarray]:
    """Standard DH frames 0..n at q = 0: frame ``i`` has ``z`` along axis ``i + 1``."""
    n = len(lines)
    origin0 = _foot(np.zeros(3), lines[0])
    z0 = lines[0][1]
    frames: list[np.ndarray] = []
    origins, xs, zs = [origin0], [_any_normal(z0)], [z0]
    for i in range(1, n):
        _, foot, x = _normal(lines[i - 1], lines[i], origins[-1], xs[-1])
        origins.append(foot)
        xs.append(x)
        zs.append(lines[i][1])
    # The last frame: on the last axis nearest the tip, z and x as the previous frame's.
    origins.append(_foot(tip, lines[-1]))
    xs.append(xs[-1])
    zs.append(zs[-1])
    xs[0] = xs[1]  # x_0 = x_1 (perpendicular to z_0 in every case): no theta_1 offset of ours
    for origin, x, z in zip(origins, xs, zs, strict=True):
        frames.append(_frame(origin, x, z))
    return frames


def _modified_frames(lines: list[tuple[np.ndarray, np.ndarray]]) -> list[np.ndarray]:
    """Modified DH frames 0..n at q = 0: frame ``i`` has ``z`` along axis ``i``; frame 0 = 1."""
    n = len(lines)
    origins: list[np.ndarray] = []
    xs: list[np.ndarray] = []
    # Where x_{i-1} meets axis i: frame i's d measures from there (d = 0 when free).
    meet = _foot(np.zeros(3), lines[0])
    x_previous = _any_normal(lines[0][1])
    for i in range(n):
        if i + 1 < n:
            foot, next_meet, x = _normal(lines[i], lines[i + 1], meet, x_previous)
        else:
            foot, next_meet, x = meet, meet, x_previous
        origins.append(foot)
        xs.append(x)
        meet, x_previous = next_meet, x
    frames = [_frame(o, x, line[1]) for o, x, line in zip(origins, xs, lines, strict=True)]
    return [frames[0], *frames]


def _angle(u: np.ndarray, v: np.ndarray, axis: np.ndarray) -> float:
    """The angle from ``u`` to ``v`` about ``axis`` [rad]."""
    return math.atan2(float(np.cross(u, v) @ axis), float(u @ v))


def _standard_row(frames: list[np.ndarray], i: int) -> tuple[float, float, float, float]:
    """``(a, alpha, d, theta)`` of standard row ``i`` (frames ``i - 1`` and ``i``)."""
    before, after = frames[i - 1], frames[i]
    x0, z0, o0 = before[:3, 0], before[:3, 2], before[:3, 3]
    x1, z1, o1 = after[:3, 0], after[:3, 2], after[:3, 3]
    step = o1 - o0
    return float(step @ x1), _angle(z0, z1, x1), float(step @ z0), _angle(x0, x1, z0)


def _modified_row(frames: list[np.ndarray], i: int) -> tuple[float, float, float, float]:
    """``(a_{i-1}, alpha_{i-1}, d_i, theta_i)`` of modified row ``i`` (frames ``i - 1``, ``i``)."""
    before, after = frames[i - 1], frames[i]
    x0, z0, o0 = before[:3, 0], before[:3, 2], before[:3, 3]
    x1, z1, o1 = after[:3, 0], after[:3, 2], after[:3, 3]
    step = o1 - o0
    return float(step @ x0), _angle(z0, z1, x0), float(step @ z1), _angle(x0, x1, z1)


def check_table(
    chain: UrdfChain, table: DHTable, samples: int = 20, tolerance: float = 1e-9
) -> None:
    """The table's DH product equals Pinocchio's FK of the URDF chain, else an error.

    The table has a row per joint of the chain, mimic ones included: the joint vectors sampled
    are the independent joints' (within their limits), expanded by :meth:`UrdfChain.expand`.
    """
    import pinocchio as pin

    from .dh_table import dh_link_transform

    model = pin.buildModelFromXML(chain.text)
    data = model.createData()
    tip = model.getFrameId(chain.tip, pin.FrameType.BODY)
    base = model.getFrameId(chain.base, pin.FrameType.BODY)
    ids = [model.getJointId(joint.name) for joint in chain.joints]
    rng = np.random.default_rng(7)
    lower = np.array([joint.lower for joint in chain.independent])
    upper = np.array([joint.upper for joint in chain.independent])
    # Within the limits and [-pi, pi]; anywhere in [-pi, pi] where they do not meet (the DH
    # product equals FK at every q: the limits only keep the samples where the arm goes).
    low, high = np.maximum(lower, -math.pi), np.minimum(upper, math.pi)
    low, high = np.where(low <= high, low, -math.pi), np.where(low <= high, high, math.pi)
    for _ in range(samples):
        q = chain.expand(rng.uniform(low, high))
        full = pin.neutral(model)
        for value, joint_id in zip(q, ids, strict=True):
            joint = model.joints[joint_id]
            if joint.nq == 2:
                full[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
            else:
                full[joint.idx_q] = value
        pin.forwardKinematics(model, data, full)
        pin.updateFramePlacements(model, data)
        expected = (data.oMf[base].inverse() * data.oMf[tip]).homogeneous
        product = np.array(table.T_world_base)
        for row, value in zip(table.rows, q, strict=True):
            theta, d = row.dh_values(float(value))
            product = product @ dh_link_transform(table.convention, row.a, row.alpha, d, theta)
        product = product @ table.T_last_tool
        error = float(np.abs(product - expected).max())
        if not error < tolerance:
            raise UrdfChainError(
                chain.path,
                f"the DH table read from the chain misses the URDF's FK by {error:.3g} at "
                f"q = {np.round(q, 4).tolist()}: please report this URDF",
            )
