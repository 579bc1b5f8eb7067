"""Check a joint vector for collisions: the arm with itself and with a scene.

Joint values as in `kin fk`: revolute in radians (degrees with --deg), prismatic in --unit, like
every printed length. Shapes: a URDF's <collision> elements of every link, the chain's and those
off it (fingers, flange: their joints held at --hold values, else the SRDF's group state or 0, said
in one line; meshes as their convex hulls), or a DH table's link cylinders; --scene adds a cell (TOML with [[box]], [[sphere]],
[[cylinder]], [[mesh]], or a URDF); --srdf allows the pairs of its <disable_collisions>; adjacent
links are always allowed. Prints the verdict, every pair in contact (depth and witness points)
and the closest pair. --json is SI. Exit 0: free; 1: in collision; 2: bad input.
"""

from __future__ import annotations

from dh2urdf.link_volumes import default_radius_note
from dh2urdf.output_text import counted, shown_name

from ..cli import ArgumentParser, finite_float, length_scale, run_guarded
from .collision_options import add_collision_options, held_joints
from .json_output import dumps
from .robot_argument import add_robot_arguments

PROG = "kin check"

#: Exit status of a configuration in collision.
EXIT_IN_COLLISION = 1


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin check``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add_robot_arguments(parser)
    parser.add_argument(
        "--q",
        type=finite_float,
        nargs="+",
        required=True,
        help="joint values, base to tip: revolute [rad, or deg with --deg], prismatic [--unit]",
    )
    parser.add_argument(
        "--deg", action="store_true", help="revolute joint values in degrees (default radians)"
    )
    parser.add_argument(
        "--unit",
        choices=("m", "cm", "mm"),
        default="m",
        help="length unit of prismatic joint values and of the printed lengths (default m)",
    )
    add_collision_options(
        parser,
        scene="the cell: a TOML of boxes, spheres... or a URDF",
        srdf="a MoveIt SRDF: its disable_collisions pairs are allowed",
        self_check=True,
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object, SI units")
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Print the verdict; exit 0 free, 1 in collision, 2 with one line on stderr for bad input."""
    args = get_argument_parser(prog).parse_args(argv)

    def body() -> int:
        from ..collision import CollisionChecker, load_collision_model
        from .arm_route import arm_units
        from .robot_argument import load_robot_argument

        robot = load_robot_argument(args)
        units = arm_units(robot, args.unit, args.deg)
        q = units.to_si(args.q, "--q")
        scale = length_scale(args.unit)
        model = load_collision_model(
            robot,
            srdf=args.srdf,
            scene=args.scene,
            padding=args.padding * scale,
            hold=held_joints(args),
        )
        checker = CollisionChecker(model)
        contacts = checker.collisions(q)
        closest = checker.distance(q) if model.pairs else None
        if args.json:
            record = {
                "robot": robot.name,
                "joint_names": list(units.joint_names),
                "q": q.tolist(),
                "q_units": list(units.si_labels),
                "in_collision": bool(contacts),
                "contacts": [
                    {
                        "a": c.a,
                        "b": c.b,
                        "depth_m": c.depth,
                        "point_a_m": c.point_a.tolist(),
                        "point_b_m": c.point_b.tolist(),
                    }
                    for c in contacts
                ],
                "closest": None
                if closest is None
                else {
                    "a": closest.a,
                    "b": closest.b,
                    "distance_m": closest.distance,
                    "point_a_m": closest.point_a.tolist(),
                    "point_b_m": closest.point_b.tolist(),
                },
                "pairs_checked": len(model.pairs),
                "pairs_allowed": len(model.disabled),
                "shapes": model.shape_note,
                "held_joints": model.held.values,
            }
            print(dumps(record))
            return EXIT_IN_COLLISION if contacts else 0
        unit = args.unit

        def point(values: object) -> str:
            return " ".join(f"{v / scale:.4f}" for v in values)  # type: ignore[attr-defined]

        verdict = "IN COLLISION" if contacts else "collision-free"
        print(f"{shown_name(robot.name)}: {verdict}")
        attached = f", {counted(len(model.attached), 'attached object')}" if model.attached else ""
        print(
            f"pairs checked: {len(model.pairs)} ({counted(len(model.links), 'link')} with "
            f"shapes, {counted(len(model.scene_objects), 'scene object')}{attached}; "
            f"{counted(len(model.disabled), 'pair')} allowed)"
        )
        print(f"shapes: {model.shape_note}")
        note = default_radius_note(robot.table) if robot.urdf_source is None else None
        if note:  # a DH table's 1 cm sticks
            print(note)
        if model.held.note:
            print(f"joints off the chain held at: {model.held.note}")
        for c in contacts:
            kind = "scene" if c.b in model.scene_objects else "self"
            print(
                f"contact ({kind}): {shown_name(c.a)} / {shown_name(c.b)}  depth "
                f"{c.depth / scale:.4f} {unit}  points [{unit}] ({point(c.point_a)}) "
                f"({point(c.point_b)})"
            )
        if closest is not None:
            print(
                f"closest: {shown_name(closest.a)} / {shown_name(closest.b)}  distance "
                f"{closest.distance / scale:.4f} {unit}  points [{unit}] "
                f"({point(closest.point_a)}) ({point(closest.point_b)})"
            )
        return EXIT_IN_COLLISION if contacts else 0

    return run_guarded(prog, body)
