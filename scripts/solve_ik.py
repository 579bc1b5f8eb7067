"""Solve the inverse kinematics of a robot for a tool target and print the solutions.

The solver is chosen per robot (ik.get_solver): closed form for the small arms. Targets:
position only (planar2, pickplace3); for the five-joint arms (ned5, lab5, scorbot) a full pose
(--rpy, URDF roll-pitch-yaw: R = Rz(yaw) Ry(pitch) Rx(roll)) or a position with --pitch, the
angle of the tool's approach axis BELOW the horizontal, in the vertical plane through the base
axis and the target, measured from the direction pointing away from the base axis (0 = straight
out, 90 deg = straight down; for lab5 with the shoulder in front, pitch = 90 deg - (q2+q3+q4)),
with --roll the wrist-roll joint value q5 (default: the seed's). Robots without a closed form
(humanoid7) use the numeric solver (--solver mink: seed table, damped Newton, mink QP, inside the
limits, within --timeout); --solver nr is the paper's Newton-Raphson (position only, no limits).
Exit 0 when a valid solution exists, 1 when none (success false), 2 for bad input.
"""

from __future__ import annotations

import json

import numpy as np

from kin.cli import (
    ArgumentParser,
    angle_scale,
    finite_float,
    length_scale,
    positive_float,
    run_guarded,
)
from kin.ik import PitchTarget, PoseTarget, PositionTarget, get_solver
from kin.ik.exceptions import IKError
from kin.ik.numeric.newton_raphson import newton_raphson
from kin.ik.numeric.solver import NumericIK
from kin.robot_model import load_robot

EXIT_NO_SOLUTION = 1


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="solve_ik.py", description=__doc__)
    parser.add_argument(
        "--robot", required=True, help="shipped robot name, or a DH table file (.toml)"
    )
    parser.add_argument(
        "--target",
        type=finite_float,
        nargs=3,
        required=True,
        metavar=("X", "Y", "Z"),
        help="tool position in the world frame, in --unit",
    )
    parser.add_argument(
        "--pitch", type=finite_float, help="approach angle below the horizontal (five-joint arms)"
    )
    parser.add_argument(
        "--roll", type=finite_float, help="wrist-roll joint value q5 with --pitch (default: seed's)"
    )
    parser.add_argument(
        "--rpy",
        type=finite_float,
        nargs=3,
        metavar=("R", "P", "Y"),
        help="tool orientation, URDF roll-pitch-yaw (five-joint arms)",
    )
    parser.add_argument(
        "--unit", choices=("m", "cm", "mm"), default="m", help="length unit (default m)"
    )
    parser.add_argument(
        "--deg", action="store_true", help="angles in and out in degrees (default radians)"
    )
    parser.add_argument(
        "--seed-q", type=finite_float, nargs="+", help="current joint vector (default zeros)"
    )
    parser.add_argument(
        "--all", action="store_true", help="print every solution, also those outside the limits"
    )
    parser.add_argument(
        "--json",
        action="store_true",
        help="print a JSON object (q in radians, errors in m and rad)",
    )
    parser.add_argument(
        "--quat",
        type=finite_float,
        nargs=4,
        metavar=("W", "X", "Y", "Z"),
        help="tool orientation as a unit quaternion (numeric solver)",
    )
    parser.add_argument("--position-only", action="store_true", help="ignore the tool orientation")
    parser.add_argument(
        "--solver",
        choices=("mink", "nr"),
        help="numeric solver: mink (default for humanoid7) or nr (the paper's Newton-Raphson)",
    )
    parser.add_argument(
        "--timeout",
        type=positive_float,
        default=50.0,
        help="numeric solver time budget [ms] (default 50)",
    )
    return parser


def _target(args, angle: float, length: float):  # noqa: ANN001, ANN202
    position = np.array(args.target) * length
    if args.position_only and (
        args.rpy is not None or args.quat is not None or args.pitch is not None
    ):
        raise IKError("--position-only excludes --rpy, --quat and --pitch")
    if args.quat is not None:
        if args.rpy is not None or args.pitch is not None:
            raise IKError("give one of --quat, --rpy, --pitch")
        w, x, y, z = args.quat
        norm = float(np.linalg.norm(args.quat))
        if norm < 1e-9:
            raise IKError(f"--quat must not be zero, got {args.quat}")
        w, x, y, z = w / norm, x / norm, y / norm, z / norm
        rotation = [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
        return PoseTarget(position, rotation)
    if args.rpy is not None and args.pitch is not None:
        raise IKError("give either --rpy or --pitch, not both")
    if args.rpy is not None:
        return PoseTarget.from_rpy(position, np.array(args.rpy) * angle)
    if args.pitch is not None:
        return PitchTarget(
            position, args.pitch * angle, None if args.roll is None else args.roll * angle
        )
    if args.roll is not None:
        raise IKError("--roll needs --pitch")
    return PositionTarget(position)


def main(argv: list[str] | None = None) -> int:
    """Print the solutions; exit 0, 1 (no valid solution) or 2 (bad input)."""
    args = get_argument_parser().parse_args(argv)

    def body() -> int:
        robot = load_robot(args.robot)
        solver = (
            NumericIK(robot)
            if args.solver == "mink"
            else None
            if args.solver == "nr"
            else get_solver(robot)
        )
        angle, length = angle_scale(args.deg), length_scale(args.unit)
        target = _target(args, angle, length)
        seed = None
        if args.seed_q is not None:
            if len(args.seed_q) != robot.nq:
                raise IKError(
                    f"--seed-q needs {robot.nq} values for '{robot.name}', got {len(args.seed_q)}"
                )
            seed = np.array(args.seed_q) * angle
        if args.solver == "nr":
            if not isinstance(target, PositionTarget):
                raise IKError(
                    "--solver nr is the paper's position-only method: drop --rpy/--quat/--pitch"
                )
            result = newton_raphson(robot, target.position, seed)
        elif isinstance(solver, NumericIK):
            result = solver.solve(target, seed, timeout=args.timeout / 1e3)
        else:
            result = solver.solve(target, seed)
        shown = list(result.solutions) + (list(result.rejected) if args.all else [])
        if not args.all:
            shown = shown[:1]
        numeric = result.solver in ("mink", "nr")
        if numeric and not shown:
            shown = list(result.rejected[:1])  # the best configuration found, and its error
        if args.json:
            out = result.to_dict()
            out["unit"] = args.unit
            print(json.dumps(out))
            return 0 if result.success else EXIT_NO_SOLUTION
        angle_unit = "deg" if args.deg else "rad"
        print(f"{robot.name} ({result.solver}): {result.status}: {result.message}")
        if result.distance_to_workspace is not None:
            print(
                f"distance to the workspace: {result.distance_to_workspace / length:.6g} {args.unit}"
            )
        if numeric:
            print(f"iterations: {result.iterations}, time: {result.time * 1e3:.3f} ms")
        if shown:
            names = "  ".join(f"{n:>10}" for n in robot.joint_names)
            print(f"{'branch':<34} {names}  limits  pos.err [{args.unit}]  rot.err [rad]")
            for solution in shown:
                values = "  ".join(f"{v / angle:>10.4f}" for v in solution.q)
                print(
                    f"{solution.branch:<34} {values}  {'ok' if solution.within_limits else 'OUT':>6}  "
                    f"{solution.position_error / length:.3g}  {solution.rotation_error:.3g}"
                )
            print(f"joint values in {angle_unit}")
        return 0 if result.success else EXIT_NO_SOLUTION

    return run_guarded("solve_ik.py", body, extra=(IKError,))


if __name__ == "__main__":
    raise SystemExit(main())
