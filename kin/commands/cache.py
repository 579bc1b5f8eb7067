"""The seed-table cache of the numeric IK solver: its folder, files and size; --clear empties it.

The folder is $XDG_CACHE_HOME/dh-kinematics (else ~/.cache/dh-kinematics); a solver writes one
file per DH table there and reads it in the next process instead of sampling the table again.
It is kept under a fixed size, the least recently used tables removed first.
"""

from __future__ import annotations

from collections import Counter

from dh2urdf.output_text import counted

from ..cli import ArgumentParser, run_guarded
from ..exceptions import KinError
from .json_output import dumps

PROG = "kin cache"


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin cache``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    parser.add_argument(
        "--clear", action="store_true", help="remove the cache's files (they are rebuilt on use)"
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object, sizes in bytes")
    return parser


def _megabytes(size: int) -> str:
    """``size`` [B] as text in MB (10^6 B)."""
    return f"{size / 1e6:.1f} MB"


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Print the cache's folder, file count and size (or clear it); exit 0, 2 for bad input."""
    args = get_argument_parser(prog).parse_args(argv)

    def body() -> int:
        from ..ik.numeric import seed_cache

        limit = seed_cache.MAX_BYTES
        if args.clear:
            try:
                removed = seed_cache.clear()
            except OSError as err:
                raise KinError(
                    f"cannot remove {err.filename}: {err.strerror}; check the folder's permissions"
                ) from err
            if args.json:
                record = {"folder": str(removed.folder), "removed_files": removed.files}
                others = {"removed_not_regular": list(removed.others)} if removed.others else {}
                print(dumps({**record, "removed_bytes": removed.size, **others}))
            else:
                note = _megabytes(removed.size)
                if removed.others:  # a FIFO or a link put at a cache file's name
                    kinds = ", ".join(counted(n, k) for k, n in Counter(removed.others).items())
                    note += f"; {kinds} among them"
                print(f"removed {counted(removed.files, 'file')} ({note}) from {removed.folder}")
            return 0
        usage = seed_cache.usage()
        enabled = seed_cache.enabled()
        if args.json:
            record = {"folder": str(usage.folder), "files": usage.files, "bytes": usage.size}
            print(dumps({**record, "max_bytes": limit, "enabled": enabled}))
            return 0
        print(f"folder: {usage.folder}")
        print(f"files:  {usage.files} ({_megabytes(usage.size)}; kept under {_megabytes(limit)})")
        if not enabled:
            print("off:    DH_KINEMATICS_NO_CACHE is set: nothing is read or written")
        return 0

    return run_guarded(prog, body)
