"""The arm of ``kin fk`` and ``kin ik``: a robot, or a URDF chain with mimic joints.

A mimic joint in series on a URDF chain follows its leader (``q = multiplier * q_leader +
offset``). These two commands load such a chain as a :class:`kin.mimic.arm.MimicArm`
(:func:`kin.mimic.arm.load_arm`): the user's joint vector holds the independent joints only,
base to tip, and the output names them and says how each mimic joint follows its leader. Every
other robot loads as the other commands load it (:func:`load_robot_argument`).
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

import numpy as np

from dh2urdf.command_line import angle_scale, length_scale

from ..robot_model import RobotModel
from .joint_units import JointUnits

if TYPE_CHECKING:
    from ..mimic.arm import MimicArm

#: What ``--q``'s help adds: the joint vector of a chain with mimic joints.
MIMIC_HELP = "a URDF's mimic joints are not given: they follow their leaders"


def load_arm_argument(args: argparse.Namespace) -> RobotModel | MimicArm:
    """The robot the options name, a :class:`~kin.mimic.arm.MimicArm` for a mimic chain."""
    from ..mimic.arm import load_arm

    return load_arm(args.robot, getattr(args, "base", None), getattr(args, "tip", None))


def arm_units(arm: RobotModel | MimicArm, unit: str = "m", degrees: bool = False) -> JointUnits:
    """Units of the arm's joints for ``--unit unit`` and ``--deg`` (independent joints only).

    Args:
        arm: The arm.
        unit: The length unit of ``--unit``.
        degrees: Revolute values in degrees (``--deg``).
    """
    if isinstance(arm, RobotModel):
        return JointUnits.of(arm.name, arm.table, unit, degrees)
    revolute = [joint.joint_type == "revolute" for joint in arm.chain.independent]
    angle, length = angle_scale(degrees), length_scale(unit)
    scales = np.array([angle if r else length for r in revolute], dtype=float)
    scales.setflags(write=False)
    return JointUnits(
        robot=arm.name,
        joint_names=arm.joint_names,
        scales=scales,
        labels=tuple(("deg" if degrees else "rad") if r else unit for r in revolute),
        si_labels=tuple("rad" if r else "m" for r in revolute),
        lower=arm.lower,
        upper=arm.upper,
    )


def mimic_records(arm: RobotModel | MimicArm) -> list[dict[str, object]]:
    """Each mimic joint of the chain: ``joint``, ``leader``, ``multiplier``, ``offset`` (SI)."""
    if isinstance(arm, RobotModel):
        return []
    return [
        {
            "joint": joint.name,
            "leader": joint.mimic.leader,
            "multiplier": joint.mimic.multiplier,
            "offset": joint.mimic.offset,
        }
        for joint in arm.chain.joints
        if joint.mimic is not None
    ]


def mimic_line(arm: RobotModel | MimicArm) -> str | None:
    """One text line on how the mimic joints follow their leaders, or None without any.

    E.g. ``mimic: j3m = 1 * j3 + 0.3 rad (q holds the independent joints)``; offsets in SI.
    """
    if isinstance(arm, RobotModel):
        return None
    terms = [
        f"{joint.name} = {joint.mimic.multiplier:g} * {joint.mimic.leader} + "
        f"{joint.mimic.offset:g} {'rad' if joint.joint_type == 'revolute' else 'm'}"
        for joint in arm.chain.joints
        if joint.mimic is not None
    ]
    return f"mimic: {', '.join(terms)} (q holds the independent joints)" if terms else None
