"""``dh2urdf from-urdf``: the DH table of a URDF's chain, as a table file users write by hand.

Usage::

    dh2urdf from-urdf arm.urdf -o arm.toml                    # root link to the single leaf
    dh2urdf from-urdf ur5_robot.urdf --tip tool0 -o ur5.toml
    dh2urdf from-urdf panda.urdf --tip panda_link8 --convention modified -o -

The table's forward kinematics equals the URDF's (checked on the spot, and in the tests to
1e-12 m over 1000 joint vectors of every serial arm of example-robot-data); ``[base]`` and
``[tool]`` carry what the rows cannot; joint names, limits, velocity and effort come along;
lengths in m, angles in rad. The meshes of the links riding on the chain come along (their
``<visual>`` and ``<collision>`` meshes as ``[[joints.mesh]]`` / ``[[base_mesh]]``, origins in the
DH frames, files relative to the table; ``--no-meshes``: none); the line printed counts them and
what was left out (fingers on joints off the chain, primitive shapes). A continuous joint is a revolute one with limits [-pi, pi] (every
angle has a copy there; the solvers and paths wrap angles into the limits). Bad input (not XML,
not a URDF, an unknown link, no serial chain) exits 2 with one line; nothing is written.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .command_line import ArgumentParser, run_guarded
from .exceptions import Dh2UrdfError
from .output_text import counted

PROG = "dh2urdf from-urdf"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Arguments of ``dh2urdf from-urdf``."""
    parser = ArgumentParser(
        prog=prog,
        description=__doc__.splitlines()[0],
        epilog=__doc__.split("\n\n", 1)[1],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("urdf", help="the URDF file (.urdf; .xacro with the optional xacrodoc)")
    parser.add_argument("--base", metavar="LINK", help="base link (default: the root link)")
    parser.add_argument(
        "--tip", metavar="LINK", help="tip link (default: the single leaf below the last joint)"
    )
    parser.add_argument(
        "--convention",
        choices=("standard", "modified"),
        default="standard",
        help="DH convention of the table (default standard)",
    )
    parser.add_argument("-o", "--output", required=True, help="table file (.toml), '-' for stdout")
    parser.add_argument(
        "--no-meshes",
        action="store_true",
        help="leave the URDF's visual and collision meshes out of the table",
    )
    return parser


def _run(args: argparse.Namespace) -> int:
    from .table_writer import table_text, write_table
    from .urdf_to_dh import chain_table

    output: str = args.output
    if output != "-":
        from .output_file import checked_output

        # a regular file or a new path, before any work; never the URDF itself
        checked_output(output, "-o", (".toml",), [("the URDF", args.urdf)])
    chain, table = chain_table(args.urdf, args.base, args.tip, args.convention)
    meshes = ""
    if not args.no_meshes:
        from .urdf_meshes import carry_meshes

        carried = carry_meshes(chain, table)
        table = carried.table
        left = f"; left out: {', '.join(carried.left_out)}" if carried.left_out else ""
        meshes = f"; {counted(carried.carried, 'mesh', 'meshes')}{left}"
    header = (
        f"Read from {Path(args.urdf).name} by dh2urdf from-urdf ({table.convention} DH): the chain\n"
        f"{table.source.split(', chain ')[-1]}; its forward kinematics equals the URDF's.\n"
        "Lengths in m, angles in rad; [base] places DH frame 0 in the base link, [tool] the tip\n"
        "link in the last DH frame."
    )
    if output == "-":
        sys.stdout.write(table_text(table, header))  # mesh files: absolute paths
        return 0
    write_table(table, output, header)
    print(
        f"wrote {output} ({counted(table.dof, 'joint')} {''.join('R' if r.joint_type == 'revolute' else 'P' for r in table.rows)}, "
        f"{table.convention} DH, m/rad{meshes})"
    )
    return 0


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Write the table; exit 0, or 2 with one line on stderr for bad input."""
    args = get_argument_parser(prog).parse_args(argv)
    return run_guarded(prog, lambda: _run(args), (Dh2UrdfError, OSError))
