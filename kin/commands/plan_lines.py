"""One line of ``kin plan --stdin``: a JSON request read into a plan, and its answer.

A line is an object with the keys of :data:`KEYS`, named as the command's options: ``"start"``
and ``"goal"`` (joint values: revolute [rad, or deg with ``"deg": true``], prismatic [--unit]) or
``"target"`` [--unit] with ``"rpy"``, ``"quat"``, ``"mask"``, ``"axis"`` (and ``"tool_axis"``)
as in ``kin ik --stdin``; ``"planner"``, ``"seed"``, ``"time_limit"`` [s], ``"max_checks"``,
``"time"``, ``"any_turn"``. What a line leaves out is the command line's (:class:`StreamSetup`).

The answer is the object ``kin plan --json`` prints (:func:`kin.commands.plan_answer.plan_record`), SI,
with ``"line"`` (the 1-based input line number) and ``"warnings"`` (a unit slip of the line);
a bad line's is ``{"line": n, "error": "..."}``, a blank line's ``{"line": n, "skipped": ...}``.

:class:`PlanLines` holds what every line shares, built once: the robot, its joint units and the
collision checker. :func:`answer_lines` answers a run of lines in a Dask worker, where the
:class:`PlanLines` of a :class:`StreamSetup` is built on the first call and kept for the others.
"""

from __future__ import annotations

import argparse
import json
import math
import threading
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from dh2urdf.quoted_input import quoted

from ..cli import angle_scale, length_scale
from .json_output import dumps
from .stream_records import error_record

__all__ = ["KEYS", "PlanLines", "StreamSetup", "answer_lines"]

#: Keys of a target goal (as ``kin ik --stdin`` reads them), ``"target"`` first.
_TARGET_KEYS = ("target", "rpy", "quat", "mask", "axis", "tool_axis")
#: Keys an input line may have.
KEYS = (
    "start",
    "goal",
    *_TARGET_KEYS,
    "deg",
    "planner",
    "seed",
    "time_limit",
    "max_checks",
    "time",
    "any_turn",
)
_KEYS = frozenset(KEYS)
#: :class:`PlanLines` a worker process keeps (one per stream and worker thread it served).
_KEPT = 4
_built: dict[tuple[StreamSetup, int], PlanLines] = {}


@dataclass(frozen=True)
class StreamSetup:
    """What the plans of a stream share, as the command line gives it (a worker's key).

    Attributes:
        robot: ``--robot`` (a name, or a file's absolute path).
        base: ``--base`` link, or None.
        tip: ``--tip`` link, or None.
        unit: ``--unit``.
        deg: ``--deg`` (a line's ``"deg"`` default).
        start: ``--start`` in command-line units (a line's default), or None.
        planner: ``--planner``.
        seed: ``--seed``.
        time_limit: ``--time-limit`` [s].
        max_checks: ``--max-checks``.
        time: ``--time``.
        any_turn: ``--any-turn``.
        scene: ``--scene`` (absolute path), or None.
        srdf: ``--srdf`` (absolute path), or None.
        padding: ``--padding`` [--unit], or None.
        hold: ``--hold`` as (joint, value [rad or m]) pairs.
    """

    robot: str
    base: str | None
    tip: str | None
    unit: str
    deg: bool
    start: tuple[float, ...] | None
    planner: str
    seed: int
    time_limit: float
    max_checks: int
    time: bool
    any_turn: bool
    scene: str | None
    srdf: str | None
    padding: float | None
    hold: tuple[tuple[str, float], ...]

    @classmethod
    def of(cls, args: argparse.Namespace) -> StreamSetup:
        """The setup of parsed ``kin plan`` options.

        Files are made absolute: the workers may not share this working directory.
        """
        from .collision_options import held_joints

        return cls(
            robot=_absolute(args.robot),
            base=args.base,
            tip=args.tip,
            unit=args.unit,
            deg=args.deg,
            start=None if args.start is None else tuple(args.start),
            planner=args.planner,
            seed=args.seed,
            time_limit=args.time_limit,
            max_checks=args.max_checks,
            time=args.time,
            any_turn=args.any_turn,
            scene=None if args.scene is None else _absolute(args.scene),
            srdf=None if args.srdf is None else _absolute(args.srdf),
            padding=args.padding,
            hold=tuple(sorted(held_joints(args).items())),
        )


def _absolute(name: str) -> str:
    """``name`` as an absolute path when it names a file here, else as it is (a robot's name)."""
    path = Path(name)
    return str(path.resolve()) if path.is_file() else name


class PlanLines:
    """Answers the request lines of one stream: the robot and collision model built once.

    Args:
        setup: The command line's choices.

    Raises:
        KinError, Dh2UrdfError: The robot or a collision file cannot be loaded.
    """

    def __init__(self, setup: StreamSetup):
        from ..robot_model import load_robot
        from .arm_route import arm_units
        from .plan_answer import joints_within_limits, plan_checker

        self.setup = setup
        self.robot = load_robot(setup.robot, setup.base, setup.tip)
        self.units = {deg: arm_units(self.robot, setup.unit, deg) for deg in (False, True)}
        self.length = length_scale(setup.unit)
        options = argparse.Namespace(
            scene=setup.scene, srdf=setup.srdf, padding=setup.padding, hold=list(setup.hold)
        )
        self.checker = plan_checker(self.robot, options, self.length)
        #: ``--start`` [rad, m] in the command line's units, or None.
        self.start = None
        if setup.start is not None:
            units = self.units[setup.deg]
            self.start = joints_within_limits(self.robot, units, setup.start, "--start", setup.srdf)

    def answer(self, number: int, line: str | bytes) -> tuple[dict[str, Any], bool]:
        """The answer of input line ``number`` and whether it failed (an error, or no path).

        Never raises for a bad line or a failed plan (an error record instead); a Ctrl-C
        (``KeyboardInterrupt``) goes through.
        """
        if not line or line.isspace():
            return {"line": number, "skipped": "blank line"}, False
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                record = self._planned(line)
        except Exception as err:  # noqa: BLE001 - one line fails, never the stream
            record = error_record(number, err)
            slips = [  # degrees read as radians, say
                _one_line(w.message).replace("add --deg", 'add "deg": true') for w in caught
            ]
            if slips:
                record["error"] = "; ".join([record["error"], *slips])
            return {"line": number, **record}, True
        notes = [_one_line(w.message) for w in caught]
        if notes:
            record["warnings"] = notes
        record["line"] = number
        return record, record["status"] != "ok"

    def _planned(self, line: str | bytes) -> dict[str, Any]:
        """The plan record of one request line (raises for a bad one)."""
        from ..plan import plan
        from .plan_answer import plan_record, timed_plan

        request = _request(line)
        setup = self.setup
        deg = _flag(request, "deg", setup.deg)
        units = self.units[deg]
        if "start" in request:
            q0 = self._joints(units, request["start"], "start")
        elif self.start is not None:
            q0 = self.start
        else:
            raise ValueError('missing "start": [joint values] (or give --start)')
        result = plan(
            self.robot,
            q0,
            self._goal(request, units, deg),
            collisions=self.checker,
            planner=request.get("planner", setup.planner),
            time_limit=_seconds(request.get("time_limit", setup.time_limit)),
            max_checks=request.get("max_checks", setup.max_checks),
            seed=request.get("seed", setup.seed),
            any_turn=_flag(request, "any_turn", setup.any_turn),
        )
        timed = None
        if _flag(request, "time", setup.time) and result.success:
            timed = timed_plan(self.robot, result)
        return plan_record(self.robot, units, result, timed)

    def _joints(self, units: Any, values: Any, key: str) -> Any:
        """A line's joint vector in SI [rad, m], within the limits (the error names the key)."""
        from .plan_answer import joints_within_limits

        if isinstance(values, str):  # a named state ("start": "ready")
            values = [values]
        elif not isinstance(values, (list, tuple)):
            raise ValueError(
                f'"{key}" must be a list of numbers or a state\'s name, got {quoted(values)}'
            )
        return joints_within_limits(self.robot, units, values, f'"{key}"', self.setup.srdf)

    def _goal(self, request: dict[str, Any], units: Any, deg: bool) -> Any:
        """The line's goal: a joint vector [rad, m] or a target (SI)."""
        from .targets import build_target

        if ("goal" in request) == ("target" in request):
            raise ValueError('give the goal as "goal": [joints] or as "target": [x, y, z]')
        if "goal" in request:
            given = [key for key in _TARGET_KEYS[1:] if key in request]
            if given:
                raise ValueError(f'{quoted(given)} go with "target", not "goal"')
            return self._joints(units, request["goal"], "goal")
        target, _ = build_target(
            request["target"],
            rpy=request.get("rpy"),
            quat=request.get("quat"),
            mask=request.get("mask"),
            axis=request.get("axis"),
            tool_axis=request.get("tool_axis"),
            length=self.length,
            angle=angle_scale(deg),
        )
        return target


def _one_line(message: Warning | str) -> str:
    """A warning's text on one line."""
    return " ".join(str(message).split())


def _request(line: str | bytes) -> dict[str, Any]:
    """The JSON object of a line, with known keys only."""
    try:
        request = json.loads(line)
    except (ValueError, RecursionError) as err:
        raise ValueError(f"not JSON: {err}") from None
    if not isinstance(request, dict):
        raise ValueError(f"a line must be a JSON object, got {type(request).__name__}")
    if not request.keys() <= _KEYS:
        unknown = sorted(request.keys() - _KEYS)
        raise ValueError(f"unknown key(s) {quoted(unknown)}; known: {', '.join(KEYS)}")
    return request


def _flag(request: dict[str, Any], key: str, default: bool) -> bool:
    """A true/false key of the line, or ``default``."""
    value = request.get(key, default)
    if value is not True and value is not False:
        raise ValueError(f'"{key}" must be true or false, got {quoted(value)}')
    return bool(value)


def _seconds(value: Any) -> float:
    """A line's ``"time_limit"``: a positive, finite number of seconds."""
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, float))
        or not math.isfinite(value)
        or value <= 0
    ):
        raise ValueError(f'"time_limit" must be a positive number of seconds, got {quoted(value)}')
    return float(value)


def answer_lines(setup: StreamSetup, first: int, lines: list[bytes]) -> list[tuple[str, bool]]:
    """The answers of consecutive input lines in a worker, each one encoded JSON line.

    The worker's :class:`PlanLines` of ``setup`` is built on its first call in a thread and kept
    (the collision checker's Pinocchio and coal data are not shared between threads).

    Args:
        setup: The stream's setup.
        first: The line number of ``lines[0]``.
        lines: The input lines.

    Returns:
        Per line, its answer (ending in a newline) and whether it failed.
    """
    key = (setup, threading.get_ident())  # a checker is not shared between threads
    answering = _built.get(key)
    if answering is None:
        if len(_built) >= _KEPT:
            _built.clear()
        answering = _built[key] = PlanLines(setup)
    out = []
    for number, line in enumerate(lines, start=first):
        record, failed = answering.answer(number, line)
        out.append((dumps(record) + "\n", failed))
    return out
