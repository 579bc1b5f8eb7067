"""Print the tool pose (position and rotation) of a robot at a joint vector."""

from __future__ import annotations

import json
import sys

import numpy as np

from kin.cli import ArgumentParser, angle_scale, finite_float, length_scale, run_guarded
from kin.configuration import Configuration, limit_violations
from kin.robot_model import load_robot


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="fk.py", description=__doc__)
    parser.add_argument(
        "--robot", required=True, help="shipped robot name, or a DH table file (.toml)"
    )
    parser.add_argument("--q", type=finite_float, nargs="+", required=True, help="joint values")
    parser.add_argument(
        "--deg", action="store_true", help="revolute joint values in degrees (default radians)"
    )
    parser.add_argument(
        "--unit", choices=("m", "cm", "mm"), default="m", help="output length unit (default m)"
    )
    parser.add_argument("--frame", default="tool", help="frame to report (default: tool)")
    parser.add_argument("--json", action="store_true", help="print a JSON object")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print the pose; exit 0, or 2 with one line on stderr for bad input."""
    args = get_argument_parser().parse_args(argv)

    def body() -> int:
        robot = load_robot(args.robot)
        q = np.array(args.q, dtype=float)
        if args.deg:
            revolute = np.array([row.joint_type == "revolute" for row in robot.table.rows])
            if q.size == revolute.size:
                q = np.where(revolute, q * angle_scale(True), q)
        configuration = Configuration(robot, q)
        violations = limit_violations(robot, configuration.q)
        for violation in violations:
            print(f"fk.py: warning: {violation}", file=sys.stderr)
        pose = configuration.transform_frame_to_world(args.frame)
        position = pose.translation / length_scale(args.unit)
        rotation = pose.rotation
        if args.json:
            print(
                json.dumps(
                    {
                        "robot": robot.name,
                        "frame": args.frame,
                        "q": configuration.q.tolist(),
                        "within_limits": not violations,
                        "position": position.tolist(),
                        "rotation": rotation.tolist(),
                        "unit": args.unit,
                    }
                )
            )
            return 0
        print(f"{robot.name}: pose of '{args.frame}' in the world frame")
        print(f"position [{args.unit}]: " + "  ".join(f"{v:.6f}" for v in position))
        print("rotation:")
        for line in rotation:
            print("  " + "  ".join(f"{v:+.6f}" for v in line))
        return 0

    return run_guarded("fk.py", body)


if __name__ == "__main__":
    raise SystemExit(main())
