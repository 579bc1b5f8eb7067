"""Plan a collision-free joint motion: from --start to --goal joints or to any IK target.

Joint values as in `kin fk`: revolute in radians (degrees with --deg), prismatic in --unit; a
target as in `kin ik` (--target X Y Z with --rpy, --quat, --mask or --axis; position only
without). Every collision-free IK answer of a target is a goal. The search is OMPL's (--planner),
bounded by --max-checks (the same --seed gives the same path on a busy machine) and capped by
--time-limit; every returned path is certified collision-free between its joint vectors by the
rule `kin path` prints, and checked once more whole. Collisions: the arm with itself, --scene
(a TOML cell, a URDF or a MoveIt PlanningScene) and --srdf, as in `kin check`. --time times the
path (toppra, the table's or URDF's velocity and acceleration limits). --json prints one object in
SI units; -o writes the path (CSV, or JSON that `kin preview --path` animates).
Exit 0: a path; 1: no path (the status says why); 2: bad input.
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
from .collision_options import add_collision_options, collision_checker
from .json_output import dumps
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
    add("--start", type=finite_float, nargs="+", required=True, help=f"start joints: {joints}")
    add("--goal", type=finite_float, nargs="+", help=f"goal joints: {joints}")
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
    add("--time", action="store_true", help="time the path (toppra, the joint limits)")
    add("-o", "--output", metavar="FILE", help="write the path: .csv or .json (SI units)")
    add("--json", action="store_true", help="print one JSON object, SI units")
    add_collision_options(
        parser,
        scene="the cell: a TOML of boxes, spheres..., a URDF or a MoveIt PlanningScene",
        srdf="a MoveIt SRDF: its disable_collisions pairs are allowed",
        self_check=True,
    )
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Plan and print; exit 0 with a path, 1 without, 2 with one line for bad input."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    if (args.goal is None) == (args.target is None):
        parser.error("give the goal as --goal joints or as --target X Y Z (one of them)")
    if args.goal is not None and any(
        v is not None for v in (args.rpy, args.quat, args.mask, args.axis)
    ):
        parser.error("--rpy, --quat, --mask and --axis go with --target, not --goal")
    if not 0 <= args.seed < 2**31:
        parser.error(f"--seed must be from 0 to 2147483647, got {args.seed}")
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
    start = units.to_si(args.start, "--start")
    if args.goal is not None:
        goal: Any = units.to_si(args.goal, "--goal")
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
    checker = collision_checker(args, robot, length)  # None: plan() checks the arm alone
    result = plan(
        robot,
        start,
        goal,
        collisions=checker,
        planner=args.planner,
        time_limit=args.time_limit,
        max_checks=args.max_checks,
        seed=args.seed,
    )
    timed = _timed(robot, result) if args.time and result.success else None
    record = _record(robot, units, result, timed)
    if output is not None and result.success:
        _write(output, units, record)
    if args.json:
        print(dumps(record))
    else:
        _print_text(robot.name, units, length, args.unit, result, timed)
    return 0 if result.success else EXIT_NO_PATH


def _timed(robot: Any, result: Any) -> Any:
    from ..path import table_limits, time_optimal

    vmax, amax = table_limits(robot.table)
    return time_optimal(result.path, vmax, amax)


def _record(robot: Any, units: Any, result: Any, timed: Any) -> dict[str, Any]:
    """The JSON answer, SI."""
    record: dict[str, Any] = {
        "robot": robot.name,
        "status": result.status,
        "message": result.message,
        "planner": result.planner,
        "seed": result.seed,
        "plan_time": result.plan_time,
        "checks": result.checks,
        "joint_names": list(units.joint_names),
        "q_units": list(units.si_labels),
        "length": result.length,
        "straight_length": result.straight_length,
        "clearance_m": result.clearance,
        "goal_index": result.goal_index,
        "goals": result.goals.tolist(),
        "path": result.path.tolist(),
        "q": result.path.tolist(),
    }
    if timed is not None:
        record["duration_s"] = timed.duration
        record["t"] = timed.waypoint_times.tolist()
        record["t_s"] = record["t"]
        record["qd"] = timed.waypoint_qd.tolist()
        record["qd_units"] = [f"{u}/s" for u in units.si_labels]
    return record


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
