"""Write docs/reproduction.md, the papers' numbers against ours; --check: exit 1 if it is stale."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

from kin.cli import ArgumentParser, run_guarded

#: The repository: ``reproduction/`` is its tool for the papers, not an installed package.
ROOT = Path(__file__).resolve().parent.parent
#: The committed report.
DEFAULT_OUTPUT = ROOT / "docs" / "reproduction.md"
if str(ROOT) not in sys.path:
    sys.path.append(str(ROOT))  # after site-packages: the installed dh2urdf and kin come first


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="reproduce_papers.py", description=__doc__)
    parser.add_argument(
        "--check",
        action="store_true",
        help="write nothing; exit 1 when the report differs from the file",
    )
    parser.add_argument(
        "--output",
        type=Path,
        default=DEFAULT_OUTPUT,
        help=f"report file (default: {DEFAULT_OUTPUT.name} in docs/)",
    )
    return parser


def _write_atomically(path: Path, text: str) -> None:
    """Write ``text`` to a temporary file next to ``path``, then rename it over ``path``."""
    path.parent.mkdir(parents=True, exist_ok=True)
    umask = os.umask(0)
    os.umask(umask)
    mode = path.stat().st_mode & 0o777 if path.exists() else 0o666 & ~umask
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as handle:
            handle.write(text)
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def main(argv: list[str] | None = None) -> int:
    """Write (or check) the report; exit 0, 1 when --check finds it stale, 2 for errors."""
    args = get_argument_parser().parse_args(argv)

    def body() -> int:
        from reproduction import all_sections, render

        text = render(all_sections())
        path: Path = args.output
        if args.check:
            current = path.read_text(encoding="utf-8") if path.exists() else None
            if current != text:
                print(
                    f"reproduce_papers.py: stale: {path}; run: python scripts/reproduce_papers.py",
                    file=sys.stderr,
                )
                return 1
            print(f"{path} up to date")
            return 0
        _write_atomically(path, text)
        print(f"wrote {path}")
        return 0

    return run_guarded("reproduce_papers.py", body, extra=(OSError,))


if __name__ == "__main__":
    raise SystemExit(main())
