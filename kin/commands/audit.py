"""Audit a DH table: find the reading of it that reproduces a source's printed numbers or a URDF.

With --samples: tries the table as written, the other DH convention, offsets not applied (all,
or one), joint zeros a quarter turn away, each twist sign flipped (and all), length and offset
signs flipped, the table's or the samples' units, printed values truncated, every pair of these,
and one link length refitted; ranks them by the samples they reproduce at the printed precision. With --urdf:
fits the constant base and tool transforms T_urdf(q) = B T_table(q) E for every reading and
ranks the residuals. Sample file: CSV with a header naming q1..qN, x, y, z, optionally roll,
pitch, yaw or r11..r33, optionally label; # starts a comment; values in the table's units
(docs/audit.md).
"""

from __future__ import annotations

from dh2urdf.command_line import whole_number

from ..cli import ArgumentParser, positive_float, positive_int, run_guarded
from .json_output import dumps

PROG = "dh2urdf audit"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``dh2urdf audit``."""
    import argparse

    parser = ArgumentParser(
        prog=prog,
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "table",
        metavar="TABLE",
        help="DH table file (.toml), shipped robot name, or a URDF (its chain read as a table; m, rad)",
    )
    parser.add_argument("--base", metavar="LINK", help="a URDF TABLE: the chain's base link")
    parser.add_argument("--tip", metavar="LINK", help="a URDF TABLE: the chain's tip link")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--samples", metavar="CSV", help="printed samples, in the table's units")
    source.add_argument("--urdf", metavar="URDF", help="reference URDF (e.g. the maker's)")
    parser.add_argument("--frame", help="with --urdf: the URDF frame of the table's tool")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--top", type=positive_int, default=10, help="readings shown in the text report (10)"
    )
    parser.add_argument("--singles", action="store_true", help="try single changes only, not pairs")
    parser.add_argument(
        "--no-refit", action="store_true", help="--samples: do not refit a link length"
    )
    parser.add_argument(
        "--count", type=positive_int, default=64, help="--urdf: joint vectors sampled (64)"
    )
    parser.add_argument("--seed", type=whole_number, default=0, help="--urdf: sampling seed (0)")
    parser.add_argument(
        "--position-tol", type=positive_float, default=1e-6, help="--urdf: [m] (1e-6)"
    )
    parser.add_argument(
        "--rotation-tol", type=positive_float, default=1e-6, help="--urdf: [rad] (1e-6)"
    )
    parser.add_argument(
        "--check",
        action="store_true",
        help="exit 1 unless the table as written is the best reading",
    )
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Run the audit; exit 0 (1 with --check and a better reading), 2 for bad input."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    if args.urdf and not args.frame:
        parser.error("--urdf needs --frame (the URDF frame of the table's tool, e.g. tool0)")
    if args.frame and not args.urdf:
        parser.error("--frame goes with --urdf")
    if (args.base or args.tip) and not args.table.endswith((".urdf", ".xacro")):
        parser.error("--base and --tip go with a URDF TABLE (a .urdf or .xacro file)")

    def body() -> int:
        from ..audit import report
        from ..audit.audited_table import load_audited_table
        from ..audit.sample_audit import audit_samples
        from ..audit.urdf_audit import audit_urdf

        table = load_audited_table(args.table, args.base, args.tip)
        if args.samples:
            audit = audit_samples(
                table, args.samples, pairs=not args.singles, refit=not args.no_refit
            )
            text = (
                dumps(report.sample_audit_json(audit))
                if args.json
                else report.sample_audit_text(audit, args.top)
            )
            best_changes = audit.best.reading.changes
        else:
            audit_u = audit_urdf(
                table,
                args.urdf,
                args.frame,
                count=args.count,
                seed=args.seed,
                pairs=not args.singles,
                position_tol=args.position_tol,
                rotation_tol=args.rotation_tol,
            )
            text = (
                dumps(report.urdf_audit_json(audit_u))
                if args.json
                else report.urdf_audit_text(audit_u, args.top)
            )
            best_changes = audit_u.best.reading.changes
        print(text)
        return 1 if args.check and best_changes else 0

    return run_guarded(prog, body)
