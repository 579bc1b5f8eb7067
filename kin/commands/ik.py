"""Solve the inverse kinematics of a robot for a tool target and print the solutions.

The solver is the robot's own (kin.ik.get_solver): the closed form when the DH table fits one,
with every branch, else the numeric solver (seed table, damped Newton, mink QP, inside the
limits, within --timeout); --solver mink forces the numeric one, --solver nr is the paper's
Newton-Raphson (position only, no limits). Targets: a position; a pose (--rpy, URDF
roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll); or --quat), whole or with --mask X Y Z RX RY RZ
(1 = constrained, 0 = free; rotations about the world axes: a SCARA's position and yaw is
1 1 1 0 0 1), on any arm (one of fewer than six joints is solved where it reaches the pose, else
told how far the nearest pose it reaches is); a position with --axis AX AY AZ, the world
direction of the tool's z axis (or --tool-axis x/y) with the roll about it free (a drill); or, for
five-joint arms, a position
with --pitch, the angle of the tool's approach axis BELOW the horizontal in the vertical plane
through the base axis and the target (0 = straight out, 90 deg = straight down), with --roll the
wrist-roll joint value q5 (default: the seed's).

Units: every length (target, prismatic joint values in and out) in --unit; revolute joint values
and the --rpy/--pitch/--roll angles in radians, degrees with --deg. --json and --stdin answers are
SI (q in rad / m as "q_units" says, errors in m and rad, time in s).

--stdin reads one JSON target per line ({"target": [x, y, z], "rpy": [r, p, y]} or "quat",
"mask", "axis", "tool_axis", "pitch", "roll", "position_only", "seed_q", "all"; in --unit / --deg) and writes exactly one JSON answer
per input line, in order, each with its "line" number ({"error": ...} for a bad line,
{"skipped": ...} for a blank one).

A URDF chain with mimic joints in series: joint vectors (--seed-q, answers) hold the independent
joints only (the names printed; each mimic joint follows its leader), the solver is damped least
squares on the coupled Jacobian (a pose without --mask, or a position), and every answer is judged
by Pinocchio's model of the original URDF with mimic joints; a search that ends without an answer
says "not_found" (or "timeout"), not "out_of_reach".

--all prints every solution, also those outside the limits; on a 7R arm (Panda, xArm7,
humanoid7, a 7R URDF) every branch of its free-joint closed form at 32 values evenly spaced over
the free joint's range, the seed's and the answer's, nearest the seed first ("all": true on a
--stdin line does the same for that line).

--scene FILE (a TOML cell or a URDF) and/or --srdf FILE [--padding M, in --unit] make the solve
collision-aware (kin.ik.collision.collision_aware): a colliding answer is rejected with its reason
("self: a/b", "scene: name"; shown with --all), the search goes on through the free joint of a
7R arm, every roll of an --axis target or --mask, and more numeric starts; "in_collision" when
the target is reached but every answer found collides. With --stdin every line is solved so.

Exit 0 when a valid solution exists, 1 when none (success false), 2 for bad input; with --stdin,
once the input ends: 1 when any line had an error or no valid solution, else 0.
"""

from __future__ import annotations

import argparse
import re
import sys
from typing import TYPE_CHECKING, Any

from ..cli import (
    ArgumentParser,
    angle_scale,
    finite_float,
    length_scale,
    positive_float,
    run_guarded,
)
from .collision_options import add_collision_options, check_padding
from .ik_counts import hidden_note, shown_rows
from .json_output import dumps
from .named_states import joint_value
from .robot_argument import add_robot_arguments
from .targets import add_orientation_options

if TYPE_CHECKING:
    from collections.abc import Callable

    from ..ik.result import IKResult
    from ..ik.solver import IKSolver
    from ..robot_model import RobotModel
    from .joint_units import JointUnits

PROG = "kin ik"
EXIT_NO_SOLUTION = 1


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin ik``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add = parser.add_argument
    add_robot_arguments(parser)
    add(
        "--target",
        type=finite_float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="tool position in the world frame [--unit] (required unless --stdin)",
    )
    add("--pitch", type=finite_float, help="approach angle below the horizontal (five-joint arms)")
    add(
        "--roll", type=finite_float, help="wrist-roll joint value q5 with --pitch (default: seed's)"
    )
    add_orientation_options(parser)
    add(
        "--tool-axis",
        choices=("x", "y", "z"),
        help="with --axis: the tool axis that points along it (default z)",
    )
    add("--position-only", action="store_true", help="ignore the tool orientation")
    add(
        "--unit",
        choices=("m", "cm", "mm"),
        default="m",
        help="unit of every length, prismatic joint values included (default m)",
    )
    add("--deg", action="store_true", help="revolute joint values and angles in degrees")
    add(
        "--seed-q",
        type=joint_value,
        nargs="+",
        metavar="Q",
        help="current joint vector: revolute [rad or deg], prismatic [--unit] (default zeros); "
        "or a named state: the table's [states], --srdf's group_state (ready)",
    )
    add(
        "--all",
        action="store_true",
        help="print every solution, also those outside the limits; on a 7R arm every branch at "
        "32 values of its free joint over its range, the seed's and the answer's",
    )
    add("--json", action="store_true", help="print one JSON object, SI units")
    add("--solver", choices=("mink", "nr"), help="force the numeric solver: mink, or nr (paper's)")
    add(
        "--timeout",
        type=positive_float,
        help="time cap of a numeric solve [ms] (default 2000; the answer is decided by its "
        "seeded starts, 200 for a full pose or position, 32 for a partial one)",
    )
    add("--stdin", action="store_true", help="read JSON targets from stdin, one per line")
    add_collision_options(
        parser,
        scene="avoid collisions with a cell: TOML of boxes... or URDF",
        srdf="avoid collisions; a MoveIt SRDF's pairs are allowed",
    )
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Solve and print; exit 0, 1 (no valid solution) or 2 (bad input)."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    target_options = [
        name
        for name, value in (
            ("--target", args.target),
            ("--rpy", args.rpy),
            ("--quat", args.quat),
            ("--mask", args.mask),
            ("--axis", args.axis),
            ("--tool-axis", args.tool_axis),
            ("--pitch", args.pitch),
            ("--roll", args.roll),
        )
        if value is not None
    ] + (["--position-only"] if args.position_only else [])
    if args.stdin and target_options:
        parser.error(f"--stdin reads the targets from stdin: drop {', '.join(target_options)}")
    if not args.stdin and args.target is None:
        parser.error("the following arguments are required: --target (or --stdin)")
    check_padding(parser, args)
    return run_guarded(prog, lambda: _run(args))


def _run(args: argparse.Namespace) -> int:
    """Load the robot and its solver, then solve the target or the stdin stream."""
    import numpy as np

    from ..ik.targets.target import PositionTarget
    from ..robot_model import RobotModel
    from .arm_route import arm_units, load_arm_argument, mimic_line, mimic_records
    from .collision_options import collision_checker
    from .named_states import joint_vector, robot_states
    from .solver_choice import command_solver
    from .targets import Takes, build_target

    robot = load_arm_argument(args)
    units = arm_units(robot, args.unit, args.deg)
    # The documented default start is q = 0, as `kin preview --ik` starts from --q's zeros: the
    # same target and start give the same answer in both.
    seed = joint_vector(robot, args.seed_q, units, "--seed-q", args.srdf)
    seed = np.zeros(robot.nq) if seed is None else seed
    checker = None
    if isinstance(robot, RobotModel):
        checker = collision_checker(args, robot, length_scale(args.unit))
    chosen = command_solver(
        robot,
        args.solver,
        collisions=checker,
        collision_files=args.scene or args.srdf,
        timeout=None if args.timeout is None else args.timeout / 1e3,
        all_branches=args.all,
    )
    solver, solve, kinds = chosen.solver, chosen.solve, chosen.kinds
    length = length_scale(args.unit)
    angle = angle_scale(args.deg)
    if args.stdin:
        from .ik_stream import StreamSolver

        stream = StreamSolver(
            robot.name,
            robot.nq,
            units,
            solve,
            kinds,
            seed,
            length,
            angle,
            args.all,
            # the compiled batch route answers without the checker: bypassed with collisions
            batch=_batch_stage(robot, solver) if isinstance(robot, RobotModel) else None,
            pipeline=solver.name,
            solve_all=chosen.solve_all,
            states=robot_states(robot, args.srdf),
        )
        return stream.run(sys.stdin, sys.stdout)
    target, _ = build_target(
        args.target,
        rpy=args.rpy,
        quat=args.quat,
        pitch=args.pitch,
        roll=args.roll,
        position_only=args.position_only,
        length=length,
        angle=angle,
        mask=args.mask,
        axis=args.axis,
        tool_axis=args.tool_axis,
        takes=None if kinds is None else Takes(robot.name, robot.nq, kinds),
    )
    result = solve(target, seed)
    if args.json:
        from .ik_stream import result_record

        record = result_record(result, target)
        record.update(robot=robot.name, joint_names=list(units.joint_names))
        record["q_units"] = list(units.si_labels)
        mimic = mimic_records(robot)
        if mimic:
            record["mimic"] = mimic
        print(dumps(record))
    else:
        free_rotation = isinstance(target, PositionTarget)
        _print_result(result, robot.name, units, args.unit, args.all, free_rotation)
        note = mimic_line(robot)
        if note is not None:
            print(note)
    return 0 if result.success else EXIT_NO_SOLUTION


def _batch_stage(robot: RobotModel, solver: IKSolver) -> Callable[..., Callable[[], Any]] | None:
    """``batch(points, rotations, seeds) -> finish`` of the solver's free-joint closed form, or None.

    The lines of a read batch are answered together by it
    (:func:`kin.ik.batch_solve.start_free_joint_answers`: its scans started in threads, ``finish()``
    waits for them and gives ``(q, position errors, rotation errors)``) when the solver has that
    batch route (:meth:`kin.ik.solver.IKSolver.batch_route`: the numeric one with a free-joint
    closed form, humanoid7, Panda, xArm7): the answers its calls would give first. The
    collision-aware solver has none (its answers are judged one by one).
    """
    from ..ik.batch_solve import start_free_joint_answers

    if solver.batch_route() is None:
        return None

    def batch(points: Any, rotations: Any, seeds: Any) -> Callable[[], Any]:
        started = start_free_joint_answers(solver, robot, points, rotations, seeds)
        assert started is not None  # the solver has a free-joint closed form (checked above)
        return started.result

    return batch


#: A length in meters as the library's messages write it: ``0.386 m`` (not ``m^3``, ``ms``).
_METERS = re.compile(r"(?<![\w.])([-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?) m\b(?!\^)")


def message_in_unit(message: str, length: float, unit: str) -> str:
    """``message`` with its lengths in meters (``0.386 m``) written in ``unit`` (``386 mm``).

    Args:
        message: A library message (lengths in meters).
        length: Meters per ``unit``.
        unit: The user's length unit.
    """
    if unit == "m":
        return message
    return _METERS.sub(lambda found: f"{float(found.group(1)) / length:.4g} {unit}", message)


def _print_result(
    result: IKResult,
    robot: str,
    units: JointUnits,
    unit: str,
    show_all: bool,
    free_rotation: bool,
) -> None:
    """The result as text, every number with its unit."""
    length = length_scale(unit)
    method = f", {result.method}" if result.method else ""
    message = message_in_unit(result.message, length, unit)
    shown = shown_rows(result, show_all)
    print(
        f"{robot} ({result.solver}{method}): {result.status}: {message}{hidden_note(result, shown)}"
    )
    if result.free:
        print(f"free: {', '.join(result.free)} (verified on the other components)")
    if result.distance_to_workspace is not None:
        print(f"distance to the workspace: {result.distance_to_workspace / length:.6g} {unit}")
    print(f"iterations: {result.iterations}, time: {result.time * 1e3:.3f} ms")
    if not shown:
        return
    columns = units.columns()
    widths = [max(10, len(c)) for c in columns]
    header = "  ".join(f"{c:>{w}}" for c, w in zip(columns, widths))
    label = max([len("branch"), *(len(solution.branch) for solution in shown)])
    print(f"{'branch':<{label}} {header}  limits  pos.err [{unit}]  rot.err [rad]")
    for solution in shown:
        values = "  ".join(f"{v:>{w}.4f}" for v, w in zip(units.from_si(solution.q), widths))
        error = None if free_rotation else solution.rotation_error
        rotation = "-" if error is None else f"{error:.3g}"
        reason = solution.reason
        if reason.startswith(("self:", "scene:")):  # a collision-aware solve's reason
            reason = f"collides: {reason}"
        reason = f"  {reason}" if reason else ""
        print(
            f"{solution.branch:<{label}} {values}  {'ok' if solution.within_limits else 'OUT':>6}  "
            f"{solution.position_error / length:.3g}  {rotation}{reason}"
        )
