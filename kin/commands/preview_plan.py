"""``kin preview --plan FILE.json``: the plan ``kin plan -o FILE.json`` (or ``--json``) wrote.

A plan file is one JSON object with ``status``, ``planner`` and ``path`` (and ``q``, ``q_units``,
``robot``, ``t_s`` when timed: :func:`kin.commands.plan_answer.plan_record`); a ``kin plan --stdin``
answer line saved alone is one too. Its path is animated as ``--path`` animates a joint path
(:func:`kin.path.joint_path_file.read_joint_path`: SI units, as its ``q_units`` say), in real
time when it was timed. Without ``--robot`` the plan's own ``robot`` is loaded.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from dh2urdf.input_file import read_input

from ..path.exceptions import PathError

__all__ = ["check_plan_robot", "plan_robot", "read_plan"]

#: Keys every plan record has.
PLAN_KEYS = ("status", "planner", "path")


def read_plan(file: str) -> dict[str, Any]:
    """The plan record of ``file``, checked to be a plan with a path.

    Raises:
        PathError: No such file, not JSON, not a plan (one line naming what is missing and what
            to do), or a plan without a path (its status and message).
    """
    if not Path(file).is_file():
        raise PathError(f"--plan {file}: no such file", "--plan")
    try:
        document = json.loads(read_input(file).decode("utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as err:
        raise PathError(
            f"--plan {file}: not JSON ({err}); write the plan with kin plan -o FILE.json", "--plan"
        ) from err
    missing = [key for key in PLAN_KEYS if not isinstance(document, dict) or key not in document]
    if missing:
        path_file = isinstance(document, dict) and "q" in document
        hint = " (a kin path --json file goes with --path)" if path_file else ""
        raise PathError(
            f"--plan {file} is not a plan of kin plan -o FILE.json: no "
            f"{', '.join(repr(key) for key in missing)}{hint}",
            "--plan",
        )
    if document["status"] != "ok":
        raise PathError(
            f"--plan {file}: the plan has no path to show (status {document['status']!r}: "
            f"{document.get('message', '')})",
            "--plan",
        )
    return document


def plan_robot(file: str, plan: dict[str, Any], given: str | None) -> str:
    """The ``--robot`` to load: the one given, else the plan's own.

    Raises:
        PathError: Neither gives a robot.
    """
    if given is not None:
        return given
    robot = plan.get("robot")
    if not isinstance(robot, str) or not robot:
        raise PathError(f"--plan {file} does not name its robot: give --robot", "--plan")
    return robot


def check_plan_robot(file: str, plan: dict[str, Any], robot: str) -> None:
    """Raise when the plan was made for another robot than ``robot`` (its loaded name).

    Raises:
        PathError: The plan names another robot.
    """
    made_for = plan.get("robot")
    if made_for and made_for != robot:
        raise PathError(
            f"--plan {file} was made for '{made_for}', not '{robot}': give --robot {made_for} "
            "(or leave --robot out)",
            "--plan",
        )
