"""Reachability (capability) map: per voxel, the fraction of K tool orientations the arm reaches.

For each voxel of the cube around the base that holds the arm's maximum reach, K tool
orientations spread evenly over SO(3) (a super-Fibonacci spiral: deterministic, the same K gives
the same rotations) are solved by batch IK at the voxel's centre; the index is the fraction with
a verified answer inside the joint limits. Voxels beyond the maximum reach get 0 unsolved.
--scheduler ADDRESS (or local-cluster:N) runs the chunks on a Dask cluster: same map.
--scene FILE (a TOML cell or a URDF) and/or --srdf FILE [--padding] count collision-free answers
only (kin check's shapes and pairs): every valid branch of a closed form is checked, an
orientation counts when one is free (arms without a vectorized closed form: the one answer found).
The map's "collisions" field, the summary and the picture's title say so.

-o writes the map (.npz: voxel_m, centers_m (n, n, n, 3), index (n, n, n), orientations,
rotations, time_s; SI units) through a temporary file and a rename; --png draws horizontal
slices. --json prints the same as one JSON object (SI units). A progress bar on stderr (on a
terminal, unless --quiet); Ctrl-C stops with one line and exit 130, leaving no file.
"""

from __future__ import annotations

from dh2urdf.output_text import counted, shown_name

from ..cli import (
    ArgumentParser,
    length_scale,
    positive_float,
    positive_int,
    run_guarded,
)
from ..exceptions import KinError
from .collision_options import add_collision_options, check_padding, held_joints
from .json_output import dumps
from .robot_argument import add_robot_arguments, load_robot_argument

PROG = "kin reach"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin reach``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add_robot_arguments(parser)
    parser.add_argument(
        "--voxel", type=positive_float, default=0.05, help="voxel edge in --unit (default 0.05 m)"
    )
    parser.add_argument(
        "--orientations",
        type=positive_int,
        default=64,
        metavar="K",
        help="tool orientations per voxel (default 64)",
    )
    parser.add_argument(
        "--scheduler",
        default="local",
        metavar="local|ADDRESS",
        help="local (this process, default), a Dask scheduler address, or local-cluster:N",
    )
    add_collision_options(
        parser,
        scene="count collision-free answers: a TOML cell or a URDF",
        srdf="count collision-free answers; the SRDF's pairs allowed",
    )
    parser.add_argument("-o", "--output", required=True, metavar="FILE.npz", help="the map")
    parser.add_argument("--png", metavar="FILE", help="draw horizontal slices (.png, .svg, .pdf)")
    parser.add_argument("--json", action="store_true", help="print the map as JSON, SI units")
    parser.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    parser.add_argument(
        "--unit", choices=("m", "cm", "mm"), default="m", help="length unit (default m)"
    )
    parser.add_argument(
        "--timeout",
        type=positive_float,
        help="arms without a closed form: time cap of a numeric solve [ms] (default 2000); "
        "its work bound is 16 starts",
    )
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Compute and write the map; exit 0, 2 for bad input, 130 on Ctrl-C."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    check_padding(parser, args)

    def body() -> int:
        from ..ik.reach import arm_reach
        from ..reach.map import (
            MAX_VOXELS_PER_SIDE,
            plot_reach_map,
            reachability_map,
            save_reach_map,
            smallest_voxel,
        )
        from .output_file import FIGURE_SUFFIXES, checked_output, input_files
        from .progress import ProgressBar

        inputs = input_files(args, "--robot", "--scene", "--srdf")  # never written over
        output = checked_output(args.output, "-o", (".npz",), inputs)  # before minutes of solving
        if args.png:
            checked_output(args.png, "--png", FIGURE_SUFFIXES, [*inputs, ("-o", args.output)])
        robot = load_robot_argument(args)
        scale = length_scale(args.unit)
        reach = arm_reach(robot).maximum
        if args.voxel * scale < smallest_voxel(reach):  # said in the user's unit
            raise KinError(
                f"--voxel {args.voxel:g} {args.unit} needs more than {MAX_VOXELS_PER_SIDE} voxels "
                f"per side for a reach of {reach / scale:.4g} {args.unit}: give --voxel "
                f"{smallest_voxel(reach) / scale:.3g} or more"
            )
        with ProgressBar(prog, "poses", quiet=args.quiet) as progress:
            reach_map = reachability_map(
                robot,
                args.voxel * scale,
                args.orientations,
                scheduler=args.scheduler,
                progress=progress,
                timeout=None if args.timeout is None else args.timeout / 1e3,
                scene=args.scene,
                srdf=args.srdf,
                padding=0.0 if args.padding is None else args.padding * scale,
                hold=held_joints(args),
            )
        save_reach_map(reach_map, output)
        if args.png:
            plot_reach_map(reach_map, args.png, args.unit)
        if args.json:
            print(dumps(reach_map.to_dict()))
        else:
            solved = int((reach_map.index > 0).sum())
            print(
                f"{shown_name(reach_map.robot)}: {counted(reach_map.index.size, 'voxel')} of "
                f"{args.voxel:g} {args.unit}, {solved:,} with an index above 0, "
                f"best {reach_map.index.max():.3g}; {counted(reach_map.orientations, 'orientation')}; "
                f"{reach_map.time_s:.3g} s; wrote {output}"
                + (f" and {args.png}" if args.png else "")
            )
            if reach_map.collisions:
                print(f"counted: {reach_map.collisions}")
        return 0

    return run_guarded(prog, body)
