"""A robot's named joint states: its table's ``[states]`` and an SRDF's ``<group_state>``.

Where a joint vector is asked for (a seed, a start), a name may stand for it: ``ready``,
``home``. The names come from, in this order:

1. the DH table's ``[states]`` (:mod:`dh2urdf.table_states`; the shipped Panda's ``ready``, the
   URs' ``home`` and ``up``, from the makers' MoveIt configurations);
2. an SRDF's ``<group_state>`` elements (``srdf``) that set every joint of the robot's chain
   (matched by joint name; other joints they set, such as a gripper's, are ignored). An SRDF
   state takes the place of a table's state of the same name.

A group state that sets only some of the chain's joints (a gripper's ``open``) is no joint
vector of the arm: asking for it says which joints it leaves out.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

import numpy as np

from dh2urdf.quoted_input import quoted

from .exceptions import NamedStateError

__all__ = ["NamedJointState", "NamedStates", "named_states"]


class _Arm(Protocol):
    """What the lookup reads of a robot (:class:`kin.RobotModel`, :class:`kin.mimic.arm.MimicArm`)."""

    @property
    def name(self) -> str: ...

    @property
    def joint_names(self) -> tuple[str, ...]: ...

    @property
    def table(self) -> object: ...


@dataclass(frozen=True)
class NamedJointState:
    """A named joint vector of a robot.

    Attributes:
        name: The state's name.
        q: One value per joint of the robot, base to tip [rad, or m for a prismatic joint].
        source: Where it was read: ``"table"`` or ``"SRDF group_state"``.
    """

    name: str
    q: tuple[float, ...]
    source: str


@dataclass(frozen=True)
class NamedStates:
    """The named states of one robot.

    Attributes:
        robot: The robot's name (for messages).
        states: The full joint vectors, table's first, then the SRDF's.
        partial: SRDF group states that leave chain joints out: name -> the joints left out.
    """

    robot: str
    states: tuple[NamedJointState, ...] = ()
    partial: Mapping[str, tuple[str, ...]] = field(default_factory=dict)

    @property
    def names(self) -> tuple[str, ...]:
        """The names of the full joint vectors."""
        return tuple(state.name for state in self.states)

    def q(self, name: str) -> np.ndarray:
        """The joint vector named ``name`` [rad, m].

        Raises:
            NamedStateError: One line: the robot has no such full state; it lists the names
                there are (or says where names come from when there are none).
        """
        for state in self.states:
            if state.name == name:
                return np.array(state.q, dtype=float)
        known = self.names
        if name in self.partial:
            message = (
                f"{self.robot}: the SRDF group_state {quoted(name)} leaves out joints "
                f"{', '.join(self.partial[name])} of the arm"
            )
        else:
            message = f"{self.robot}: no named state {quoted(name)}"
        if known:
            message += f"; its named states: {', '.join(known)}"
        else:
            message += (
                "; it has none: give a [states] table in its DH table, or --srdf FILE with "
                "<group_state> elements"
            )
        raise NamedStateError(message, name, known)


def named_states(robot: _Arm, srdf: str | Path | None = None) -> NamedStates:
    """The named states of ``robot``: its table's ``[states]``, then ``srdf``'s group states.

    Args:
        robot: The robot (its ``table`` and ``joint_names``).
        srdf: A MoveIt SRDF, or None.

    Raises:
        CollisionModelError: The SRDF cannot be read, or a group state's value is no number.
    """
    joints = tuple(robot.joint_names)
    found: dict[str, NamedJointState] = {}
    for state in getattr(robot.table, "states", ()):
        if len(state.q) == len(joints):  # a chain with mimic joints: the table has more rows
            found[state.name] = NamedJointState(state.name, tuple(state.q), "table")
    partial: dict[str, tuple[str, ...]] = {}
    if srdf is not None:
        from .collision.held_joints import _group_states

        for name, values in _group_states(srdf):
            missing = tuple(joint for joint in joints if joint not in values)
            if missing:
                partial[name] = missing
                continue
            q = tuple(float(values[joint]) for joint in joints)
            found.pop(name, None)  # the SRDF's comes last, in its place
            found[name] = NamedJointState(name, q, "SRDF group_state")
    return NamedStates(robot.name, tuple(found.values()), partial)
