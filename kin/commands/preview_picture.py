"""How ``kin preview`` is seen and kept: the camera (--camera, --zoom), the page and the picture.

The options are declared, checked and carried out here: --camera X Y Z TX TY TZ and --zoom F
place the camera (else it is framed on the arm, :meth:`~kin.viewer.RobotViewer.fit_camera`);
--html FILE writes the scene as one self-contained page and --png FILE an 800 x 600 picture of
that page through headless Chromium, both refused before any work when they cannot be written
(or, for --png, when no Chromium is on PATH).
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from dh2urdf.output_text import shown_name

from ..cli import ArgumentParser, finite_float, length_scale, positive_float

if TYPE_CHECKING:
    import numpy as np

    from ..viewer import RobotViewer

__all__ = [
    "PICTURE_SETTLE_MS",
    "add_picture_options",
    "check_outputs",
    "check_picture_options",
    "place_camera",
    "write_still",
]

#: Virtual time a page runs before its picture, past its animation [ms] (meshes load, it draws).
PICTURE_SETTLE_MS = 4000


def add_picture_options(parser: ArgumentParser) -> None:
    """Add --camera, --zoom, --html and --png to ``parser``."""
    add = parser.add_argument
    add(
        "--camera",
        type=finite_float,
        nargs=6,
        metavar=("X", "Y", "Z", "TX", "TY", "TZ"),
        help="camera position X Y Z and the point it looks at TX TY TZ, base frame [--unit] "
        "(default: framed on the arm)",
    )
    add("--zoom", type=positive_float, help="magnify the view by F (default 1)", metavar="F")
    add("--html", metavar="FILE", help="write a self-contained page and exit (no server)")
    add(
        "--png",
        metavar="FILE",
        help="write an 800 x 600 picture through headless Chromium and exit (no server)",
    )


def check_picture_options(parser: ArgumentParser, args: argparse.Namespace) -> None:
    """Refuse (``parser.error``, exit 2) a --camera whose position is the point it looks at."""
    if args.camera is not None and args.camera[:3] == args.camera[3:]:
        parser.error("--camera: the position X Y Z and the target TX TY TZ are the same point")


def check_outputs(args: argparse.Namespace) -> None:
    """Refuse an unwritable --html or --png before any work, and --png without a browser.

    Raises:
        kin.exceptions.OutputFileError: A folder, device or input file at the path, a missing
            folder, or another suffix; or --png and --html naming one file.
        kin.viewer.exceptions.NoBrowserError: --png and no Chromium on PATH.
    """
    from .output_file import checked_output, input_files

    inputs = input_files(args, "--robot", "--path", "--reach", "--scene", "--srdf")
    if args.html is not None:
        checked_output(args.html, "--html", (".html", ".htm"), inputs)
    if args.png is not None:
        page = [] if args.html is None else [("--html", args.html)]
        checked_output(args.png, "--png", (".png",), [*inputs, *page])
        from ..viewer.exceptions import NoBrowserError
        from ..viewer.screenshot import find_chromium

        if find_chromium() is None:
            raise NoBrowserError(
                "--png needs Chromium to take the picture and none is on PATH "
                "(Debian: apt-get install chromium); --html FILE writes the page without it"
            )


def place_camera(
    viewer: RobotViewer,
    args: argparse.Namespace,
    extra: np.ndarray | None,
    configurations: list[np.ndarray],
) -> None:
    """--camera (in --unit) and --zoom, or the view framed on the arm, ``extra`` and the q shown."""
    from ..viewer.camera_view import LENS_ZOOM

    zoom = 1.0 if args.zoom is None else args.zoom
    if args.camera is not None:
        scale = length_scale(args.unit)
        position, target = args.camera[:3], args.camera[3:]
        viewer.set_camera(
            [v * scale for v in target], [v * scale for v in position], LENS_ZOOM * zoom
        )
        return
    viewer.fit_camera(extra, configurations, zoom)


def write_still(
    viewer: RobotViewer, args: argparse.Namespace, title: str | None, played: float
) -> None:
    """Write the --html page and the --png picture of the scene; a line on stdout for each.

    Args:
        viewer: The scene, built.
        args: The command's arguments (--html, --png).
        title: The page's title and caption (the collision verdict), or None.
        played: Length of the scene's animation [s]: the picture is taken after it.
    """
    import numpy as np

    from ..viewer import write_page
    from ..viewer.page_file import captioned, titled

    name = shown_name(viewer.robot.name)
    page = viewer.static_html()
    if title is not None:
        page = captioned(titled(page, title), title)
    if args.html is not None:
        written = write_page(args.html, page)
        print(f"{name}: preview written to {written}")
    if args.png is not None:
        from ..viewer.screenshot import write_picture

        budget_ms = PICTURE_SETTLE_MS + int(np.ceil(1000.0 * played))
        written = write_picture(page, args.png, budget_ms)
        print(f"{name}: picture written to {written}")
