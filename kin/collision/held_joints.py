"""The joints off a robot's chain and the values they are held at in its collision model.

A robot loaded from a URDF has a collision model of every link of the URDF (:mod:`.arm_shapes`):
the chain from base to tip moves with ``q``; a joint off that chain (a gripper's finger, a head's
pan, a torso's lift) does not: it is held at one value [rad, or m when prismatic], so the links
beyond it ride rigidly on the chain joint that carries them. Each joint's value, first found of:

1. ``hold`` (the commands' ``--hold NAME=VALUE``), which must lie within the joint's limits;
2. an SRDF's ``<group_state>`` that sets the joint: the state named :data:`PREFERRED_STATE` when
   it does, else the first such state in the file;
3. 0, moved into the joint's limits (to the nearer limit when 0 lies outside them).

A mimic joint (``<mimic joint= multiplier= offset=>``) follows its leader, ``multiplier * leader
+ offset``, and is not held itself. :attr:`HeldJoints.note` says every value and where it came
from, in one line.
"""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

from dh2urdf.quoted_input import quoted

from ..exceptions import CollisionModelError

__all__ = ["PREFERRED_STATE", "HeldJoint", "HeldJoints", "held_joints"]

#: The SRDF group state taken first when several set a held joint.
PREFERRED_STATE = "ready"

#: URDF joint types that can be held at a value.
_MOVABLE = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class HeldJoint:
    """One joint off the chain and its held value.

    Attributes:
        name: The URDF joint.
        value: Its value [rad, or m when prismatic].
        prismatic: Whether the value is a length.
        source: Where the value came from: ``"hold"``, ``"SRDF group_state 'NAME'"``, ``"zero"``,
            ``"zero moved into the limits"`` or ``"mimics LEADER"``.
    """

    name: str
    value: float
    prismatic: bool
    source: str

    def __str__(self) -> str:
        unit = "m" if self.prismatic else "rad"
        return f"{self.name} = {self.value:g} {unit} ({self.source})"


@dataclass(frozen=True)
class HeldJoints:
    """The values of every movable joint off the chain, in the URDF's order.

    Attributes:
        joints: One per joint off the chain (mimic joints included).
    """

    joints: tuple[HeldJoint, ...] = ()

    @property
    def values(self) -> dict[str, float]:
        """Joint name -> held value [rad or m]."""
        return {joint.name: joint.value for joint in self.joints}

    @property
    def note(self) -> str:
        """One line: every held joint, its value and its source ("" when there is none).

        As ``panda_finger_joint1 = 0.04 m (hold), panda_finger_joint2 = 0.04 m (mimics
        panda_finger_joint1)``.
        """
        if not self.joints:
            return ""
        return ", ".join(str(joint) for joint in self.joints)


@dataclass(frozen=True)
class _UrdfJoint:
    name: str
    kind: str
    lower: float
    upper: float
    leader: str | None
    multiplier: float
    offset: float


def held_joints(
    root: ElementTree.Element,
    chain: Collection[str],
    hold: Mapping[str, float] | None = None,
    srdf: str | Path | None = None,
) -> HeldJoints:
    """The held value of every movable joint of the URDF ``root`` not in ``chain``.

    Args:
        root: The URDF's ``<robot>`` element.
        chain: The joints that move with ``q`` (the kin model's).
        hold: Joint name -> value [rad, or m when prismatic], within the joint's limits.
        srdf: A MoveIt SRDF whose ``<group_state>`` values come before the zero default.

    Raises:
        CollisionModelError: ``hold`` names a joint that is not a movable joint off the chain (a
            chain joint, a fixed or mimic joint, an unknown name), or a value that is not a
            finite number within the joint's limits; the SRDF cannot be read.
    """
    joints = {j.name: j for j in _urdf_joints(root) if j.name not in chain}
    hold = dict(hold or {})
    _check_hold(hold, joints, chain)
    states = _group_states(srdf) if srdf is not None and joints else []
    held: dict[str, HeldJoint] = {}
    for joint in joints.values():
        if joint.leader is not None and joint.leader in joints:
            continue  # follows its leader, below
        held[joint.name] = _value(joint, hold, states)
    for joint in joints.values():
        if joint.name not in held:
            assert joint.leader is not None
            leader = held.get(joint.leader) or _value(joints[joint.leader], hold, states)
            value = joint.multiplier * leader.value + joint.offset
            held[joint.name] = HeldJoint(
                joint.name, value, joint.kind == "prismatic", f"mimics {joint.leader}"
            )
    return HeldJoints(tuple(held[name] for name in joints))


def _value(joint: _UrdfJoint, hold: dict[str, float], states: list[tuple[str, dict]]) -> HeldJoint:
    prismatic = joint.kind == "prismatic"
    if joint.name in hold:
        return HeldJoint(joint.name, hold[joint.name], prismatic, "hold")
    named = [(name, values) for name, values in states if joint.name in values]
    named.sort(key=lambda item: item[0] != PREFERRED_STATE)  # stable: else the file's first
    if named:
        state, values = named[0]
        return HeldJoint(joint.name, values[joint.name], prismatic, f"SRDF group_state {state!r}")
    value = min(max(0.0, joint.lower), joint.upper)
    return HeldJoint(
        joint.name, value, prismatic, "zero" if value == 0.0 else "zero moved into the limits"
    )


def _check_hold(hold: dict[str, float], joints: dict[str, _UrdfJoint], chain: Collection[str]):
    free = [j.name for j in joints.values() if j.leader is None or j.leader not in joints]
    choices = ", ".join(free) or "none: the robot has no movable joint off its chain"
    for name, value in hold.items():
        field = f"hold {quoted(name)}"
        if name in chain:
            raise CollisionModelError(
                "", f"{field}: a joint of the chain moves with q; hold one off it: {choices}"
            )
        joint = joints.get(name)
        if joint is None:
            raise CollisionModelError(
                "", f"{field}: no movable joint off the chain has that name; choose: {choices}"
            )
        if name not in free:
            raise CollisionModelError(
                "", f"{field}: a mimic joint, it follows {joint.leader}: hold {joint.leader}"
            )
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise CollisionModelError("", f"{field}: {quoted(value)} is not a number")
        if not joint.lower <= float(value) <= joint.upper:  # NaN fails too
            unit = "m" if joint.kind == "prismatic" else "rad"
            raise CollisionModelError(
                "",
                f"{field}: {value!r} {unit} is outside the joint's limits "
                f"[{joint.lower:g}, {joint.upper:g}] {unit}",
            )
        hold[name] = float(value)


def _urdf_joints(root: ElementTree.Element) -> list[_UrdfJoint]:
    """The URDF's movable joints (limits of a continuous joint: +-inf)."""
    joints = []
    for element in root.iter("joint"):
        kind = element.get("type", "")
        if kind not in _MOVABLE:
            continue
        limit = element.find("limit")
        lower, upper = -math.inf, math.inf
        if kind != "continuous" and limit is not None:
            lower = _attribute(limit, "lower", 0.0)
            upper = _attribute(limit, "upper", 0.0)
        mimic = element.find("mimic")
        joints.append(
            _UrdfJoint(
                element.get("name", ""),
                kind,
                lower,
                upper,
                None if mimic is None else mimic.get("joint"),
                1.0 if mimic is None else _attribute(mimic, "multiplier", 1.0),
                0.0 if mimic is None else _attribute(mimic, "offset", 0.0),
            )
        )
    return joints


def _attribute(element: ElementTree.Element, name: str, default: float) -> float:
    """A number attribute (the default when absent or not a finite number, as urdfdom reads)."""
    try:
        value = float(element.get(name, default))
    except ValueError:
        return default
    return value if math.isfinite(value) else default


def _group_states(srdf: str | Path) -> list[tuple[str, dict[str, float]]]:
    """An SRDF's group states: ``(name, {joint: value})`` in the file's order."""
    from .srdf import srdf_root

    where = str(srdf)
    states = []
    for index, state in enumerate(srdf_root(where).iter("group_state")):
        values: dict[str, float] = {}
        for joint in state.iter("joint"):
            text = joint.get("value", "")
            try:
                value = float(text.split()[0])
            except (ValueError, IndexError):
                raise CollisionModelError(
                    where,
                    f"group_state[{index}] joint {quoted(joint.get('name', ''))}: value "
                    f"{quoted(text)} is not a number",
                ) from None
            values[joint.get("name", "")] = value
        states.append((state.get("name", f"group_state[{index}]"), values))
    return states
