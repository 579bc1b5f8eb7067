r"""Screenshot a ``kin preview`` page in headless Chromium (software WebGL, no network).

Regenerates the picture of docs/commands.md::

    python scripts/screenshot_preview.py -o docs/preview.png

which writes the page of ``kin preview --robot humanoid7 --q 20 30 0 60 0 30 0 --deg
--target 30 20 -20 --unit cm --frames --ik --html PAGE`` and runs, in a fresh profile::

    chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
        --disable-background-networking --disable-component-update --disable-sync \
        --use-angle=swiftshader --enable-unsafe-swiftshader --hide-scrollbars \
        --host-resolver-rules="MAP * ~NOTFOUND" --proxy-server=http://127.0.0.1:9 \
        --user-data-dir=PROFILE \
        --window-size=800,600 --virtual-time-budget=4000 --screenshot=docs/preview.png \
        file:///.../PAGE

Options after ``--`` are ``kin preview``'s (then they replace the picture's). The virtual time
budget [ms] covers the --ik animation (2 s), which ends at the IK answer.
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

from kin.cli import EXIT_BAD_INPUT, ArgumentParser, positive_int

#: ``kin preview`` options of the docs picture (docs/preview.png).
DOCS_PREVIEW = (
    "--robot humanoid7 --q 20 30 0 60 0 30 0 --deg --target 30 20 -20 --unit cm --frames --ik"
).split()

#: Chromium flags: headless, no network at all, software WebGL (SwiftShader).
CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--hide-scrollbars",
    # no network: every host unresolvable, every request through a closed proxy port
    "--host-resolver-rules=MAP * ~NOTFOUND",
    "--proxy-server=http://127.0.0.1:9",
)


def find_chromium() -> str | None:
    """Path of a Chromium executable, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def _run_group(command: list[str], timeout_s: float) -> subprocess.CompletedProcess[str]:
    """Run ``command`` in its own process group; on timeout kill the whole group.

    Raises:
        subprocess.TimeoutExpired: The command ran longer than ``timeout_s`` [s].
    """
    process = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        out, err = process.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        process.communicate()
        raise
    finally:
        try:  # chromium's helpers outlive a normal exit too, now and then
            os.killpg(process.pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
    return subprocess.CompletedProcess(command, process.returncode, out, err)


def render(
    page: Path,
    png: Path,
    width: int = 800,
    height: int = 600,
    budget_ms: int = 4000,
    chromium: str | None = None,
    timeout_s: float = 120.0,
) -> Path:
    """Screenshot ``page`` into ``png`` with headless Chromium.

    Args:
        page: An HTML file.
        png: The picture to write.
        width: Window width [px].
        height: Window height [px].
        budget_ms: Virtual time the page runs before the picture [ms].
        chromium: Executable (default: found on PATH).
        timeout_s: A run that takes longer is killed (with every process it started) and tried
            again with a fresh profile, three runs in all [s].

    Raises:
        RuntimeError: No Chromium, or it wrote no picture.
        subprocess.TimeoutExpired: All three runs took longer than ``timeout_s``.
    """
    chromium = chromium or find_chromium()
    if chromium is None:
        raise RuntimeError("no chromium on PATH (Debian: apt-get install chromium)")
    # Headless Chromium on a loaded machine now and then never finishes a page (seen about once
    # in ten CI runs): a stuck run is killed after ``timeout_s``, with every process it started (they
    # would go on writing into the profile), and tried again with a fresh profile.
    attempts = 3
    for attempt in range(1, attempts + 1):
        with tempfile.TemporaryDirectory(
            prefix="kin-chromium-", ignore_cleanup_errors=True
        ) as profile:
            command = [
                chromium,
                *CHROMIUM_FLAGS,
                f"--user-data-dir={profile}",
                f"--window-size={width},{height}",
                f"--virtual-time-budget={budget_ms}",
                f"--screenshot={Path(png).resolve()}",
                Path(page).resolve().as_uri(),
            ]
            try:
                done = _run_group(command, timeout_s)
                break
            except subprocess.TimeoutExpired:
                if attempt == attempts:
                    raise
    if not Path(png).is_file():
        raise RuntimeError(
            f"chromium wrote no {png} (exit {done.returncode}): {done.stderr[-300:]}"
        )
    return Path(png)


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(
        prog="screenshot_preview.py",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("-o", "--output", default="docs/preview.png", help="PNG to write")
    parser.add_argument("--width", type=positive_int, default=800, help="window width [px]")
    parser.add_argument("--height", type=positive_int, default=600, help="window height [px]")
    parser.add_argument(
        "--budget-ms", type=positive_int, default=4000, help="virtual time before the shot [ms]"
    )
    parser.add_argument("preview", nargs="*", help="kin preview options (after --)")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Write the page, take the picture; exit 0, or 2 with one line on stderr."""
    from kin.commands import preview

    args = get_argument_parser().parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="kin-preview-") as folder:
        page = Path(folder) / "preview.html"
        code = preview.main([*(args.preview or DOCS_PREVIEW), "--html", str(page)])
        if code != 0:
            return code
        shot = Path(folder) / "preview.png"
        try:
            render(page, shot, args.width, args.height, args.budget_ms)
            shutil.move(shot, args.output)  # the whole picture or none
        except (RuntimeError, OSError, subprocess.TimeoutExpired) as err:
            print(f"screenshot_preview.py: error: {err}", file=sys.stderr)
            return EXIT_BAD_INPUT
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
