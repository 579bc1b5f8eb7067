"""A robot's body on the kin model's joints: every link of its URDF, its shapes and its neighbours.

A robot loaded from a URDF keeps the ``<collision>`` elements of every link of that URDF: the
chain from base to tip, and every link attached to it off the chain (a gripper's fingers, a tool
flange, a camera, ``ee_link``, a torso below the base). The joints off the chain are held at the
values :mod:`.held_joints` states, so each link rides rigidly on the chain joint nearest above it
(its *carrier*; links reached from the base without crossing a chain joint are fixed in the
world, joint 0). Each link's placement on its carrier is measured once, with the chain at q = 0
(where the URDF and the kin model agree) and the other joints at their held values. A DH table
robot has the link cylinders the URDF writer emits (per-row ``radius``).

Neighbours (MoveIt's setup assistant's adjacency): a link with shapes and the nearest link with
shapes above it in the URDF's tree.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin

from ..robot_model import RobotModel
from .held_joints import HeldJoints, held_joints
from .urdf_shapes import Shape, link_shapes

__all__ = ["ArmBody", "ArmShape", "arm_body"]


@dataclass(frozen=True, eq=False)
class ArmShape(Shape):
    """A shape on the kin model: ``placement`` is ``T_joint_shape`` of joint ``parent``."""

    parent: int = 0


@dataclass(frozen=True)
class ArmBody:
    """What a robot brings to its collision model.

    Attributes:
        shapes: Every shape of every link, on the kin model's joints.
        links: The links with shapes, by carrier joint (base to tip), then in the URDF's order.
        adjacent: Link pairs joined by a joint, links without shapes skipped; base side first.
        all_links: Every link of the URDF.
        base: The link the world frame sits on (the chain's first).
        robot_name: The URDF's ``<robot name=>``.
        held: The joints off the chain and their values.
        mounts: Every link -> ``(joint, T_joint_link)``: its carrier joint in the kin model and
            its placement on it [m] (where an attached object hangs).
    """

    shapes: tuple[ArmShape, ...]
    links: tuple[str, ...]
    adjacent: tuple[tuple[str, str], ...]
    all_links: tuple[str, ...]
    base: str
    robot_name: str
    held: HeldJoints
    mounts: Mapping[str, tuple[int, pin.SE3]]


def arm_body(
    robot: RobotModel,
    hold: Mapping[str, float] | None = None,
    srdf: str | Path | None = None,
) -> ArmBody:
    """The body of ``robot`` (the module docstring), its joints off the chain held (``hold``).

    Raises:
        CollisionModelError: A bad ``hold`` or SRDF group state (:func:`.held_joints.held_joints`).
        kin.ModelLoadError: The robot's URDF can no longer be read.
    """
    from dh2urdf.exceptions import UrdfChainError
    from dh2urdf.urdf_parse import build_pinocchio_model, parse_urdf_xml

    if robot.urdf_source is None:
        where, text, base = robot.table.path or robot.name, robot.urdf, None
    else:
        from dh2urdf.urdf_chain import urdf_text

        where, base, _ = robot.urdf_source
    try:
        if robot.urdf_source is not None:
            text = urdf_text(where)
        root, text = parse_urdf_xml(text, where)
        source = robot.model if robot.urdf_source is None else build_pinocchio_model(text, where)
    except UrdfChainError as err:
        from ..exceptions import ModelLoadError

        raise ModelLoadError(str(err)) from err
    chain_joints = set(robot.model.names[1:])
    held = held_joints(root, chain_joints, hold, srdf)
    data = source.createData()
    pin.framesForwardKinematics(source, data, _held_q(source, held))
    world = pin.SE3.Identity() if base is None else _placement(source, data, base).inverse()
    base = base or _root_link(root)
    ours = robot.model.createData()
    pin.framesForwardKinematics(robot.model, ours, np.zeros(robot.nq))
    mounts = {}
    all_links = tuple(link.get("name", "") for link in root.iter("link"))
    for link in all_links:
        joint = _carrier(source, robot.model, link)
        mounts[link] = (joint, ours.oMi[joint].inverse() * world * _placement(source, data, link))
    shapes = []
    for shape in link_shapes(root, all_links, where, strict_meshes=False):
        joint, T_joint_link = mounts[shape.owner]
        placement = T_joint_link * shape.placement
        shapes.append(
            ArmShape(shape.owner, shape.name, shape.geometry, placement, shape.kind, joint)
        )
    shaped = {s.owner for s in shapes}
    links = tuple(sorted(shaped, key=lambda link: (mounts[link][0], all_links.index(link))))
    return ArmBody(
        shapes=tuple(shapes),
        links=links,
        adjacent=_adjacent(root, links),
        all_links=all_links,
        base=base,
        robot_name=root.get("name", robot.name),
        held=held,
        mounts=mounts,
    )


def _held_q(source: pin.Model, held: HeldJoints) -> np.ndarray:
    """The source model's configuration: every joint at 0 but the held ones."""
    q = pin.neutral(source)
    for name, value in held.values.items():
        joint = source.joints[source.getJointId(name)]
        if joint.nq == 2:  # continuous: (cos, sin)
            q[joint.idx_q : joint.idx_q + 2] = (np.cos(value), np.sin(value))
        elif joint.nq == 1:
            q[joint.idx_q] = value
    return q


def _carrier(source: pin.Model, model: pin.Model, link: str) -> int:
    """The kin model's joint nearest above ``link`` in the source model (0: none, the world)."""
    joint = source.frames[source.getFrameId(link, pin.FrameType.BODY)].parentJoint
    while joint > 0:
        ours = model.getJointId(source.names[joint])
        if ours < model.njoints:
            return int(ours)
        joint = source.parents[joint]
    return 0


def _placement(model: pin.Model, data: pin.Data, link: str) -> pin.SE3:
    return data.oMf[model.getFrameId(link, pin.FrameType.BODY)]


def _parents(root: ElementTree.Element) -> dict[str, str]:
    """Child link -> parent link, of every URDF joint."""
    parents = {}
    for joint in root.iter("joint"):
        child, parent = joint.find("child"), joint.find("parent")
        if child is not None and parent is not None:
            parents[child.get("link", "")] = parent.get("link", "")
    return parents


def _root_link(root: ElementTree.Element) -> str:
    """The URDF's first link that is no joint's child."""
    children = set(_parents(root))
    return next(
        name for link in root.iter("link") if (name := link.get("name", "")) not in children
    )


def _adjacent(root: ElementTree.Element, links: tuple[str, ...]) -> tuple[tuple[str, str], ...]:
    """Each link with shapes and the nearest one with shapes above it, base side first."""
    parent = _parents(root)
    pairs = []
    for link in links:
        above = parent.get(link)
        seen = {link}
        while above is not None and above not in links and above not in seen:
            seen.add(above)
            above = parent.get(above)
        if above is not None and above in links and above != link:
            a, b = sorted((above, link), key=links.index)
            pairs.append((a, b))
    return tuple(sorted(pairs, key=lambda p: (links.index(p[0]), links.index(p[1]))))
