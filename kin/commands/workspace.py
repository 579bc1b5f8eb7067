"""Monte Carlo workspace of a robot: reach, bounding box, volume, and a PNG of the views.

Joint vectors are drawn uniformly within the limits (seeded; the same --seed and --n give the
same numbers with any --workers or --scheduler), tool points by batched FK. Lengths are printed
in --unit; --json is SI with unit-named keys (max_radius_m, volume_m3, ...). A progress bar on
stderr (on a terminal, unless --quiet); Ctrl-C stops with one line and exit 130, leaving no
half-written PNG.
"""

from __future__ import annotations

from dh2urdf.command_line import whole_number
from dh2urdf.output_text import counted, shown_name

from ..cli import ArgumentParser, length_scale, positive_float, positive_int, run_guarded
from .json_output import dumps
from .robot_argument import add_robot_arguments, load_robot_argument

PROG = "kin workspace"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin workspace``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add_robot_arguments(parser)
    parser.add_argument(
        "--n", type=positive_int, default=1_000_000, help="joint vectors (default 1000000)"
    )
    parser.add_argument("--seed", type=whole_number, default=0, help="random seed (default 0)")
    parser.add_argument(
        "-o", "--output", help="write the views to this file (.png, .svg or .pdf, by its suffix)"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object, SI units")
    parser.add_argument(
        "--workers", type=positive_int, default=1, help="processes for the chunks (default 1)"
    )
    parser.add_argument(
        "--scheduler", metavar="ADDRESS", help="run the chunks on this Dask scheduler (needs dask)"
    )
    parser.add_argument(
        "--unit", choices=("m", "cm", "mm"), default="m", help="length unit (default m)"
    )
    parser.add_argument(
        "--voxel", type=positive_float, help="voxel edge in --unit (default reach bound / 50)"
    )
    parser.add_argument(
        "--chunk-size", type=positive_int, default=100_000, help="joint vectors per chunk"
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar on stderr")
    return parser


#: A run estimated to take longer than this says so on stderr after its first chunk [s].
LONG_RUN_S = 60.0


def _duration_text(seconds: float) -> str:
    """``seconds`` [s] in minutes, hours, days or years (the largest that gives 2 or more)."""
    value, unit = seconds / 60, "minutes"
    for name, size in (("years", 365.25 * 86400), ("days", 86400), ("hours", 3600)):
        if seconds >= 2 * size:
            value, unit = seconds / size, name
            break
    return f"{value:,.0f} {unit}" if value >= 1000 else f"{value:.3g} {unit}"


class _LongRunNotice:
    """One line on stderr when the first chunk's rate says the run takes over :data:`LONG_RUN_S`."""

    def __init__(self, prog: str, n: int):
        self.prog = prog
        self.n = n

    def __call__(self, seconds: float) -> None:
        import sys

        if seconds > LONG_RUN_S:
            clear = "\r\x1b[K" if sys.stderr.isatty() else ""  # over a progress bar's line
            print(
                f"{clear}{self.prog}: {self.n:,} samples take about {_duration_text(seconds)} at "
                "the first chunk's rate; Ctrl-C stops",
                file=sys.stderr,
                flush=True,
            )


def _volume(volume_m3: float, unit: str) -> str:
    """A volume in m^3 with 4 digits, and in the user's length unit cubed when not m."""
    text = f"{volume_m3:.4g} m^3"
    if unit != "m":
        text += f" ({volume_m3 / length_scale(unit) ** 3:.4g} {unit}^3)"
    return text


def _print_text(stats, unit: str) -> None:  # noqa: ANN001
    s = length_scale(unit)
    print(
        f"{shown_name(stats.robot)}: workspace of the tool from "
        f"{counted(stats.n_samples, 'joint vector')} "
        f"(seed {stats.seed}), lengths in {unit}"
    )
    print(
        f"radius from the base z axis:     {stats.min_radius_m / s:.6g} .. {stats.max_radius_m / s:.6g}"
    )
    print(
        f"distance from DH frame 1 origin: {stats.min_shoulder_distance_m / s:.6g} .. "
        f"{stats.max_shoulder_distance_m / s:.6g}"
    )
    print(f"reach bound (sum |a|+|d|+tool):  {stats.reach_bound_m / s:.6g}")
    for axis, lo, hi in zip("xyz", stats.bbox_min_m, stats.bbox_max_m):
        print(f"bounding box {axis}:                  {lo / s:.6g} .. {hi / s:.6g}")
    v = stats.voxel_size_m / s
    growth = stats.volume_error_m3 / max(stats.volume_m3, 1e-300)
    print(
        f"volume ({counted(stats.occupied_voxels, 'voxel')} of {v:.4g} {unit} hit): "
        f"{_volume(stats.volume_m3, unit)}; +{100 * growth:.2g}% from N/2 to N samples, "
        + ("converged" if stats.volume_converged else "NOT converged")
    )
    if not stats.volume_converged:
        print(
            f"  with the voxels not hit yet (Chao's estimate): {_volume(stats.volume_estimate_m3, unit)}"
            "; still low: more samples (--n) or larger voxels (--voxel) converge"
        )
    print(
        f"area seen from above: {stats.area_xy_m2 / s**2:.6g} {unit}^2 "
        f"+- {stats.area_xy_error_m2 / s**2:.2g}"
    )


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Sample, print the statistics (and write the PNG); exit 0, 2 for bad input, 130 on Ctrl-C."""
    args = get_argument_parser(prog).parse_args(argv)

    def body() -> int:
        from contextlib import nullcontext

        from ..workspace.monte_carlo import workspace
        from ..workspace.run import dask_client
        from .progress import ProgressBar

        if args.output:
            from .output_file import FIGURE_SUFFIXES, checked_output, input_files

            # before minutes of sampling; never over the robot's file
            checked_output(args.output, "-o", FIGURE_SUFFIXES, input_files(args, "--robot"))
        table = load_robot_argument(args).table
        scale = length_scale(args.unit)
        voxel = None if args.voxel is None else args.voxel * scale
        context = dask_client(args.scheduler) if args.scheduler else nullcontext()
        with context as client, ProgressBar(prog, "samples", quiet=args.quiet) as progress:
            progress(0, args.n)  # at once: the first chunk may take seconds
            work = workspace(
                table,
                args.n,
                args.seed,
                voxel_size_m=voxel,
                chunk_size=args.chunk_size,
                workers=args.workers,
                client=client,
                progress=progress,
                estimate=None if args.quiet else _LongRunNotice(prog, args.n),
            )
        if args.output:
            from ..workspace.plot import plot_workspace

            plot_workspace(work, args.output, args.unit)
        if args.json:
            print(dumps(work.stats.to_dict()))
        else:
            _print_text(work.stats, args.unit)
            if args.output:
                print(f"wrote {args.output}")
        return 0

    return run_guarded(prog, body)
