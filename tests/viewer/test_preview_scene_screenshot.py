"""``kin preview`` pages rendered by headless Chromium: the arm large and whole, the closest pair.

Each page is built by the command (``--html``) and rendered twice from the same camera: as written,
and with the arm's node hidden. The pixels that differ are the arm; their bounding box must keep
off the picture's edges and cover at least a third of it (a DH UR5 in the cell covered about 0.5 %,
Panda 15 %) for a DH arm (ur5), a URDF arm with the maker's meshes (Panda to panda_hand) and an
arm in a cell (examples/cell.toml). A colliding posture shows pure-red pixels (of the arm's pixels:
red above 0.45, green and blue below 0.2), a free one none. The closest pair's rod and balls are
the pixels that change when their node is hidden. Nine pictures, about 2 s of CPU each. Skipped
without Chromium.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support.urdf_reference import erd

from kin.commands import preview as command
from kin.viewer import screenshot

if screenshot.find_chromium() is None:
    pytest.skip("no chromium on PATH (apt-get install chromium)", allow_module_level=True)
viewer_module = pytest.importorskip("kin.viewer")
image = pytest.importorskip("matplotlib.image")

CELL = str(Path(__file__).resolve().parents[2] / "examples" / "cell.toml")
PANDA = str(erd("panda_description/urdf/panda.urdf"))
#: name -> kin preview arguments (without --html).
PAGES = {
    "ur5": ["--robot", "ur5", "--q", "1.2", "-2.0", "-1.0", "0.5", "-0.8", "1.0"],
    "panda": [
        "--robot",
        PANDA,
        "--tip",
        "panda_hand",
        "--q",
        "0.3",
        "-0.6",
        "0.2",
        "-2.0",
        "0.1",
        "1.6",
        "0.7",
    ],  # fmt: skip
    # the maker's base frame: q1 = 0 reaches towards the wall (+x)
    "cell-collision": ["--robot", "ur5", "--q", "0.785", "-0.6", "0.3", "0", "0", "0"],
    "cell-free": ["--robot", "ur5", "--q", "3.1416", "-1.2", "0.5", "0", "0", "0"],
}
PIXEL_TOLERANCE = 0.08  # a pixel of the arm differs by more than this in some channel


@pytest.fixture(scope="module")
def pictures(tmp_path_factory) -> dict[str, np.ndarray]:
    """name -> RGB (600, 800, 3) for each page, and name + "-hidden" with the arm hidden."""
    folder = tmp_path_factory.mktemp("scene-shots")
    viewers = []
    keep = viewer_module.RobotViewer.close

    def close(self):  # the command closes its viewer last: keep it for the hidden page
        viewers.append(self)
        keep(self)

    pages = {}
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(viewer_module.RobotViewer, "close", close)
        for name, argv in PAGES.items():
            scene = ["--scene", CELL] if name.startswith("cell") else []
            page = folder / f"{name}.html"
            assert command.main([*argv, *scene, "--html", str(page)]) == 0
            viewer = viewers[-1]
            dressed = _dressing(page.read_text(encoding="utf-8"))
            viewer.scene["robot"].set_property("visible", False)
            pages[name] = page
            pages[f"{name}-hidden"] = folder / f"{name}-hidden.html"
            pages[f"{name}-hidden"].write_text(dressed(viewer.static_html()), encoding="utf-8")
            if name == "cell-free":  # the arm back, the closest pair's markers hidden
                viewer.scene["robot"].set_property("visible", True)
                viewer.scene["markers"]["closest"].set_property("visible", False)
                pages[f"{name}-unmarked"] = folder / f"{name}-unmarked.html"
                pages[f"{name}-unmarked"].write_text(
                    dressed(viewer.static_html()), encoding="utf-8"
                )
    shots = {}
    for name, page in pages.items():
        png = screenshot.render(page, folder / f"{name}.png", budget_ms=4000)
        shots[name] = image.imread(png)[..., :3].astype(float)
    return shots


def _dressing(page: str):
    """A function that gives another page the title and caption ``page`` has (the verdict line):
    the pictures then differ only in the 3D view."""
    import html
    import re

    from kin.viewer.page_file import captioned, titled

    found = re.search(r'<p id="kin-caption"[^>]*>(.*?)</p>', page)
    if found is None:
        return lambda other: other
    text = html.unescape(found.group(1))
    return lambda other: captioned(titled(other, text), text)


def arm_box(pictures: dict[str, np.ndarray], name: str) -> tuple[int, int, int, int]:
    """Rows and columns (first, last) of the pixels where the arm's page and the hidden differ."""
    differs = np.abs(pictures[name] - pictures[f"{name}-hidden"]).max(axis=2) > PIXEL_TOLERANCE
    rows, cols = np.flatnonzero(differs.any(axis=1)), np.flatnonzero(differs.any(axis=0))
    assert differs.sum() > 200, f"{name=}: the arm covers {differs.sum()} pixels"
    return int(rows[0]), int(rows[-1]), int(cols[0]), int(cols[-1])


def red_pixels(pictures: dict[str, np.ndarray], name: str) -> int:
    """Pixels of the arm (differing from the hidden page) in red: r > 0.45, g and b < 0.2."""
    rgb = pictures[name]
    arm = np.abs(rgb - pictures[f"{name}-hidden"]).max(axis=2) > PIXEL_TOLERANCE
    return int((arm & (rgb[..., 0] > 0.45) & (rgb[..., 1] < 0.2) & (rgb[..., 2] < 0.2)).sum())


@pytest.mark.browser
@pytest.mark.parametrize("name", ["ur5", "panda", "cell-collision", "cell-free"])
def test_the_whole_arm_is_in_the_picture(name, pictures):
    """The arm's projected bounding box keeps at least 2 px off every edge of the 800 x 600 view."""
    assert pictures[name].shape == (600, 800, 3)
    top, bottom, left, right = arm_box(pictures, name)
    assert top >= 2 and left >= 2 and bottom <= 597 and right <= 797, (
        name,
        top,
        bottom,
        left,
        right,
    )


@pytest.mark.browser
def test_a_colliding_posture_shows_red_and_a_free_one_none(pictures):
    """link3 through the wall: its pixels are red; the free posture's arm has no red pixel.

    (Only the arm's pixels count: the base and tool triads' red x axes are not the arm.)
    """
    free, colliding = red_pixels(pictures, "cell-free"), red_pixels(pictures, "cell-collision")
    assert free == 0 and colliding > 30, (free, colliding)  # link3 is thin: about 60


@pytest.mark.browser
@pytest.mark.parametrize("name", ["ur5", "panda", "cell-collision", "cell-free"])
def test_the_arm_covers_a_third_of_the_picture(name, pictures):
    """The box of the arm's pixels covers at least a third of the 800 x 600 picture."""
    top, bottom, left, right = arm_box(pictures, name)
    share = (bottom - top + 1) * (right - left + 1) / (600 * 800)
    assert share >= 1 / 3, f"{name=} {share=:.3f}"


@pytest.mark.browser
def test_the_closest_pair_is_drawn_in_magenta(pictures):
    """Hiding the closest pair's node changes at least 100 pixels, most of them magenta
    (red and blue above 0.5, green below 0.3: the rod and balls, seen over the arm)."""
    rgb = pictures["cell-free"]
    marked = np.abs(rgb - pictures["cell-free-unmarked"]).max(axis=2) > PIXEL_TOLERANCE
    magenta = marked & (rgb[..., 0] > 0.5) & (rgb[..., 2] > 0.5) & (rgb[..., 1] < 0.3)
    assert marked.sum() >= 100 and magenta.sum() >= 0.5 * marked.sum(), (
        marked.sum(),
        magenta.sum(),
    )
