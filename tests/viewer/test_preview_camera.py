"""``kin preview --camera/--zoom/--png``, and the framing and sight-line geometry under them.

The camera's recorded commands are read back from the scene tree; --png runs against a stand-in
``chromium`` (a shell script on PATH) so that these tests need no browser: the real pictures are
checked in test_preview_scene_screenshot.py.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from support.scripts_helper import exit_code

viewer_module = pytest.importorskip("kin.viewer")
from kin.commands import preview  # noqa: E402
from kin.viewer.camera_framing import tight_framing  # noqa: E402
from kin.viewer.camera_view import LENS_ZOOM, Obstacle  # noqa: E402

PNG = b"\x89PNG\r\n\x1a\n" + b"\x00" * 64  # what the stand-in browser writes


def _kept_viewer(monkeypatch) -> list:
    """The viewers the command builds, kept past its close()."""
    viewers: list = []
    keep = viewer_module.RobotViewer.close

    def close(self):
        viewers.append(self)
        keep(self)

    monkeypatch.setattr(viewer_module.RobotViewer, "close", close)
    return viewers


def _camera(viewer) -> tuple[np.ndarray, np.ndarray, float]:
    """(scene shift, camera position in meshcat's y-up frame, zoom) as recorded last."""
    import umsgpack
    from meshcat.servers.tree import find_node

    tree = viewer.viewer.window.tree
    shift = umsgpack.unpackb(find_node(tree, ["meshcat", "scene"]).transform)["matrix"]
    camera = find_node(tree, ["Cameras", "default", "rotated", "<object>"])
    values: dict = {}
    for packed in camera.properties:
        message = umsgpack.unpackb(packed)
        values[message["property"]] = message["value"]
    return np.array(shift[12:15]), np.array(values["position"]), float(values["zoom"])


def test_camera_and_zoom_are_taken_in_the_unit_given(tmp_path, monkeypatch, capsys):
    """--unit mm --camera 1000 0 500 0 0 300 --zoom 3: the scene shifted by -(0, 0, 0.3) m, the
    camera 1 m along x and 0.2 m up from it (meshcat's y-up frame: (x, z, -y)), zoom 2 x 3."""
    viewers = _kept_viewer(monkeypatch)
    argv = ["--robot", "ur5", "--unit", "mm", "--camera", "1000", "0", "500", "0", "0", "300"]
    assert preview.main([*argv, "--zoom", "3", "--html", str(tmp_path / "p.html")]) == 0
    shift, position, zoom = _camera(viewers[-1])
    np.testing.assert_allclose(shift, [0.0, 0.0, -0.3], atol=1e-12)
    np.testing.assert_allclose(position, [1.0, 0.2, 0.0], atol=1e-12)
    assert zoom == pytest.approx(LENS_ZOOM * 3)


def test_zoom_alone_magnifies_the_framed_view(tmp_path, monkeypatch):
    """--zoom 2 keeps the framed camera and doubles its zoom."""
    viewers = _kept_viewer(monkeypatch)
    for extra in ([], ["--zoom", "2"]):
        assert preview.main(["--robot", "ur5", *extra, "--html", str(tmp_path / "p.html")]) == 0
    (shift_1, position_1, zoom_1), (shift_2, position_2, zoom_2) = map(_camera, viewers)
    np.testing.assert_allclose(shift_1, shift_2)
    np.testing.assert_allclose(position_1, position_2)
    assert zoom_1 == pytest.approx(LENS_ZOOM) and zoom_2 == pytest.approx(2 * LENS_ZOOM)


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["--camera", "1", "1", "1", "1", "1", "1"], "--camera: the position"),
        (["--camera", "1", "1", "1"], "--camera"),
        (["--zoom", "0"], "--zoom"),
        (["--zoom", "nan"], "--zoom"),
        (["--png", "picture.jpg"], "--png"),
    ],
)
def test_bad_camera_zoom_or_png_is_one_line_exit_2(argv, needle, tmp_path, capsys, monkeypatch):
    """A camera at its target, a missing number, a zoom not above 0, a PNG named .jpg: exit 2."""
    monkeypatch_dir = tmp_path / "work"
    monkeypatch_dir.mkdir()
    monkeypatch.chdir(monkeypatch_dir)
    code = exit_code(preview.main, ["--robot", "ur5", *argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and needle in err[-1], err
    assert not list(monkeypatch_dir.iterdir())


def _fake_chromium(folder: Path, writes: bool) -> None:
    """A ``chromium`` on PATH that writes :data:`PNG` at --screenshot=..., or nothing."""
    script = folder / "chromium"
    (folder / "picture.png").write_bytes(PNG)
    body = 'for a in "$@"; do case "$a" in --screenshot=*) out="${a#*=}";; esac; done\n'
    if writes:
        body += f'cp "{folder / "picture.png"}" "$out"\n'
    script.write_text("#!/bin/sh\n" + body)
    script.chmod(0o755)


def test_png_without_chromium_is_one_line_exit_2(tmp_path, monkeypatch, capsys):
    """No browser on PATH: exit 2 before any work, one line naming --png and the package."""
    monkeypatch.setenv("PATH", str(tmp_path))
    picture = tmp_path / "arm.png"
    assert preview.main(["--robot", "ur5", "--png", str(picture)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--png" in err[0] and "apt-get install chromium" in err[0], err
    assert not picture.exists()


def test_png_is_the_browsers_picture_written_whole(tmp_path, monkeypatch, capsys):
    """A browser that writes a picture: its bytes at --png, no temporary file left beside it."""
    bin_folder = tmp_path / "bin"
    bin_folder.mkdir()
    _fake_chromium(bin_folder, writes=True)
    monkeypatch.setenv("PATH", f"{bin_folder}{os.pathsep}{os.environ['PATH']}")
    out = tmp_path / "out"
    out.mkdir()
    assert preview.main(["--robot", "ur5", "--png", str(out / "arm.png")]) == 0
    assert (out / "arm.png").read_bytes() == PNG
    assert [p.name for p in out.iterdir()] == ["arm.png"]
    assert "picture written to" in capsys.readouterr().out


def test_a_browser_that_writes_nothing_keeps_the_old_picture(tmp_path, monkeypatch, capsys):
    """A browser that exits without a picture: exit 1 with one line; the old file unchanged."""
    bin_folder = tmp_path / "bin"
    bin_folder.mkdir()
    _fake_chromium(bin_folder, writes=False)
    monkeypatch.setenv("PATH", f"{bin_folder}{os.pathsep}{os.environ['PATH']}")
    picture = tmp_path / "arm.png"
    picture.write_bytes(b"old")
    assert preview.main(["--robot", "ur5", "--png", str(picture)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "wrote no picture" in err[0], err
    assert picture.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["arm.png", "bin"]


def _pinhole(points, aim, position, zoom):
    """(left, right, bottom, top) in a look-at pinhole view written here (75 deg / zoom, 4:3)."""
    forward = (aim - position) / np.linalg.norm(aim - position)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    relative = points - position
    depth = relative @ forward
    tan_half = np.tan(np.radians(37.5)) / zoom
    x = relative @ right / depth / (4 / 3 * tan_half)
    y = relative @ up / depth / tan_half
    return x.min(), x.max(), y.min(), y.max()


@pytest.mark.parametrize("zoom", [1.0, 2.0])
def test_tight_framing_fills_the_stricter_field_to_the_margin(zoom):
    """Seeded clouds: every point in the view, the stricter field filled to 1 / 1.08 both ways."""
    rng = np.random.default_rng(3)
    for _ in range(20):
        points = rng.normal(size=(40, 3)) * rng.uniform(0.05, 1.0, size=3) + rng.normal(size=3)
        direction = rng.normal(size=3)
        direction[2] = abs(direction[2])
        direction /= np.linalg.norm(direction)
        aim, distance, fill = tight_framing(points, direction, 0.01, zoom)
        left, right, bottom, top = _pinhole(points, aim, aim + distance * direction, zoom)
        assert -1 < left and right < 1 and -1 < bottom and top < 1
        # the stricter field is filled to the margin on both sides; the other only fits
        sides = [(left, right), (bottom, top)]
        low, high = max(sides, key=lambda side: side[1] - side[0])
        assert low == pytest.approx(-1 / 1.08, abs=1e-9) and high == pytest.approx(
            1 / 1.08, abs=1e-9
        )
        assert fill == pytest.approx((right - left) * (top - bottom) / 4, rel=0.02)


def test_an_obstacle_hides_exactly_the_segments_through_it():
    """A turned box: its verdicts equal a dense sampling of each segment (points inside it)."""
    rng = np.random.default_rng(5)
    angle = 0.7
    T = np.eye(4)
    T[:3, :3] = [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    T[:3, 3] = [0.2, -0.1, 0.3]
    low, high = np.array([-0.3, -0.1, -0.2]), np.array([0.3, 0.1, 0.2])
    box = Obstacle(T, low, high)
    eye = np.array([1.5, 0.4, 0.5])
    ends = rng.uniform(-1.0, 1.0, size=(300, 3))
    hidden = box.hides(eye, ends)
    samples = eye + np.linspace(0, 1, 2001)[None, :, None] * (ends - eye)[:, None, :]
    local = (samples - T[:3, 3]) @ T[:3, :3]
    expected = np.all((local >= low) & (local <= high), axis=2).any(axis=1)
    assert 10 < expected.sum() < 290  # both kinds are tried
    assert np.sum(hidden != expected) <= 2, np.flatnonzero(hidden != expected)  # grazing ones
