"""Follow a straight line or a polyline of tool poses with the joints, and optionally time it.

The tool moves from --from through each --via (in the order given) to --to, in --steps steps in
all: positions on straight segments, orientations turning about one axis (slerp). A point takes
its orientation from the option right after it: --rpy R P Y (URDF roll-pitch-yaw) or --quat W X
Y Z (full pose; --mask X Y Z RX RY RZ keeps only some of its components, at every point), --axis
AX AY AZ (the tool's z axis, or --tool-axis, along that world direction, the roll free), or, for
five-joint arms, --pitch P [--roll R]; give one at every point or none. Closed-form arms
stay on one branch (the one nearest --seed-q, or --branch); redundant and numeric-only arms move
by velocity-limited differential IK steps. A joint limit, an unreachable point or a jump larger
than --max-step stops the motion there: "stopped_at" is that sample.

--time adds the time-optimal timing (toppra) under the joint velocity and acceleration limits of
the DH table (rows' "velocity" and "acceleration"), or --vmax / --amax (one value, or one per
joint).

Units: every length (points, prismatic joint values and their rates) in --unit; revolute joint
values, angles and their rates in radians, degrees with --deg. --json and --csv are SI (q in rad /
m as "q_units" says, deviations in m, times in s).

A progress bar (samples followed) goes to stderr on a terminal, unless --quiet.

--scene FILE (a TOML cell or a URDF) and/or --srdf FILE [--padding M] check the solved path for
collisions (kin check's shapes and pairs): every sample, and the motion between samples by a step
bound (a pair is free between two samples when its distances there add up to more than how far
the links can move, |dq_j| times their reach from joint j; else the step is halved, down to
1e-6 m). The first colliding segment and pair are named. --avoid keeps every sample and the
motion between samples free: when the plain path collides, the free answers of every sample
(another branch of a closed form, the free joint of a 7R arm, the numeric solver's other starts)
are joined, within --max-step and by free motions, into the path of least joint motion; or one
line names the sample (index, arc length, pose) where no free answer goes on, exit 1, nothing
written.

Exit 0 when the whole path is followed (and collision-free), 1 when the motion stopped or the
path collides, 2 for bad input.
"""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING, Any

from ..cli import ArgumentParser, finite_float, positive_float, positive_int, run_guarded
from .collision_options import add_collision_options, check_padding, collision_checker
from .json_output import dumps
from .named_states import joint_value, joint_vector
from .robot_argument import add_robot_arguments, load_robot_argument

if TYPE_CHECKING:
    from ..path import PathResult, TimedPath
    from .joint_units import JointUnits

PROG = "kin path"
EXIT_STOPPED = 1
POINTS = ("--from", "--via", "--to")


class _PointAction(argparse.Action):
    """``--from/--via/--to X Y Z`` start a point; ``--rpy/--quat/--pitch/--roll`` complete it."""

    def __call__(self, parser, namespace, values, option_string=None):  # noqa: ANN001, D102
        points = list(getattr(namespace, "points", None) or [])
        if option_string in POINTS:
            points.append({"option": option_string, "xyz": values})
        else:
            if not points:
                parser.error(f"{option_string} must follow --from, --via or --to")
            key = option_string.lstrip("-")
            if key in points[-1]:
                parser.error(f"{option_string} given twice for {points[-1]['option']}")
            points[-1][key] = values
        namespace.points = points


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin path``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add = parser.add_argument
    add_robot_arguments(parser)
    for option, text in (
        ("--from", "start point of the tool, world frame [--unit]"),
        ("--via", "intermediate point (repeat for a polyline) [--unit]"),
        ("--to", "end point of the tool [--unit]"),
    ):
        add(
            option,
            type=finite_float,
            nargs=3,
            metavar=("X", "Y", "Z"),
            action=_PointAction,
            help=text,
        )
    add(
        "--rpy",
        type=finite_float,
        nargs=3,
        metavar=("R", "P", "Y"),
        action=_PointAction,
        help="orientation of the point before it: URDF roll-pitch-yaw",
    )
    add(
        "--quat",
        type=finite_float,
        nargs=4,
        metavar=("W", "X", "Y", "Z"),
        action=_PointAction,
        help="orientation of the point before it: unit quaternion",
    )
    add(
        "--axis",
        type=finite_float,
        nargs=3,
        metavar=("AX", "AY", "AZ"),
        action=_PointAction,
        help="tool z axis (or --tool-axis) of the point before it, world direction; roll free",
    )
    add(
        "--mask",
        type=finite_float,
        nargs=6,
        metavar=("X", "Y", "Z", "RX", "RY", "RZ"),
        help="with --rpy/--quat points: the pose components kept (1) or free (0), every point",
    )
    add("--tool-axis", choices=("x", "y", "z"), help="with --axis: the tool axis (default z)")
    add("--pitch", type=finite_float, action=_PointAction, help="five-joint arms: approach angle")
    add("--roll", type=finite_float, action=_PointAction, help="with --pitch: wrist-roll q5")
    add("--steps", type=positive_int, required=True, help="number of steps along the whole path")
    add("--unit", choices=("m", "cm", "mm"), default="m", help="unit of every length (default m)")
    add("--deg", action="store_true", help="revolute joint values and angles in degrees")
    add(
        "--seed-q",
        type=joint_value,
        nargs="+",
        metavar="Q",
        help="joint vector the start should be near, or a named state (the table's [states], "
        "--srdf's group_state: ready)",
    )
    add("--branch", help="closed form: branch label of the start (e.g. 'shoulder front, elbow up')")
    add(
        "--max-step",
        type=positive_float,
        help="largest joint change between samples: revolute [rad or deg], prismatic [--unit] "
        "(default 0.35 rad or m)",
    )
    add("--time", action="store_true", help="time-optimal timing under the joint limits")
    add(
        "--vmax", type=positive_float, nargs="+", help="joint velocity limits [unit/s], with --time"
    )
    add(
        "--amax", type=positive_float, nargs="+", help="joint accel. limits [unit/s^2], with --time"
    )
    add("--dt", type=positive_float, help="with --time: resample the motion every DT [s]")
    add_collision_options(
        parser,
        scene="check collisions with a cell: TOML of boxes... or URDF",
        srdf="check collisions; a MoveIt SRDF's pairs are allowed",
    )
    add(
        "--avoid",
        action="store_true",
        help="with --scene/--srdf: keep every sample and motion collision-free (another branch, "
        "the free joint, other starts), or fail naming the sample",
    )
    add("--json", action="store_true", help="print one JSON object, SI units")
    add("--csv", metavar="FILE", help="write the joint path (SI, header with units) to FILE")
    add("--quiet", action="store_true", help="no progress bar on stderr")
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Follow the path and print it; exit 0, 1 (stopped) or 2 (bad input)."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    points = getattr(args, "points", None) or []
    for option in ("--from", "--to"):
        count = sum(p["option"] == option for p in points)
        if count != 1:
            parser.error(f"give {option} exactly once, got it {count} times")
    for option in ("--vmax", "--amax", "--dt"):
        if getattr(args, option[2:]) is not None and not args.time:
            parser.error(f"{option} needs --time")
    if args.mask is not None and not any("rpy" in p or "quat" in p for p in points):
        parser.error(
            "--mask needs --rpy or --quat at the points (the poses whose components it keeps)"
        )
    if args.tool_axis is not None and not any("axis" in p for p in points):
        parser.error("--tool-axis needs --axis at the points")
    check_padding(parser, args)
    if args.avoid and args.scene is None and args.srdf is None:
        parser.error("--avoid needs --scene or --srdf (the cell to avoid)")
    return run_guarded(prog, lambda: _run(args, points, prog))


def _run(args: argparse.Namespace, points: list[dict[str, Any]], prog: str = PROG) -> int:
    """Build the path, follow it, time it, and write the outputs."""
    from ..cli import angle_scale, length_scale
    from ..path import (
        check_path_collisions,
        follow_path,
        follow_path_avoiding,
        path_solver,
        polyline,
    )
    from ..path.follow import MAX_JOINT_STEP
    from .joint_units import JointUnits
    from .output_file import checked_output, input_files
    from .path_output import print_text, write_csv
    from .progress import ProgressBar
    from .targets import Takes, build_target

    if args.csv:
        inputs = input_files(args, "--robot", "--scene", "--srdf")  # never written over
        checked_output(args.csv, "--csv", (".csv",), inputs)  # before the path is computed
    robot = load_robot_argument(args)
    units = JointUnits.of(robot.name, robot.table, args.unit, args.deg)
    length, angle = length_scale(args.unit), angle_scale(args.deg)
    ordered = [p for p in points if p["option"] == "--from"]
    ordered += [p for p in points if p["option"] == "--via"]
    ordered += [p for p in points if p["option"] == "--to"]
    _check_orientations(ordered)
    solver = path_solver(robot)
    takes = Takes(robot.name, robot.nq, tuple(solver.target_kinds))  # type: ignore[attr-defined]
    waypoints = []
    for point in ordered:
        target, _ = build_target(
            point["xyz"],
            rpy=point.get("rpy"),
            quat=point.get("quat"),
            pitch=point.get("pitch"),
            roll=point.get("roll"),
            length=length,
            angle=angle,
            mask=args.mask if ("rpy" in point or "quat" in point) else None,
            axis=point.get("axis"),
            tool_axis=args.tool_axis if "axis" in point else None,
            takes=takes,
        )
        waypoints.append(target)
    checker = collision_checker(args, robot, length)  # bad files fail before the solve
    seed = joint_vector(robot, args.seed_q, units, "--seed-q", args.srdf)
    max_step = MAX_JOINT_STEP if args.max_step is None else _max_step(args, units)
    path = polyline(waypoints, args.steps)
    avoided = None
    with ProgressBar(prog, "samples", quiet=args.quiet) as bar:
        if args.avoid:
            avoided = follow_path_avoiding(
                robot,
                path,
                checker,
                seed,
                branch=args.branch,
                max_joint_step=max_step,
                progress=bar,
            )
        else:
            result = follow_path(
                robot,
                path,
                seed,
                solver=solver,
                branch=args.branch,
                max_joint_step=max_step,
                progress=bar,
            )
    if avoided is not None:
        if avoided.result is None:
            assert avoided.failure is not None
            print(f"{prog}: {avoided.failure.describe()}", file=sys.stderr)
            return EXIT_STOPPED  # nothing written: no path
        result = avoided.result
    timed = _timing(args, robot, units, result) if args.time and len(result.q) >= 2 else None
    check = avoided.check if avoided is not None else None
    if check is None and checker is not None:
        check = check_path_collisions(checker, result.q)
    if args.csv:
        write_csv(args.csv, units, result, timed, args.dt is not None)
    if args.json:
        record = _record(robot.name, units, result, timed, args.dt is not None)
        if check is not None:
            record["collisions"] = check.to_dict()
        if avoided is not None:
            record["avoid"] = avoided.to_dict()
        print(dumps(record))
    else:
        collides = check is not None and check.first is not None
        print_text(robot.name, units, args.unit, length, result, timed, collides)
        if avoided is not None:
            plain = avoided.plain
            why = "stops before the end" if plain is None else f"collides ({plain.describe()})"
            done = (
                f"the plain path {why}; this one is free" if avoided.searched else "nothing to do"
            )
            print(f"avoid: {done}")
        if check is not None:
            verdict = "free" if check.first is None else f"IN COLLISION: {check.describe()}"
            print(f"collisions: {verdict} ({len(result.q)} samples; {check.rule})")
            if checker.model.held.note:
                print(f"joints off the chain held at: {checker.model.held.note}")
    if check is not None and check.first is not None:
        print(f"{prog}: the path collides: {check.describe()}", file=sys.stderr)
        return EXIT_STOPPED
    return 0 if result.success else EXIT_STOPPED


def _check_orientations(points: list[dict[str, Any]]) -> None:
    """Every point gives the same kind of orientation (a pose, a pitch, or none)."""
    from ..path import PathError

    def kind(point: dict[str, Any]) -> str:
        if "rpy" in point or "quat" in point:
            return "--rpy/--quat"
        if "axis" in point:
            return "--axis"
        return "--pitch" if "pitch" in point else "none"

    first = kind(points[0])
    for point in points[1:]:
        if kind(point) != first:
            raise PathError(
                f"give the same orientation option at every point (--from has {first}, "
                f"{point['option']} has {kind(point)})",
                point["option"],
            )


def _max_step(args: argparse.Namespace, units: JointUnits) -> float:
    """--max-step in SI: revolute [rad] when the arm has a revolute joint, else prismatic [m]."""
    revolute = [label == "rad" for label in units.si_labels]
    scale = units.scales[revolute.index(True)] if any(revolute) else units.scales[0]
    return float(args.max_step * scale)


def _per_joint(values: list[float], units: JointUnits, option: str) -> Any:
    """One value for every joint, or one per joint, in SI."""
    nq = len(units.joint_names)
    return units.to_si(values * nq if len(values) == 1 else values, option)


def _timing(
    args: argparse.Namespace, robot: Any, units: JointUnits, result: PathResult
) -> TimedPath:
    from ..path import table_limits, time_optimal

    vmax, amax = table_limits(robot.table)
    if args.vmax is not None:
        vmax = _per_joint(args.vmax, units, "--vmax")
    if args.amax is not None:
        amax = _per_joint(args.amax, units, "--amax")
    stops = [i for i in result.path.waypoint_indices if i < len(result.q)]
    return time_optimal(result.q, vmax, amax, dt=args.dt, stops=stops)


def _record(
    robot: str, units: JointUnits, result: PathResult, timed: TimedPath | None, dense: bool
) -> dict[str, Any]:
    """The JSON answer, SI."""
    record = {"robot": robot, **result.to_dict()}
    record["joint_names"] = list(units.joint_names)
    record["q_units"] = list(units.si_labels)
    joint = result.max_step_joint
    record["max_joint_step_unit"] = units.si_labels[joint] if joint >= 0 else None
    record["max_joint_step_joint"] = units.joint_names[joint] if joint >= 0 else None
    if timed is not None:
        record["duration_s"] = timed.duration
        record["t_s"] = timed.waypoint_times.tolist()
        record["qd"] = timed.waypoint_qd.tolist()
        record["qd_units"] = [f"{u}/s" for u in units.si_labels]
        if dense:
            record["trajectory"] = {
                "t_s": timed.t.tolist(),
                "q": timed.q.tolist(),
                "qd": timed.qd.tolist(),
            }
    return record
