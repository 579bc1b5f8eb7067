"""A joint vector on the command line as numbers or as a named state (``--seed-q ready``).

``--seed-q`` takes one value per joint (in the command's ``--deg``/``--unit``) or one name of
the robot's named states (:mod:`kin.named_states`: its table's ``[states]``, the ``--srdf``
file's ``<group_state>`` elements); ``"seed_q": "ready"`` does the same on a ``--stdin`` line.
An unknown name is one line listing the names there are (exit 2). For another option (``kin
plan --start``): declare it with ``type=joint_value`` and read it with :func:`joint_vector`.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from dh2urdf.command_line import finite_float
from dh2urdf.quoted_input import quoted
from dh2urdf.table_states import STATE_NAME

from ..exceptions import JointVectorError

if TYPE_CHECKING:
    import numpy as np

    from ..named_states import NamedStates, _Arm
    from .joint_units import JointUnits

__all__ = ["joint_value", "joint_vector", "robot_states"]


def joint_value(text: str) -> float | str:
    """Argparse type: a finite number (as ``finite_float``), or a state's name (a word)."""
    try:
        return finite_float(text)
    except argparse.ArgumentTypeError:
        if STATE_NAME.fullmatch(text) and not _float_word(text):
            return text
        raise


def _float_word(text: str) -> bool:
    """Whether Python reads ``text`` as a float (``nan``, ``inf``, ``infinity``)."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def joint_vector(
    robot: _Arm,
    values: Sequence[float | str] | None,
    units: JointUnits,
    option: str,
    srdf: str | Path | None = None,
) -> np.ndarray | None:
    """The joint vector [rad, m] an option gave: numbers in the command's units, or one name.

    Args:
        robot: The robot (its table's ``[states]``, its joint names).
        values: The option's values (:func:`joint_value` of each word), or None.
        units: The command's joint units (numbers are converted from them).
        option: The option, for messages (``--seed-q``).
        srdf: The command's ``--srdf`` file, whose group states are named states too.

    Returns:
        None when the option was not given.

    Raises:
        NamedStateError: An unknown name (the line lists the robot's named states).
        JointVectorError: A name among numbers, or numbers that are not one per joint.
    """
    if values is None:
        return None
    words = [value for value in values if isinstance(value, str)]
    if not words:  # numbers, checked by to_si (a JSON true is not 1.0)
        return units.to_si(list(values), option)  # type: ignore[arg-type]
    if len(values) != 1:
        raise JointVectorError(
            f"{option}: give one value per joint or one named state, not {quoted(words[0])} "
            "among numbers",
            len(units.joint_names),
            len(values),
        )
    return robot_states(robot, srdf).q(words[0])


def robot_states(robot: _Arm, srdf: str | Path | None = None) -> NamedStates:
    """The robot's named states (:func:`kin.named_states.named_states`), for a stream's lines."""
    from ..named_states import named_states

    return named_states(robot, srdf)
