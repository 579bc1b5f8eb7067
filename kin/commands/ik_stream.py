"""``kin ik --stdin``: one JSON target per input line, one JSON answer per output line.

Start-up (imports, model, solver, seed table) is paid once; then each line costs one solve. An
input line is an object: ``"target": [x, y, z]`` [--unit], optionally one of ``"rpy"``,
``"quat"``, ``"pitch"`` (with ``"roll"``) [rad, or deg with --deg], ``"position_only"``, and
``"seed_q"`` (revolute [rad or deg], prismatic [--unit]; default: the command's --seed-q).
An answer is :meth:`kin.ik.IKResult.to_dict` (SI) with ``"line"`` (1-based input line number)
and ``"q_units"``; a bad line gives ``{"line": n, "error": "..."}`` and the run goes on. Blank
lines are skipped. Nothing else is written on stdout.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable
from typing import TextIO

import numpy as np

from ..exceptions import KinError
from ..ik.result import IKResult
from ..ik.target import PositionTarget, Target
from ..robot_model import RobotModel
from .joint_units import JointUnits
from .targets import build_target, check_kind

#: Keys an input line may have.
KEYS = ("target", "rpy", "quat", "pitch", "roll", "position_only", "seed_q")
_KEYS = frozenset(KEYS)


def _answer(
    line: str,
    robot: RobotModel,
    units: JointUnits,
    solve: Callable[[Target, np.ndarray | None], IKResult],
    kinds: tuple[type, ...] | None,
    seed: np.ndarray | None,
    length: float,
    angle: float,
) -> dict:
    """The answer to one input line (raises for a bad line)."""
    try:
        request = json.loads(line)
    except ValueError as err:
        raise ValueError(f"not JSON: {err}") from None
    if not isinstance(request, dict):
        raise ValueError(f"a line must be a JSON object, got {type(request).__name__}")
    unknown = request.keys() - _KEYS
    if unknown:
        raise ValueError(f"unknown key(s) {sorted(unknown)}; known: {', '.join(KEYS)}")
    if "target" not in request:
        raise ValueError('missing "target": [x, y, z]')
    position_only = request.get("position_only", False)
    if not isinstance(position_only, bool):
        raise ValueError(f'"position_only" must be true or false, got {position_only!r}')
    target, given = build_target(
        request["target"],
        rpy=request.get("rpy"),
        quat=request.get("quat"),
        pitch=request.get("pitch"),
        roll=request.get("roll"),
        position_only=position_only,
        length=length,
        angle=angle,
    )
    if kinds is not None:
        check_kind(robot.name, robot.nq, kinds, target, given)
    seed_q = request.get("seed_q")
    if seed_q is not None:
        if not isinstance(seed_q, list):
            raise ValueError(f'"seed_q" must be a list of numbers, got {seed_q!r}')
        seed = units.to_si(seed_q, '"seed_q"')
    return result_record(solve(target, seed), target)


def result_record(result: IKResult, target: Target) -> dict:
    """``result.to_dict()`` (SI); rotation errors null when ``target`` leaves the rotation free."""
    record = result.to_dict()
    if isinstance(target, PositionTarget):
        for key in ("solutions", "rejected"):
            for solution in record[key]:
                solution["rotation_error_rad"] = None
    return record


def run_stream(
    lines: Iterable[str],
    out: TextIO,
    robot: RobotModel,
    units: JointUnits,
    solve: Callable[[Target, np.ndarray | None], IKResult],
    kinds: tuple[type, ...] | None,
    seed: np.ndarray | None,
    length: float,
    angle: float,
) -> int:
    """Answer every line of ``lines`` on ``out``, one flushed JSON line each; return 0.

    Args:
        lines: Input lines (e.g. ``sys.stdin``).
        out: Output stream.
        robot: The robot.
        units: Its joint units on the command line.
        solve: ``solve(target, seed)`` of the chosen solver, time budget bound.
        kinds: Target classes the solver accepts (None: the solver checks).
        seed: Default seed [rad] / [m], or None.
        length: Meters per ``--unit``.
        angle: Radians per input angle unit.
    """
    q_units = list(units.si_labels)
    write, flush, dumps = out.write, out.flush, json.dumps
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            record = _answer(line, robot, units, solve, kinds, seed, length, angle)
        except (KinError, ValueError, TypeError) as err:
            record = {"line": number, "error": " ".join(str(err).split())}
        else:
            record["line"] = number
            record["q_units"] = q_units
        write(dumps(record) + "\n")
        flush()
    return 0
