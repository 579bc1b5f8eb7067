"""The preview page rendered by a real headless Chromium (software WebGL, network blocked).

The background (meshcat's blue ramp) and the grid hold no warm color: warm pixels (red above blue)
are the arm's orange joints, red x axes and the yellow target, so a blank canvas counts none.
UR5's fitted housings (issue 43) enclose its joints and DH triads: drawn opaque they hid them all
(ur5-b: 0.02 % warm pixels); the preview draws them see-through (kin/viewer/see_through.py).
Six pictures, about 2 s of CPU each. Skipped without Chromium (Debian: ``apt-get install
chromium``).
"""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from support.process_state import HANG_GUARD

from kin import load_robot
from kin.commands import preview as command
from kin.viewer import screenshot
from kin.viewer.exceptions import ScreenshotError

if screenshot.find_chromium() is None:
    pytest.skip("no chromium on PATH (apt-get install chromium)", allow_module_level=True)
viewer_module = pytest.importorskip("kin.viewer")
image = pytest.importorskip("matplotlib.image")

#: Two configurations per robot [rad]; the camera is fixed, so only the arm moves.
CONFIGURATIONS = {
    "ur5": ([0.0, -1.0, 1.2, -0.5, 1.2, 0.0], [1.2, -2.0, -1.0, 0.5, -0.8, 1.0]),
    "humanoid7": ([0.3, 0.5, 0.0, 1.0, 0.0, 0.5, 0.0], [-1.0, -0.8, 0.7, -1.2, 0.6, -0.5, 0.9]),
}
#: A pixel is "drawn" when a color channel differs by more than this (colors in [0, 1]).
PIXEL_TOLERANCE = 0.08
TOP_BAR = 30  # meshcat's "Open Controls" bar [px], the same in every picture


def robot_page(robot_name: str, q: list[float]) -> str:
    """A page of the arm at ``q`` with every frame's triad, seen from a fixed camera."""
    robot = load_robot(robot_name)
    viewer = viewer_module.RobotViewer(robot)
    viewer.show_frames(["base_link", "tool"])
    viewer.show_frames([f"frame{i}" for i in range(robot.nq + 1)], 0.06 * viewer.arm_length)
    viewer.display(q)
    reach = viewer.arm_length
    viewer.set_camera([0.0, 0.0, 0.0], [0.75 * reach, 0.6 * reach, 0.45 * reach])
    return viewer.static_html()


def warm_fraction(rgb: np.ndarray) -> float:
    """Share of pixels (below the controls bar) whose red exceeds their blue by 0.25."""
    body = rgb[TOP_BAR:]
    return float((body[..., 0] - body[..., 2] > 0.25).mean())


def fraction_differing(a: np.ndarray, b: np.ndarray) -> float:
    """Share of pixels (below the controls bar) whose colors differ beyond the tolerance."""
    difference = np.abs(a[TOP_BAR:] - b[TOP_BAR:]).max(axis=2)
    return float((difference > PIXEL_TOLERANCE).mean())


@pytest.fixture(scope="module")
def pictures(tmp_path_factory) -> dict[str, np.ndarray]:
    """Every picture the tests compare, rendered in parallel: name -> RGB (600, 800, 3)."""
    folder = tmp_path_factory.mktemp("preview-shots")
    pages: dict[str, str] = {}
    for robot, (q_a, q_b) in CONFIGURATIONS.items():
        pages[f"{robot}-a"] = robot_page(robot, q_a)
        pages[f"{robot}-b"] = robot_page(robot, q_b)
    # the --ik page after its 2 s animation, and a still page of the IK answer built through the
    # API as the command builds its page (base and tool triads, target, camera on start and end)
    page = folder / "ik.html"
    argv = ["--robot", "pickplace3", "--unit", "mm", "--target", "390", "80", "300", "--ik"]
    assert command.main([*argv, "--html", str(page)]) == 0
    pages["ik"] = page.read_text(encoding="utf-8")
    from kin.ik import PositionTarget, get_solver

    robot, target, q_start = load_robot("pickplace3"), np.array([0.39, 0.08, 0.3]), np.zeros(3)
    q_goal = get_solver(robot).solve(PositionTarget(target), q_start).solutions[0].q
    still = viewer_module.RobotViewer(robot)
    still.show_frames(["base_link", "tool"])
    still.display(q_goal)
    still.show_target(target)
    still.fit_camera([target], [q_start, q_goal])
    pages["goal"] = still.static_html()
    for name, html in pages.items():
        (folder / f"{name}.html").write_text(html, encoding="utf-8")

    def shoot(name: str) -> np.ndarray:
        png = screenshot.render(folder / f"{name}.html", folder / f"{name}.png", budget_ms=4000)
        return image.imread(png)[..., :3].astype(float)

    with ThreadPoolExecutor(max_workers=2) as pool:
        return dict(zip(pages, pool.map(shoot, pages)))


@pytest.mark.browser
@pytest.mark.parametrize("name", ["ur5-a", "ur5-b", "humanoid7-a", "humanoid7-b", "ik", "goal"])
def test_the_arm_is_drawn(name, pictures):
    """Every picture is 800 x 600 with at least 0.1 % warm pixels (a blank canvas has none)."""
    assert pictures[name].shape == (600, 800, 3)
    assert warm_fraction(pictures[name]) > 0.001, f"{name=} {warm_fraction(pictures[name])=:.4f}"


@pytest.mark.browser
@pytest.mark.parametrize("robot", CONFIGURATIONS)
def test_two_configurations_give_different_pictures(robot, pictures):
    """Another joint vector, same camera: at least 0.5 % of the pixels change."""
    changed = fraction_differing(pictures[f"{robot}-a"], pictures[f"{robot}-b"])
    assert changed > 0.005, f"{robot=} {changed=:.4f}"


@pytest.mark.browser
def test_ik_animation_ends_at_the_answer(pictures):
    """The --ik page, once its 2 s animation has played, looks like the still page at the answer.

    (That it starts elsewhere: test_preview.py checks the keyframes.)
    """
    after = fraction_differing(pictures["goal"], pictures["ik"])
    assert after < 0.001, f"{after=:.5f}"


def test_docs_picture_is_a_rendered_preview():
    """docs/preview.png is an 800 x 600 render of the pipeline (not a blank canvas)."""
    picture = image.imread(Path(__file__).resolve().parents[2] / "docs" / "preview.png")
    rgb = picture[..., :3].astype(float)
    assert rgb.shape == (600, 800, 3) and warm_fraction(rgb) > 0.005, warm_fraction(rgb)


def test_a_stuck_chromium_is_killed_with_its_helpers_and_tried_again(tmp_path):
    """A browser that hangs, with a helper still writing into the profile, is killed as a group.

    A stand-in "chromium" starts a helper that keeps writing into the profile folder, then hangs.
    Each of the three runs is killed after the timeout, the profile is removed all the same (the
    CI failure this guards against: "Directory not empty" on cleanup hid the retry), and no helper
    is left running.
    """
    marker = tmp_path / "helpers.txt"
    fake = tmp_path / "fake-chromium"
    fake.write_text(
        "#!/bin/sh\n"
        'for arg in "$@"; do case "$arg" in --user-data-dir=*) profile="${arg#*=}";; esac; done\n'
        f'(while true; do mkdir -p "$profile/Default"; date > "$profile/Default/x"; sleep 0.01; done) &\n'
        f'echo $! >> "{marker}"\n'
        "sleep 600\n"
    )
    fake.chmod(0o755)
    page = tmp_path / "page.html"
    page.write_text("<html></html>")
    with pytest.raises(ScreenshotError, match="hung 3 times"):
        screenshot.render(page, tmp_path / "shot.png", chromium=str(fake), timeout_s=1.0)
    helpers = [int(line) for line in marker.read_text().split()]
    assert len(helpers) == 3

    def ended(pid: int) -> bool:  # gone, or a zombie (killed, not yet reaped)
        try:
            return "Z" in Path(f"/proc/{pid}/stat").read_text().split()[2]
        except OSError:
            return True

    deadline = time.monotonic() + HANG_GUARD  # a killed helper ends at once; a loaded machine
    while not all(ended(pid) for pid in helpers):  # may take a moment to run the kill
        assert time.monotonic() < deadline, [pid for pid in helpers if not ended(pid)]
        time.sleep(0.01)
