"""Regenerate the preview pictures of the docs with ``kin preview --png`` (headless Chromium).

    python scripts/screenshot_preview.py              # docs/preview.png and docs/preview-cell.png
    python scripts/screenshot_preview.py -o x.png -- --robot ur5 --scene examples/cell.toml

Options after ``--`` are ``kin preview``'s (one picture, at -o). The pictures are taken as
``kin preview ... --png FILE`` takes them (kin/viewer/screenshot.py).
"""

from __future__ import annotations

import argparse

from kin.cli import ArgumentParser
from kin.commands import preview

#: ``kin preview`` options of each docs picture, by file.
DOCS_PICTURES = {
    "docs/preview.png": (
        "--robot humanoid7 --q 20 30 0 60 0 30 0 --deg --target 30 20 -20 --unit cm --frames --ik"
    ).split(),
    "docs/preview-cell.png": (
        "--robot ur5 --q 0 -100 100 -90 -90 0 --deg --scene examples/cell.toml"
    ).split(),
}


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(
        prog="screenshot_preview.py",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("-o", "--output", help="PNG to write (with kin preview options)")
    parser.add_argument("preview", nargs="*", help="kin preview options (after --)")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Take each picture; exit 0, or the first non-zero exit of ``kin preview``."""
    parser = get_argument_parser()
    args = parser.parse_args(argv)
    if bool(args.preview) != bool(args.output):
        parser.error("give -o FILE and kin preview options together, or neither (the docs)")
    pictures = {args.output: args.preview} if args.output else DOCS_PICTURES
    for output, options in pictures.items():
        code = preview.main([*options, "--png", output], prog="screenshot_preview.py")
        if code != 0:
            return code
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
