"""List the shipped robots: name, joints (count and types, e.g. 6R), source of the DH table."""

from __future__ import annotations

from ..cli import ArgumentParser, run_guarded
from .json_output import dumps

PROG = "kin robots"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin robots``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    parser.add_argument(
        "--json", action="store_true", help="print a JSON list, one object per robot"
    )
    return parser


def robot_records() -> list[dict[str, object]]:
    """One record per shipped robot, sorted by name: name, dof, joints code, types, texts."""
    from dh2urdf import ROBOTS

    from .joint_units import joint_types_code

    records = []
    for name in sorted(ROBOTS):
        description = ROBOTS[name]
        table = description.load_table()
        records.append(
            {
                "name": name,
                "dof": table.dof,
                "joints": joint_types_code(table),
                "joint_types": [row.joint_type for row in table.rows],
                "joint_names": list(table.joint_names),
                "tags": list(description.tags),
                "description": table.description,
                "source": table.source,
            }
        )
    return records


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Print the table (or JSON); exit 0, or 2 with one line on stderr for bad input."""
    args = get_argument_parser(prog).parse_args(argv)

    def body() -> int:
        records = robot_records()
        if args.json:
            print(dumps(records))
            return 0
        width = max(len(str(record["name"])) for record in records)
        print(f"{'robot':<{width}}  {'joints':<7} source")
        for record in records:
            print(f"{record['name']:<{width}}  {record['joints']:<7} {record['source']}")
        return 0

    return run_guarded(prog, body)
