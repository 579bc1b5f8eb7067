"""The serial chain of a URDF between a base link and a tip link, at q = 0, in the base frame.

Pinocchio parses the URDF (fixed joints merged into their parents' frames, side branches kept
as other subtrees); this module keeps the moving joints on the path from ``base`` to ``tip`` and
gives, for each, its frame at q = 0, its axis and its limits. A light read of the XML
(:mod:`xml.etree`) checks what Pinocchio does not say: zero axes on the chain, and reads mimic
joints: a joint ``<mimic joint="L" multiplier="m" offset="c"/>`` on the chain follows its leader
``L`` (``q = m q_L + c``), which must be on the chain too; :meth:`UrdfChain.expand` gives every
joint's value from the independent ones.

Defaults: ``base`` is the URDF's root link; ``tip`` is the end of the chain when exactly one leaf
link lies below the last moving joint of the tree (cameras or grippers hanging elsewhere make
several candidates: then the error names them). A ``.xacro`` file is expanded with the optional
``xacrodoc`` package (``pip install "dh-kinematics[xacro]"``).

Errors are :class:`UrdfChainError` (a :class:`~dh2urdf.Dh2UrdfError`): one line that names the
file, the link or joint, and the fix.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .exceptions import UrdfChainError
from .input_file import read_input
from .joint_cap import urdf_joint_count_problem
from .urdf_parse import build_pinocchio_model, parse_urdf_xml

__all__ = ["ChainJoint", "MimicJoint", "UrdfChain", "UrdfChainError", "read_chain", "urdf_text"]


@dataclass(frozen=True)
class MimicJoint:
    """The coupling of a URDF mimic joint: ``q = multiplier * q_leader + offset``.

    Attributes:
        leader: Name of the joint it follows (on the same chain).
        multiplier: Factor on the leader's value [1] (URDF default 1).
        offset: Added value [rad] or [m] (URDF default 0).
    """

    leader: str
    multiplier: float = 1.0
    offset: float = 0.0


@dataclass(frozen=True)
class ChainJoint:
    """One moving joint of the chain, at q = 0.

    Attributes:
        name: Joint name in the URDF.
        joint_type: ``"revolute"`` or ``"prismatic"`` (a URDF ``continuous`` joint is revolute
            with ``continuous`` True).
        continuous: Whether the URDF joint is ``continuous`` (no limits).
        origin: Point of the joint axis at q = 0, in the base link's frame [m], shape (3,).
        axis: Unit direction of the axis at q = 0, in the base link's frame, shape (3,).
        frame: ``T_base_joint`` at q = 0 (4x4, [m]): the joint's own frame.
        lower: Lower limit [rad] or [m] (``-pi`` for a continuous joint).
        upper: Upper limit [rad] or [m] (``pi`` for a continuous joint).
        velocity: Velocity limit [rad/s] or [m/s] (0 when the URDF gives none).
        effort: Effort limit [N m] or [N] (0 when the URDF gives none).
        mimic: The coupling of a mimic joint (its value follows its leader), else None.
    """

    name: str
    joint_type: str
    continuous: bool
    origin: np.ndarray
    axis: np.ndarray
    frame: np.ndarray
    lower: float
    upper: float
    velocity: float
    effort: float
    mimic: MimicJoint | None = None


@dataclass(frozen=True, eq=False)
class UrdfChain:
    """The chain from ``base`` to ``tip``.

    Attributes:
        path: The URDF file.
        name: The URDF's robot name.
        base: Base link name.
        tip: Tip link name.
        joints: The moving joints, base to tip.
        tip_frame: ``T_base_tip`` at q = 0 (4x4, [m]).
        text: The URDF text (xacro expanded).
    """

    path: str
    name: str
    base: str
    tip: str
    joints: tuple[ChainJoint, ...]
    tip_frame: np.ndarray
    text: str

    @property
    def independent(self) -> tuple[ChainJoint, ...]:
        """The joints the user moves: every joint of the chain but the mimic ones."""
        return tuple(joint for joint in self.joints if joint.mimic is None)

    def expand(self, q: np.ndarray) -> np.ndarray:
        """Every joint's value, base to tip, from the independent joints' values ``q``.

        Args:
            q: Values of :attr:`independent` [rad] or [m], shape (..., n).

        Returns:
            Values of :attr:`joints`, shape (..., len(joints)): a mimic joint's is
            ``multiplier * q_leader + offset``.
        """
        q = np.asarray(q, dtype=float)
        index = {joint.name: i for i, joint in enumerate(self.independent)}
        columns = []
        for joint in self.joints:
            if joint.mimic is None:
                columns.append(q[..., index[joint.name]])
            else:
                leader = q[..., index[joint.mimic.leader]]
                columns.append(joint.mimic.multiplier * leader + joint.mimic.offset)
        return np.stack(columns, axis=-1)


def urdf_text(path: str | Path) -> str:
    """The URDF text of ``path``; a ``.xacro`` file expanded with ``xacrodoc`` when installed.

    Raises:
        UrdfChainError: The file cannot be read, or is a xacro file without ``xacrodoc``.
    """
    path = Path(path)
    if path.suffix == ".xacro" or path.name.endswith(".urdf.xacro"):
        try:
            from xacrodoc import XacroDoc  # type: ignore[import-not-found]
        except ImportError:
            raise UrdfChainError(
                str(path),
                'a .xacro file needs the optional xacrodoc package: pip install "dh-kinematics'
                '[xacro]" (or expand it first: xacro FILE > robot.urdf)',
            ) from None
        try:
            read_input(path)  # a regular file of bounded size, as any other input
        except OSError as err:
            raise UrdfChainError(str(path), f"cannot read the file ({err.strerror})") from err
        try:
            return str(XacroDoc.from_file(str(path)).to_urdf_string())
        except Exception as err:  # noqa: BLE001 - any xacro failure is the file's
            raise UrdfChainError(str(path), f"xacro expansion failed: {_one_line(err)}") from err
    try:
        raw = read_input(path)
    except OSError as err:
        raise UrdfChainError(str(path), f"cannot read the file ({err.strerror})") from err
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as err:
        raise UrdfChainError(
            str(path), f"not UTF-8 text (byte {err.start}): save it as UTF-8"
        ) from None


def _one_line(err: BaseException) -> str:
    return " ".join(str(err).split())[:300]


def read_chain(path: str | Path, base: str | None = None, tip: str | None = None) -> UrdfChain:
    """The moving joints from ``base`` to ``tip`` of the URDF ``path``.

    Args:
        path: A ``.urdf`` (or ``.xacro``) file.
        base: Base link (default: the root link).
        tip: Tip link (default: the single leaf below the last moving joint).

    Raises:
        UrdfChainError: Not XML, not a URDF, unknown base or tip (the message lists the links),
            no path from base to tip, a floating or planar joint or a zero axis on the chain, a
            mimic joint whose leader is not on the chain (or is itself a mimic joint), no moving
            joint between base and tip.
    """
    import pinocchio as pin

    where = str(path)
    text = urdf_text(path)
    root, text = parse_urdf_xml(text, where)
    if (too_many := urdf_joint_count_problem(root, base, tip)) is not None:
        raise UrdfChainError(where, too_many)  # before Pinocchio: its Data grows as joints^3
    xml_joints = {joint.get("name", ""): joint for joint in root.iter("joint")}
    links = [link.get("name", "") for link in root.iter("link")]
    if not links:
        raise UrdfChainError(where, "not a URDF: no <link>")
    model = build_pinocchio_model(text, where)
    parent_links = {element.get("link") for element in root.iter("parent")}
    child_links = {element.get("link") for element in root.iter("child")}
    roots = [link for link in links if link not in child_links]
    base = base if base is not None else (roots[0] if roots else links[0])
    for role, link in (("base", base), ("tip", tip)):
        if link is not None and link not in links:
            raise UrdfChainError(
                where, f"no link {link!r} for the {role}; links: {', '.join(links)}"
            )
    if tip is None:
        leaves = [link for link in links if link not in parent_links and link != base]
        tip = _default_tip(where, model, leaves, base)
    base_id = model.getFrameId(base, pin.FrameType.BODY)
    tip_id = model.getFrameId(tip, pin.FrameType.BODY)
    base_joint = model.frames[base_id].parentJoint
    tip_joint = model.frames[tip_id].parentJoint
    path_joints = list(model.supports[tip_joint])
    if base_joint not in path_joints:
        raise UrdfChainError(
            where,
            f"no path from the base {base!r} down to the tip {tip!r}: the tip is not below the "
            "base (give --base an ancestor of --tip)",
        )
    chain_ids = path_joints[path_joints.index(base_joint) + 1 :]
    if not chain_ids:
        raise UrdfChainError(where, f"no moving joint between {base!r} and {tip!r}")
    q0 = pin.neutral(model)
    data = model.createData()
    pin.forwardKinematics(model, data, q0)
    pin.updateFramePlacements(model, data)
    pin.computeJointJacobians(model, data, q0)
    base_world = data.oMf[base_id].inverse()
    joints = tuple(
        _chain_joint(where, model, data, base_world, joint_id, xml_joints) for joint_id in chain_ids
    )
    _check_mimics(where, joints)
    return UrdfChain(
        path=where,
        name=root.get("name", Path(where).stem),
        base=base,
        tip=tip,
        joints=joints,
        tip_frame=np.array((base_world * data.oMf[tip_id]).homogeneous),
        text=text,
    )


def _default_tip(where: str, model: Any, leaves: list[str], base: str) -> str:
    """The single leaf link below the deepest moving joint(s), else an error naming the leaves."""
    import pinocchio as pin

    frames = {f.name: f for f in model.frames if f.type == pin.FrameType.BODY}
    depth = {
        name: len(model.supports[frames[name].parentJoint]) for name in leaves if name in frames
    }
    deepest = max(depth.values(), default=0)
    candidates = sorted(name for name, value in depth.items() if value == deepest)
    if len(candidates) == 1:
        return candidates[0]
    if not candidates:
        raise UrdfChainError(where, f"no link below {base!r} could be the tip; give --tip LINK")
    raise UrdfChainError(
        where,
        f"several links could be the tip: {', '.join(candidates)}; choose one with --tip LINK",
    )


def _chain_joint(
    where: str,
    model: object,
    data: object,
    base_world: object,
    joint_id: int,
    xml_joints: dict[str, ElementTree.Element],
) -> ChainJoint:
    """The :class:`ChainJoint` of Pinocchio joint ``joint_id`` (checked against the XML)."""
    import pinocchio as pin

    name = model.names[joint_id]  # type: ignore[attr-defined]
    joint = model.joints[joint_id]  # type: ignore[attr-defined]
    element = xml_joints.get(name)
    kind = element.get("type", "") if element is not None else ""
    mimic = _mimic(where, name, element)
    if kind in ("floating", "planar") or joint.nv != 1:
        raise UrdfChainError(
            where,
            f"joint {name!r} on the chain is {kind or joint.shortname()}: only revolute, "
            "continuous and prismatic joints make a DH chain",
        )
    if element is not None and (axis_element := element.find("axis")) is not None:
        text = axis_element.get("xyz", "1 0 0")
        try:
            values = [float(v) for v in text.split()]
        except ValueError:
            values = []
        if len(values) != 3 or not all(map(math.isfinite, values)) or not any(values):
            raise UrdfChainError(where, f"joint {name!r}: axis xyz {text!r} is no direction")
    frame = np.array((base_world * data.oMi[joint_id]).homogeneous)  # type: ignore[attr-defined, operator]
    # The joint's column of its Jacobian in its own frame: (linear, angular) of a unit motion.
    # (6, nv), which eigenpy hands back as (6,) when nv = 1: reshape.
    jacobian = np.reshape(
        pin.getJointJacobian(model, data, joint_id, pin.ReferenceFrame.LOCAL), (6, -1)
    )
    column = jacobian[:, joint.idx_v]
    linear, angular = column[:3], column[3:]
    prismatic = not np.linalg.norm(angular) > 0.5
    local_axis = linear if prismatic else angular
    axis = frame[:3, :3] @ (local_axis / np.linalg.norm(local_axis))
    continuous = joint.nq == 2  # Pinocchio's unbounded revolute joint: (cos, sin)
    if continuous:
        lower, upper = -math.pi, math.pi
    else:
        lower = float(model.lowerPositionLimit[joint.idx_q])  # type: ignore[attr-defined]
        upper = float(model.upperPositionLimit[joint.idx_q])  # type: ignore[attr-defined]
    velocity = float(model.velocityLimit[joint.idx_v])  # type: ignore[attr-defined]
    effort = float(model.effortLimit[joint.idx_v])  # type: ignore[attr-defined]
    return ChainJoint(
        name=name,
        joint_type="prismatic" if prismatic else "revolute",
        continuous=continuous,
        origin=frame[:3, 3].copy(),
        axis=axis,
        frame=frame,
        lower=lower,
        upper=upper,
        velocity=velocity if math.isfinite(velocity) and velocity > 0 else 0.0,
        effort=effort if math.isfinite(effort) and effort > 0 else 0.0,
        mimic=mimic,
    )


def _mimic(where: str, name: str, element: ElementTree.Element | None) -> MimicJoint | None:
    """The ``<mimic>`` of joint ``name``, its numbers checked, else None."""
    mimic = element.find("mimic") if element is not None else None
    if mimic is None:
        return None
    values = []
    for field, default in (("multiplier", 1.0), ("offset", 0.0)):
        text = mimic.get(field)
        try:
            value = default if text is None else float(text)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            raise UrdfChainError(where, f"joint {name!r}: mimic {field} {text!r} is no number")
        values.append(value)
    return MimicJoint(mimic.get("joint", ""), values[0], values[1])


def _check_mimics(where: str, joints: tuple[ChainJoint, ...]) -> None:
    """Every mimic joint of the chain follows a joint of the chain that is no mimic itself."""
    by_name = {joint.name: joint for joint in joints}
    for joint in joints:
        if joint.mimic is None:
            continue
        leader = by_name.get(joint.mimic.leader)
        if leader is None:
            raise UrdfChainError(
                where,
                f"joint {joint.name!r} on the chain mimics {joint.mimic.leader!r}, which is not "
                "on the chain: choose a --tip before it, or a --base above its leader",
            )
        if leader.mimic is not None:
            raise UrdfChainError(
                where,
                f"joint {joint.name!r} mimics {leader.name!r}, itself a mimic joint: make it "
                f"mimic {leader.mimic.leader!r}",
            )
        if leader.joint_type != joint.joint_type:
            raise UrdfChainError(
                where,
                f"joint {joint.name!r} ({joint.joint_type}) mimics {leader.name!r} "
                f"({leader.joint_type}): a mimic joint follows a joint of its own type",
            )
