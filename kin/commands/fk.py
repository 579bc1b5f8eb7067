"""Print the pose (position and rotation) of a robot frame at a joint vector.

Joint values: revolute in radians (degrees with --deg), prismatic in --unit, like every length.
The text output names the unit of each number; --json is SI (q in rad / m, as "q_units" says;
"position_m" in meters). The orientation is printed three ways: the rotation matrix, URDF
roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll), in rad or deg with --deg: JSON "rpy" in the unit
"rpy_unit" names) and the unit quaternion W X Y Z (JSON "quat_wxyz", W >= 0): the same forms
`kin ik --rpy` and `kin ik --quat` take, so one command's output pastes into the other.

A URDF chain with mimic joints in series: --q holds the independent joints only (the names
printed); each mimic joint follows its leader (the "mimic" line, JSON "mimic"), and the pose is
Pinocchio's of the original URDF with mimic joints.
"""

from __future__ import annotations

import functools
import sys

from dh2urdf.output_text import shown_name

from ..cli import ArgumentParser, angle_scale, finite_float, length_scale, run_guarded
from .arm_route import MIMIC_HELP
from .json_output import dumps
from .robot_argument import add_robot_arguments

PROG = "kin fk"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin fk``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add_robot_arguments(parser)
    parser.add_argument(
        "--q",
        type=finite_float,
        nargs="+",
        required=True,
        help="joint values, base to tip: revolute [rad, or deg with --deg], prismatic [--unit]; "
        f"{MIMIC_HELP}",
    )
    parser.add_argument(
        "--deg", action="store_true", help="revolute joint values in degrees (default radians)"
    )
    parser.add_argument(
        "--unit",
        choices=("m", "cm", "mm"),
        default="m",
        help="length unit of prismatic joint values and of the printed position (default m)",
    )
    parser.add_argument("--frame", default="tool", help="frame to report (default: tool)")
    parser.add_argument("--json", action="store_true", help="print one JSON object, SI units")
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Print the pose; exit 0, or 2 with one line on stderr for bad input."""
    args = get_argument_parser(prog).parse_args(argv)

    def body() -> int:
        import pinocchio as pin

        from ..configuration import Configuration, limit_violations
        from ..robot_model import RobotModel
        from .arm_route import arm_units, load_arm_argument, mimic_line, mimic_records
        from .joint_units import limits_line

        robot = load_arm_argument(args)
        units = arm_units(robot, args.unit, args.deg)
        q_si = units.to_si(args.q, "--q", warn_units=False)
        if isinstance(robot, RobotModel):
            configuration = Configuration(robot, q_si)
            q = configuration.q
            violations = limit_violations(robot, q)
            pose_of = configuration.transform_frame_to_world
        else:  # a URDF chain with mimic joints: q holds the independent joints
            q = q_si
            violations = robot.limit_violations(q)
            pose_of = functools.partial(robot.frame_pose, q)
        warning = limits_line(violations, units.unit_slip(args.q, "--q"))
        if warning is not None:  # a unit slip and the joints outside their limits: one line
            print(f"{prog}: warning: {warning}", file=sys.stderr)
        pose = pose_of(args.frame)
        angle = angle_scale(args.deg)
        rpy = [v / angle for v in pin.rpy.matrixToRpy(pose.rotation).tolist()]
        x, y, z, w = pin.Quaternion(pose.rotation).coeffs().tolist()
        sign = -1.0 if w < 0.0 else 1.0  # q and -q are one rotation: W >= 0
        quat = [sign * w, sign * x, sign * y, sign * z]
        rpy_unit = "deg" if args.deg else "rad"
        if args.json:
            record = {
                "robot": robot.name,
                "frame": args.frame,
                "joint_names": list(units.joint_names),
                "q": q.tolist(),
                "q_units": list(units.si_labels),
                "within_limits": not violations,
                "position_m": pose.translation.tolist(),
                "rotation": pose.rotation.tolist(),
                "rpy": rpy,
                "rpy_unit": rpy_unit,
                "quat_wxyz": quat,
            }
            mimic = mimic_records(robot)
            if mimic:
                record["mimic"] = mimic
            print(dumps(record))
            return 0
        position = pose.translation / length_scale(args.unit)
        q_shown = units.from_si(q)
        print(f"{robot.name}: pose of '{args.frame}' in the world frame")
        names = map(shown_name, units.joint_names)
        shown = (f"{n} {v:.6g} {u}" for n, v, u in zip(names, q_shown, units.labels))
        print("q: " + ", ".join(shown))
        note = mimic_line(robot)
        if note is not None:
            print(note)
        print(f"position [{args.unit}]: " + "  ".join(f"{v:.6f}" for v in position))
        print("rotation (columns: frame axes in world axes):")
        for line in pose.rotation:
            print("  " + "  ".join(f"{v:+.6f}" for v in line))
        print(
            f"rpy [{rpy_unit}] (URDF roll pitch yaw, as kin ik --rpy): "
            + "  ".join(f"{v:.9g}" for v in rpy)
        )
        print("quat (W X Y Z, as kin ik --quat): " + "  ".join(f"{v:.12f}" for v in quat))
        return 0

    return run_guarded(prog, body)
