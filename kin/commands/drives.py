"""Stepper pulses of a joint vector (eq. 27 of paper 003), the angles reached, and the errors.

Needs a table with a [drives] section (steps, microstepping, gear and pulley ratio, home per
joint). --q: joint angles [rad, or deg with --deg] -> pulses counted from home, the angles the
pulses reach, the joint errors and the tool position error [--unit]. --pulses: the other way,
pulses -> angles reached and tool position. --json is SI (rad, m) with unit-named keys.
"""

from __future__ import annotations

import numpy as np

from dh2urdf.command_line import whole_number
from dh2urdf.output_text import shown_name

from ..cli import ArgumentParser, finite_float, length_scale, run_guarded
from .json_output import dumps
from .robot_argument import add_robot_arguments, load_robot_argument

PROG = "kin drives"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin drives``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add_robot_arguments(parser)
    given = parser.add_mutually_exclusive_group(required=True)
    given.add_argument(
        "--q", type=finite_float, nargs="+", help="joint angles, base to tip [rad, deg with --deg]"
    )
    given.add_argument(
        "--pulses",
        type=whole_number,
        nargs="+",
        help="pulses per joint counted from the drives' home",
    )
    parser.add_argument("--deg", action="store_true", help="angles in degrees (default radians)")
    parser.add_argument(
        "--unit", choices=("m", "cm", "mm"), default="m", help="length unit (default m)"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object, SI units")
    return parser


def _record(robot, result, drives) -> dict:  # noqa: ANN001
    return {
        "robot": robot.name,
        "joint_names": list(robot.table.joint_names),
        "pulses_per_revolution": [d.pulses_per_revolution for d in drives],
        "home_rad": [d.home for d in drives],
        "step_size_rad": result.step_size.tolist(),
        "q_asked_rad": result.q_asked[0].tolist(),
        "pulses": [int(p) for p in result.pulses[0]],
        "q_reached_rad": result.q_reached[0].tolist(),
        "joint_error_rad": result.joint_error[0].tolist(),
        "position_asked_m": result.p_world_tool_asked[0].tolist(),
        "position_reached_m": result.p_world_tool_reached[0].tolist(),
        "tool_position_error_m": result.tool_position_error[0].tolist(),
        "tool_position_error_norm_m": float(result.tool_position_error_norm[0]),
        "tool_rotation_error_rad": float(result.tool_rotation_error[0]),
    }


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Print pulses and errors; exit 0, or 2 with one line on stderr for bad input."""
    args = get_argument_parser(prog).parse_args(argv)

    def body() -> int:
        from ..drives import from_pulses, quantize, table_drives
        from .joint_units import JointUnits

        robot = load_robot_argument(args)
        drives = table_drives(robot.table)
        units = JointUnits.of(robot.name, robot.table, args.unit, args.deg)
        if args.q is not None:
            result = quantize(robot.table, units.to_si(args.q, "--q"))
        else:
            units.to_si(args.pulses, "--pulses")  # one value per joint, or a one-line error
            result = from_pulses(robot.table, args.pulses)
        if args.json:
            print(dumps(_record(robot, result, drives)))
            return 0
        scale = length_scale(args.unit)
        angle = units.labels[0]
        print(f"{robot.name}: stepper pulses from home (eqs. 27-28), angles in {angle}")
        header = f"{'joint':<12}{'pulses':>9}{'asked':>13}{'reached':>13}{'error':>11}{'step':>10}"
        print(header)
        shown = (units.from_si(result.q_asked[0]), units.from_si(result.q_reached[0]))
        error = units.from_si(result.joint_error[0])
        step = units.from_si(result.step_size)
        for j, name in enumerate(map(shown_name, units.joint_names)):
            print(
                f"{name:<12}{int(result.pulses[0, j]):>9d}{shown[0][j]:>13.6f}"
                f"{shown[1][j]:>13.6f}{error[j]:>11.2e}{step[j]:>10.6f}"
            )
        asked = result.p_world_tool_asked[0] / scale
        reached = result.p_world_tool_reached[0] / scale
        delta = result.tool_position_error[0] / scale
        print(f"tool asked   [{args.unit}]: " + "  ".join(f"{v:.6f}" for v in asked))
        print(f"tool reached [{args.unit}]: " + "  ".join(f"{v:.6f}" for v in reached))
        print(
            f"tool error   [{args.unit}]: "
            + "  ".join(f"{v:+.6f}" for v in delta)
            + f"  |e| {np.linalg.norm(delta):.6f}"
        )
        return 0

    return run_guarded(prog, body)
