"""Calibrate a DH arm from measured positions or poses: the table of the arm you actually have.

Reads joint values and the tracker's measurements (CSV or JSON lines: joint names or q1..qn, then
x, y, z; full poses add qx, qy, qz, qw or roll, pitch, yaw; markers x1, y1, z1, x2, ...), estimates
the measurement frame, the tool or markers and every identifiable DH value (Levenberg-Marquardt,
parameters the data cannot separate named with what absorbs them), and writes the calibrated arm:
-o FILE.toml (a DH table) and/or -o FILE.urdf (root measurement_frame, last link measured_point).
With --plan-poses N: the N configurations to measure (D-optimal), as CSV on stdout. Lengths in
--unit (m), angles in radians unless --deg (docs/calibration.md).
"""

from __future__ import annotations

import argparse
import math
from functools import partial
from typing import TYPE_CHECKING

from dh2urdf.command_line import whole_number

from ..cli import ArgumentParser, positive_float, positive_int, run_guarded
from .json_output import dumps

if TYPE_CHECKING:
    from dh2urdf import DHTable

PROG = "dh2urdf calibrate"
OUTPUT_SUFFIXES = (".toml", ".urdf")


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``dh2urdf calibrate``."""
    parser = ArgumentParser(
        prog=prog, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "robot", metavar="ROBOT", help="DH table (.toml), shipped robot name, or a URDF"
    )
    parser.add_argument("--base", metavar="LINK", help="a URDF ROBOT: the chain's base link")
    parser.add_argument("--tip", metavar="LINK", help="a URDF ROBOT: the chain's tip link")
    task = parser.add_mutually_exclusive_group(required=True)
    task.add_argument(
        "--measurements", metavar="FILE", help="CSV or JSON lines of joint values and measurements"
    )
    task.add_argument(
        "--plan-poses", metavar="N", type=positive_int, help="propose N configurations to measure"
    )
    parser.add_argument(
        "-o",
        "--output",
        action="append",
        default=[],
        metavar="FILE",
        help="write the calibrated arm: .toml and/or .urdf (repeatable)",
    )
    parser.add_argument(
        "--unit", choices=("m", "cm", "mm"), default="m", help="length unit of the file (m)"
    )
    parser.add_argument(
        "--deg", action="store_true", help="joint angles and roll-pitch-yaw in degrees"
    )
    parser.add_argument(
        "--loss",
        choices=("linear", "soft_l1", "huber", "cauchy"),
        default="linear",
        help="linear: Levenberg-Marquardt; else a robust loss against outliers",
    )
    parser.add_argument(
        "--folds",
        type=whole_number,
        default=5,
        help="k of the k-fold cross-validation, 0 for none (5)",
    )
    parser.add_argument(
        "--position-noise",
        type=positive_float,
        default=0.05,
        help="[mm] per coordinate, weights positions (0.05)",
    )
    parser.add_argument(
        "--rotation-noise",
        type=positive_float,
        default=0.01,
        help="[deg] per axis, weights rotations (0.01)",
    )
    parser.add_argument(
        "--rank-tol",
        type=positive_float,
        default=1e-3,
        help="relative rank tolerance of identifiability (1e-3)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    parser.add_argument(
        "--plot", metavar="FILE.png", help="residuals before/after per measurement (matplotlib)"
    )
    parser.add_argument(
        "--poses", action="store_true", help="--plan-poses: plan for full-pose measurements"
    )
    parser.add_argument(
        "--scene", metavar="FILE", help="--plan-poses: only configurations free of this cell"
    )
    parser.add_argument(
        "--seed", type=whole_number, default=0, help="--plan-poses: candidate seed (0)"
    )
    return parser


def _check(parser: ArgumentParser, args: argparse.Namespace) -> None:
    if args.plan_poses is not None:
        for option in ("output", "plot"):
            if getattr(args, option):
                parser.error(f"--{option} goes with --measurements, not --plan-poses")
    else:
        for option in ("scene", "poses"):
            if getattr(args, option):
                parser.error(f"--{option} goes with --plan-poses")
    if (args.base or args.tip) and not args.robot.endswith((".urdf", ".xacro")):
        parser.error("--base and --tip go with a URDF ROBOT (a .urdf or .xacro file)")
    if args.rank_tol >= 1.0:
        parser.error(f"--rank-tol: expected a relative tolerance below 1, got {args.rank_tol:g}")
    if args.folds == 1 or args.folds < 0:
        parser.error(f"--folds: expected 0 or at least 2, got {args.folds}")


def _plan(args: argparse.Namespace, table: DHTable) -> int:
    """Print ``--plan-poses`` configurations as CSV (``#`` lines say how they were chosen)."""
    from ..calibration.pose_plan import plan_poses

    collides = None
    if args.scene:
        from ..collision import CollisionChecker, load_collision_model
        from ..robot_model import robot_from_table

        checker = CollisionChecker(load_collision_model(robot_from_table(table), scene=args.scene))
        collides = partial(checker.in_collision_batch, threads=1)
    plan = plan_poses(table, args.plan_poses, poses=args.poses, seed=args.seed, collides=collides)
    scale = 180.0 / math.pi if args.deg else 1.0
    unit = "deg" if args.deg else "rad"
    print(
        f"# {len(plan.q)} configurations of {table.name} to measure ({unit}), D-optimal over "
        f"{plan.candidates} candidates within the limits"
        + (f", {plan.rejected} colliding left out" if args.scene else "")
    )
    print(
        f"# {len(plan.identifiable)} identifiable parameters, condition number {plan.condition_number:.1f}; "
        "measure and add the columns " + ("x,y,z,qx,qy,qz,qw" if args.poses else "x,y,z")
    )
    if len(plan.q) < plan.needed:
        print(
            f"# fewer than the {plan.needed} rows that determine them: plan at least {3 * plan.needed}"
        )
    print(",".join(table.joint_names))
    for q in plan.q:
        print(
            ",".join(
                f"{v * (scale if row.joint_type == 'revolute' else 1.0):.6f}"
                for v, row in zip(q, table.rows)
            )
        )
    return 0


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Run the calibration; exit 0, or 2 with one line on stderr for bad input."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    _check(parser, args)

    def body() -> int:
        from dh2urdf.output_file import checked_output, write_text_atomic

        from ..audit.audited_table import load_audited_table
        from ..calibration.calibration import calibrate
        from ..calibration.fit import Noise
        from ..calibration.outputs import calibrated_table, calibrated_urdf
        from ..calibration.report import calibration_json, calibration_text

        table = load_audited_table(args.robot, args.base, args.tip).table
        if args.plan_poses is not None:
            return _plan(args, table)
        inputs = [("--measurements", args.measurements)]
        for path in args.output:
            checked_output(path, "-o", OUTPUT_SUFFIXES, inputs)
        if args.plot:
            checked_output(args.plot, "--plot", (".png",), inputs)
        noise = Noise(args.position_noise * 1e-3, math.radians(args.rotation_noise))
        found = calibrate(
            table,
            args.measurements,
            unit=args.unit,
            degrees=args.deg,
            noise=noise,
            loss=args.loss,
            folds=args.folds,
            tolerance=args.rank_tol,
        )
        texts = []
        for path in args.output:  # every text first: nothing is written when one fails
            if path.lower().endswith(".toml"):
                from dh2urdf.table_writer import table_text

                header = f"Calibrated by dh2urdf calibrate from {args.measurements}; world = the measurement frame."
                texts.append((path, table_text(calibrated_table(found), header)))
            else:
                texts.append((path, calibrated_urdf(found)))
        print(dumps(calibration_json(found)) if args.json else calibration_text(found))
        if args.plot:
            from ..calibration.plot import plot_residuals

            plot_residuals(found, args.plot)
        for path, text in texts:
            write_text_atomic(path, text)
            if not args.json:
                print(f"wrote {path}")
        return 0

    return run_guarded(prog, body)
