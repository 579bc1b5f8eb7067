"""Write an SRDF of the link pairs a collision check may skip, found as MoveIt's assistant does.

By the rules of MoveIt's setup assistant (kin/collision/srdf_generator.py), a pair is disabled
when its links are joined by a joint, also through links without geometry (Adjacent), touch with
every joint at 0 (Default), touch in more than 190 of a batch of 200 random configurations
(Always, batches repeated until one disables nothing new), or in none of them and --samples more
(Never); the configurations are drawn uniformly within the joint limits with --random-seed, the
rules, count, seed and the joints held off the chain stated in the SRDF's comment. The same robot, count and seed give the same bytes. The file is written
whole or not at all; give it to `kin check --srdf` or `kin ik --srdf`.
"""

from __future__ import annotations

import sys

from dh2urdf.command_line import whole_number
from dh2urdf.output_text import counted, shown_name

from ..cli import ArgumentParser, positive_int, run_guarded
from .robot_argument import add_robot_arguments

PROG = "kin collisions"
#: Suffixes of the written SRDF.
SRDF_SUFFIXES = (".srdf", ".xml")


def _seed(text: str) -> int:
    """A random seed: an integer >= 0."""
    import argparse

    value = whole_number(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {value}")
    return value


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin collisions``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add_robot_arguments(parser)
    parser.add_argument(
        "--write-srdf",
        metavar="FILE",
        required=True,
        help="the SRDF to write (.srdf or .xml)",
    )
    parser.add_argument(
        "--samples",
        type=positive_int,
        default=10_000,
        help="random configurations to sample [count] (default 10000, as MoveIt's assistant)",
    )
    parser.add_argument(
        "--random-seed", type=_seed, default=0, help="seed of the samples (default 0)"
    )
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Write the SRDF; exit 0, 2 with one line for bad input, 1 when the disk fails."""
    args = get_argument_parser(prog).parse_args(argv)

    def body() -> int:
        from ..collision import load_collision_model
        from ..collision.srdf_generator import REASONS, generate_disabled_pairs, srdf_text
        from .output_file import checked_output, input_files, write_text_atomic
        from .robot_argument import load_robot_argument

        inputs = input_files(args, "--robot")  # the URDF is never replaced by its SRDF
        checked_output(args.write_srdf, "--write-srdf", SRDF_SUFFIXES, inputs)
        robot = load_robot_argument(args)
        model = load_collision_model(robot)
        disabled = generate_disabled_pairs(model, args.samples, args.random_seed)
        text = srdf_text(robot.name, disabled, args.samples, args.random_seed, held=model.held.note)
        write_text_atomic(args.write_srdf, text)
        counts = {r: n for r in REASONS if (n := sum(v == r for v in disabled.values()))}
        summary = ", ".join(f"{n} {r}" for r, n in counts.items())
        total = len({*model.pairs, *model.disabled})
        print(
            f"{prog}: {shown_name(robot.name)}: {len(disabled)} of "
            f"{counted(total, 'link pair')} disabled{f' ({summary})' if summary else ''}; "
            f"{counted(args.samples, 'sample')}, seed {args.random_seed} -> {args.write_srdf}",
            file=sys.stderr,
        )
        return 0

    return run_guarded(prog, body)
