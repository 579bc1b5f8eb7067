"""A picture of a preview page taken by headless Chromium (software WebGL, no network at all).

:func:`write_picture` renders a page (meshcat's static HTML) in a fresh browser profile and puts
the PNG at its path whole, or changes nothing. The browser runs as::

    chromium --headless --no-sandbox --disable-gpu --use-angle=swiftshader ... \
        --user-data-dir=PROFILE --window-size=800,600 --virtual-time-budget=MS \
        --screenshot=PICTURE.png file:///.../page.html

Every host is unresolvable and every request goes to a closed proxy port: a page that would
load anything from the network shows nothing of it. The virtual time budget [ms] lets an
animation play to its end before the picture is taken. Debian's package is ``chromium``.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import tempfile
from pathlib import Path

from .exceptions import NoBrowserError, PictureWriteError, ScreenshotError

__all__ = [
    "CHROMIUM_FLAGS",
    "PICTURE_SIZE",
    "find_chromium",
    "render",
    "write_picture",
]

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
#: Width and height of a picture [px]: the 4:3 page the camera is framed for.
PICTURE_SIZE = (800, 600)
#: Browsers looked for on PATH, in this order.
_BROWSERS = ("chromium", "chromium-browser", "google-chrome")
#: Runs of a browser that hangs, each in a fresh profile, before giving up.
_ATTEMPTS = 3


def find_chromium() -> str | None:
    """Path of a Chromium executable on PATH, or None."""
    for name in _BROWSERS:
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
        stdin=subprocess.DEVNULL,
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
    page: str | os.PathLike[str],
    png: str | os.PathLike[str],
    width: int = PICTURE_SIZE[0],
    height: int = PICTURE_SIZE[1],
    budget_ms: int = 4000,
    chromium: str | None = None,
    timeout_s: float = 120.0,
) -> Path:
    """Screenshot the HTML file ``page`` into ``png`` (written by the browser itself).

    Headless Chromium on a loaded machine now and then never finishes a page (seen about once
    in ten CI runs): a stuck run is killed after ``timeout_s`` with every process it started
    (they would go on writing into the profile) and tried again with a fresh profile.

    Args:
        page: An HTML file.
        png: The picture to write.
        width: Window width [px].
        height: Window height [px].
        budget_ms: Virtual time the page runs before the picture [ms].
        chromium: Executable (default: :func:`find_chromium`).
        timeout_s: Wall-clock time after which a run is killed [s]; three runs in all.

    Raises:
        NoBrowserError: No Chromium on PATH.
        ScreenshotError: Every run hung, or the browser wrote no picture.
    """
    chromium = chromium or find_chromium()
    if chromium is None:
        raise NoBrowserError(
            "no chromium on PATH to take the picture with (Debian: apt-get install chromium)"
        )
    done = None
    for _ in range(_ATTEMPTS):
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
                continue
    if done is None:
        raise ScreenshotError(
            f"{chromium} hung {_ATTEMPTS} times ({timeout_s:g} s each) on the page; no picture"
        )
    if not Path(png).is_file():
        detail = " ".join(done.stderr.split())[-300:]
        raise ScreenshotError(f"{chromium} wrote no picture (exit {done.returncode}): {detail}")
    return Path(png)


def write_picture(page: str, png: str | os.PathLike[str], budget_ms: int = 4000) -> Path:
    """A :data:`PICTURE_SIZE` PNG of the page text ``page`` at ``png``, whole or not at all.

    The page and the browser's picture stay in a temporary folder; the picture's bytes then go
    to ``png`` through a temporary file beside it and a rename (:mod:`dh2urdf.output_file`).

    Args:
        page: The page (meshcat's static HTML).
        png: Destination; its folder must exist.
        budget_ms: Virtual time the page runs before the picture [ms] (animations included).

    Raises:
        NoBrowserError: No Chromium on PATH.
        ScreenshotError: The browser gave no picture.
        PictureWriteError: The destination cannot take it (a folder, a full disk...).
    """
    from dh2urdf.output_file import write_atomic

    with tempfile.TemporaryDirectory(prefix="kin-picture-") as folder:
        html = Path(folder) / "preview.html"
        html.write_text(page, encoding="utf-8")
        shot = render(html, Path(folder) / "preview.png", budget_ms=budget_ms)
        content = shot.read_bytes()

    def refused(path: str, _option: str, reason: str) -> PictureWriteError:
        return PictureWriteError(path, reason)

    return write_atomic(png, lambda handle: handle.write(content), refused, PictureWriteError)
