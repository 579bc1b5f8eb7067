"""Plan a collision-free joint motion: from --start to --goal joints or to any IK target.

Joint values as in `kin fk`: revolute in radians (degrees with --deg), prismatic in --unit; a
target as in `kin ik` (--target X Y Z with --rpy, --quat, --mask or --axis; position only
without). Every collision-free IK answer of a target is a goal; --any-turn makes a --goal's
whole-turn copies within the limits goals too. The search is OMPL's (--planner),
bounded by --max-checks (the same --seed gives the same path on a busy machine) and capped by
--time-limit; every returned path is certified collision-free between its joint vectors by the
rule `kin path` prints, and checked once more whole. Collisions: the arm with itself, --scene
(a TOML cell, a URDF or a MoveIt PlanningScene) and --srdf, as in `kin check`. --time times the
path (toppra, the table's or URDF's velocity and acceleration limits). --json prints one object in
SI units; -o writes the path (CSV, or JSON that `kin preview --plan` animates).

--stdin plans one JSON request per input line ({"start": [...], "goal": [...]} or "target" with
"rpy", "quat", "mask", "axis", and "deg", "planner", "seed", "time_limit", "max_checks", "time",
"any_turn"; the command's options are the defaults) and answers each with one line, the object
--json prints plus "line", in order; a bad line gets {"line": n, "error": ...}. The robot and the
collision model are built once. --workers N plans on a local Dask cluster of N processes,
--scheduler ADDRESS on a running one: the answers still in input order, a bounded number of plans
in flight (a progress bar on a terminal's stderr).
Exit 0: a path (every line planned with --stdin); 1: no path (the status says why), or a line
without one; 2: bad input.
"""

from __future__ import annotations

import argparse
from typing import Any

from ..cli import (
    ArgumentParser,
    angle_scale,
    finite_float,
    length_scale,
    positive_float,
    positive_int,
    run_guarded,
)
from .collision_options import add_collision_options
from .json_output import dumps
from .named_states import joint_value
from .plan_answer import joints_within_limits, plan_checker, plan_record, timed_plan
from .plan_stream import add_stream_options, check_stream_options, run_stream
from .robot_argument import add_robot_arguments
from .targets import add_orientation_options

PROG = "kin plan"
#: Exit status when there is no path.
EXIT_NO_PATH = 1


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin plan``."""
    from ..plan import DEFAULT_CHECKS, DEFAULT_PLANNER, PLANNERS

    parser = ArgumentParser(prog=prog, description=__doc__)
    add = parser.add_argument
    add_robot_arguments(parser)
    joints = "revolute [rad, or deg with --deg], prismatic [--unit]"
    add(
        "--start",
        type=joint_value,
        nargs="+",
        help=f"start joints: {joints}, or a named state (ready: the table's or --srdf's)",
    )
    add("--goal", type=joint_value, nargs="+", help="goal joints, as --start (or a named state)")
    add(
        "--target",
        type=finite_float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="or a goal tool position in the world frame [--unit] (every IK answer a goal)",
    )
    add_orientation_options(parser)
    add("--deg", action="store_true", help="revolute joint values and angles in degrees")
    add(
        "--unit",
        choices=("m", "cm", "mm"),
        default="m",
        help="unit of every length, prismatic joint values included (default m)",
    )
    add(
        "--planner",
        choices=PLANNERS,
        default=DEFAULT_PLANNER,
        help="OMPL's planner (default %(default)s)",
    )
    add(
        "--time-limit",
        type=positive_float,
        default=10.0,
        help="wall-clock cap of the plan [s] (default 10): reached, the answer is 'timeout'",
    )
    add(
        "--max-checks",
        type=positive_int,
        default=DEFAULT_CHECKS,
        help=f"configurations checked before 'not_found' (default {DEFAULT_CHECKS})",
    )
    add("--seed", type=int, default=0, help="random seed of the search (default 0)")
    add(
        "--any-turn",
        action="store_true",
        help="a --goal's whole-turn copies within the limits are goals too (the same place of "
        "the arm; the path may end a turn away)",
    )
    add("--time", action="store_true", help="time the path (toppra, the joint limits)")
    add("-o", "--output", metavar="FILE", help="write the path: .csv or .json (SI units)")
    add("--json", action="store_true", help="print one JSON object, SI units")
    add_collision_options(
        parser,
        scene="the cell: a TOML of boxes, spheres..., a URDF or a MoveIt PlanningScene",
        srdf="a MoveIt SRDF: its disable_collisions pairs are allowed",
        self_check=True,
    )
    add_stream_options(parser)
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Plan and print; exit 0 with a path, 1 without, 2 with one line for bad input."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    if not 0 <= args.seed < 2**31:
        parser.error(f"--seed must be from 0 to 2147483647, got {args.seed}")
    check_stream_options(parser, args)
    if args.stdin:
        return run_guarded(prog, lambda: run_stream(args, prog))
    if args.start is None:
        parser.error("the following arguments are required: --start (or --stdin)")
    if (args.goal is None) == (args.target is None):
        parser.error("give the goal as --goal joints or as --target X Y Z (one of them)")
    if args.goal is not None and any(
        v is not None for v in (args.rpy, args.quat, args.mask, args.axis)
    ):
        parser.error("--rpy, --quat, --mask and --axis go with --target, not --goal")
    return run_guarded(prog, lambda: _run(args))


def _run(args: argparse.Namespace) -> int:
    output = None
    if args.output is not None:  # refused before any work
        from .output_file import checked_output, input_files

        inputs = input_files(args, "--robot", "--scene", "--srdf")
        output = checked_output(args.output, "-o", (".csv", ".json"), inputs)
    from ..plan import plan
    from .arm_route import arm_units
    from .robot_argument import load_robot_argument

    robot = load_robot_argument(args)
    units = arm_units(robot, args.unit, args.deg)
    length = length_scale(args.unit)
    start = joints_within_limits(robot, units, args.start, "--start", args.srdf)
    if args.goal is not None:
        goal: Any = joints_within_limits(robot, units, args.goal, "--goal", args.srdf)
    else:
        from .targets import build_target

        goal, _ = build_target(
            args.target,
            rpy=args.rpy,
            quat=args.quat,
            mask=args.mask,
            axis=args.axis,
            length=length,
            angle=angle_scale(args.deg),
        )
    checker = plan_checker(robot, args, length)
    result = plan(
        robot,
        start,
        goal,
        collisions=checker,
        planner=args.planner,
        time_limit=args.time_limit,
        max_checks=args.max_checks,
        seed=args.seed,
        any_turn=args.any_turn,
    )
    timed = timed_plan(robot, result) if args.time and result.success else None
    record = plan_record(robot, units, result, timed)
    if output is not None and result.success:
        _write(output, units, record)
    if args.json:
        print(dumps(record))
    else:
        _print_text(robot.name, units, length, args.unit, result, timed)
    return 0 if result.success else EXIT_NO_PATH


def _write(output: Any, units: Any, record: dict[str, Any]) -> None:
    """The path file: CSV (one row per joint vector, header with units) or the JSON answer."""
    if output.suffix.lower() == ".json":
        from .output_file import write_text_atomic

        write_text_atomic(output, dumps(record) + "\n")
        return
    from .path_output import write_joint_csv

    write_joint_csv(output, units, record["path"], record.get("t"), record.get("qd"))


def _print_text(robot: str, units: Any, length: float, unit: str, result: Any, timed: Any) -> None:
    from dh2urdf.output_text import shown_name

    print(f"{PROG}: {shown_name(robot)}, planner {result.planner}, seed {result.seed}")
    print(f"status: {result.status}: {result.message}")
    print(f"plan time: {result.plan_time:.3f} s, configurations checked: {result.checks}")
    if not result.success:
        return
    print(
        f"length in joint space [rad, m]: {result.length:.4f} (the straight line to the goal: "
        f"{result.straight_length:.4f}); goals offered: {len(result.goals)}"
    )
    if result.clearance is not None:
        print(f"smallest clearance at the joint vectors: {result.clearance / length:.4g} {unit}")
    if timed is not None:
        print(f"duration: {timed.duration:.3f} s (toppra, the joint limits)")
    labels = ", ".join(f"{n} [{u}]" for n, u in zip(units.joint_names, units.labels))
    print(f"joint vectors ({labels}):")
    for index, q in enumerate(result.path):
        values = " ".join(f"{v:.6g}" for v in units.from_si(q))
        print(f"  {index}: {values}")
