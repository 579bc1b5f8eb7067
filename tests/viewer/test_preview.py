"""``kin preview`` and ``kin.viewer``: the page's scene against the URDF and FK, errors, server."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import urllib.request
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call, kin_command
from support.preview_page import (
    animation_tracks,
    cloud_points,
    object_paths,
    page_commands,
    write_page,
)
from support.scripts_helper import load_script

from dh2urdf import robot_names
from kin import Configuration, load_robot
from kin.commands import COMMANDS
from kin.commands import preview as command

viewer_module = pytest.importorskip("kin.viewer")


def test_preview_is_a_kin_command_and_a_script(capsys):
    """`kin preview` is registered; scripts/preview.py is the same parser under its own name."""
    assert "preview" in COMMANDS and list(COMMANDS) == sorted(COMMANDS)
    script = load_script("preview")
    assert script.get_argument_parser().prog == "preview.py"
    assert_one_line_error(call(script.main, ["--robot", "nosuch"]), capsys.readouterr().err)


@pytest.mark.parametrize("robot", robot_names())
def test_every_robot_writes_a_page_with_its_link_geometry(robot, tmp_path, capsys):
    """One object per URDF <visual> (Pinocchio's names), triads on every DH frame, no network."""
    html = write_page(tmp_path, capsys, ["--robot", robot, "--frames"])
    model = load_robot(robot)
    root = ET.fromstring(model.urdf)
    visuals = {
        f"{link.get('name')}_{i}"
        for link in root.iter("link")
        for i, _ in enumerate(link.findall("visual"))
    }
    paths = object_paths(page_commands(html))
    drawn = {p.rsplit("/", 1)[1] for p in paths if p.startswith("/meshcat/scene/robot/visuals/")}
    assert drawn == visuals and len(visuals) >= model.nq, f"{robot=}"
    frames = [f"frame{i}" for i in range(len(model.table.rows) + 1)] + ["base_link", "tool"]
    for frame in frames:
        assert {f"/meshcat/scene/frames/{frame}/{axis}" for axis in "xyz"} <= paths, f"{robot=}"
    assert "MeshCat.Viewer" in html and len(html) > 500_000  # meshcat's JavaScript inlined
    # nothing to fetch: no external script or style, no address but an XML namespace and the
    # template of meshcat's live-server socket (never opened by a static page)
    assert not re.search(r"<script[^>]+src=|<link\b", html)
    addresses = set(re.findall(r"(?:https?|wss?)://[^\s\"'<>)]+", html))
    assert addresses <= {"http://www.w3.org/1999/xhtml", "ws://${location.host}`"}, addresses


def test_triads_and_target_sit_where_fk_puts_them(tmp_path, capsys):
    """Tool triad at FK(q), target marker at --target, both in meters, from --unit mm / --deg."""
    q_deg = [10.0, -40.0, 60.0, 0.0, 30.0, 0.0]
    argv = ["--robot", "ur5", "--q", *map(str, q_deg), "--deg", "--unit", "mm"]
    html = write_page(tmp_path, capsys, [*argv, "--target", "300", "200", "400"])
    transforms = {
        c["path"]: np.array(c["matrix"]).reshape(4, 4).T
        for c in page_commands(html)
        if c["type"] == "set_transform"
    }
    expected = Configuration(load_robot("ur5"), np.radians(q_deg)).transform_frame_to_world("tool")
    np.testing.assert_allclose(
        transforms["/meshcat/scene/frames/tool"][:3, 3], expected.translation, atol=1e-6
    )
    np.testing.assert_allclose(
        transforms["/meshcat/scene/markers/target"][:3, 3], [0.3, 0.2, 0.4], atol=1e-9
    )


def test_ik_animation_runs_from_q_to_the_answer(tmp_path, capsys):
    """--ik: the tool triad's keyframes start at FK(--q) and end on the target (closed form)."""
    robot = load_robot("pickplace3")
    q_start = np.radians([0.0, 30.0, -30.0])
    argv = ["--robot", "pickplace3", "--q", "0", "30", "-30", "--deg", "--unit", "mm"]
    html = write_page(tmp_path, capsys, [*argv, "--target", "390", "80", "300", "--ik"])
    keys = np.array(animation_tracks(page_commands(html))["/meshcat/scene/frames/tool"])
    start = Configuration(robot, q_start).transform_frame_to_world("tool").translation
    assert len(keys) == 61  # 2 s at 30 frames/s
    np.testing.assert_allclose(keys[0], start, atol=1e-6)
    np.testing.assert_allclose(keys[-1], [0.39, 0.08, 0.3], atol=1e-6)


def test_show_points_and_show_path_api():
    """RobotViewer.show_points draws (N, 3) clouds; show_path keys every joint vector."""
    robot = load_robot("planar2")
    viewer = viewer_module.RobotViewer(robot)
    points = np.random.default_rng(0).uniform(-0.5, 0.5, (500, 3))
    assert viewer.show_points(points, rgb=(1.0, 0.0, 0.0), name="cloud") == 500
    assert viewer.show_points(points[:2], rgb=[[0, 0, 1], [0, 1, 0]], name="pair") == 2
    path = np.linspace([0.0, 0.0], [1.0, -1.0], 11)
    assert viewer.show_path(path, dt=0.1) == pytest.approx(1.0)
    commands = page_commands(viewer.static_html())
    clouds = [c for c in commands if c["path"] == "/meshcat/scene/markers/cloud"]
    assert clouds[0]["object"]["object"]["type"] == "Points"
    visual = viewer.geometry_nodes[-1]
    keys = animation_tracks(commands)[f"/meshcat/{visual}"]
    assert len(keys) == 11
    with pytest.raises(viewer_module.ViewerInputError, match=r"shape \(N, 3\)"):
        viewer.show_points(np.zeros((4, 2)))
    with pytest.raises(viewer_module.ViewerInputError, match="colors"):
        viewer.show_points(points, rgb=(2.0, 0.0, 0.0))
    with pytest.raises(viewer_module.ViewerInputError, match=">= 2 joint vectors"):
        viewer.show_path([[0.0, 0.0]])


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--robot", "nosuch"], "nosuch"),
        (["--robot", "ur5", "--ik"], "--ik needs --target"),
        (["--robot", "ur5", "--rpy", "0", "0", "0"], "--rpy needs --target"),
        (["--robot", "ur5", "--q", "0", "0"], "--q needs 6 values"),
        (
            ["--robot", "ur5", "--frames", "--html", "/nonexistent/folder/page.html"],
            "does not exist",
        ),
        (
            [
                "--robot",
                "pickplace3",
                "--target",
                "0.3",
                "0",
                "0.3",
                "--rpy",
                "0",
                "0",
                "1e400",
                "--ik",
            ],
            "not a finite number",
        ),
    ],
)
def test_bad_input_exits_2_with_one_line_and_no_file(argv, needle, tmp_path, capsys):
    """Bad input: exit 2, one stderr line naming the problem, no page written."""
    argv = argv if "--html" in argv else [*argv, "--html", str(tmp_path / "page.html")]
    assert_one_line_error(call(command.main, argv), capsys.readouterr().err, needle)
    assert list(tmp_path.iterdir()) == []


def test_ik_without_a_solution_still_writes_the_page_and_exits_1(tmp_path, capsys):
    """--ik out of reach: a warning line, the page (target, no animation), exit 1."""
    page = tmp_path / "page.html"
    argv = ["--robot", "pickplace3", "--target", "5", "0", "0", "--ik", "--html", str(page)]
    assert command.main(argv) == 1
    err = capsys.readouterr().err
    assert err.startswith("kin preview: warning: no IK solution") and len(err.splitlines()) == 1
    commands = page_commands(page.read_text(encoding="utf-8"))
    assert "/meshcat/scene/markers/target/sphere" in object_paths(commands)
    assert not [c for c in commands if c["type"] == "set_animation"]


def test_missing_meshcat_is_one_line_with_the_install_hint(tmp_path, capsys, monkeypatch):
    """Without meshcat: exit 2, one line saying how to install it, no page."""
    monkeypatch.setitem(sys.modules, "meshcat", None)  # import meshcat now fails
    monkeypatch.delitem(sys.modules, "kin.viewer")
    code = call(command.main, ["--robot", "planar2", "--html", str(tmp_path / "page.html")])
    assert_one_line_error(code, capsys.readouterr().err, "pip install meshcat")
    assert list(tmp_path.iterdir()) == []


def test_unwritable_folder_leaves_nothing(tmp_path, capsys):
    """A read-only folder: exit 2, one line, and neither the page nor a temporary file in it."""
    folder = tmp_path / "readonly"
    folder.mkdir()
    folder.chmod(0o500)
    if os.access(folder, os.W_OK):
        folder.chmod(0o700)
        pytest.skip("this user writes into read-only folders (root)")
    try:
        code = call(command.main, ["--robot", "planar2", "--html", str(folder / "p.html")])
        assert_one_line_error(code, capsys.readouterr().err, "is not writable")
        assert list(folder.iterdir()) == []
    finally:
        folder.chmod(0o700)


def test_failed_write_keeps_the_old_page(tmp_path, monkeypatch):
    """write_page is all or nothing: a failing rename leaves the old file and no temporary."""
    page = tmp_path / "page.html"
    page.write_text("old", encoding="utf-8")

    def refuse(source, target):  # noqa: ANN001, ANN202
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(viewer_module.page_file.os, "replace", refuse)
    with pytest.raises(viewer_module.PageWriteError, match="No space left"):
        viewer_module.write_page(page, "new")
    assert page.read_text(encoding="utf-8") == "old" and list(tmp_path.iterdir()) == [page]


def test_server_mode_prints_url_serves_and_stops_on_ctrl_c():
    """Without --html: one URL line on stdout, the page is served, Ctrl-C: exit 130, one line."""
    process = subprocess.Popen(
        [*kin_command(), "preview", "--robot", "planar2"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        url = process.stdout.readline().strip()
        assert re.fullmatch(r"http://127\.0\.0\.1:\d+/static/", url), url
        with urllib.request.urlopen(url, timeout=10) as response:
            assert response.status == 200 and b"main.min.js" in response.read()
        servers = _children(process.pid)  # the meshcat server kin started
        assert servers, "kin preview started no server process"
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=20)
    finally:
        process.kill()
    assert process.returncode == 130 and out == ""
    assert err.strip().splitlines() == ["kin preview: interrupted"], err
    # the meshcat server stopped with it (not judged by its port: a test running beside this one
    # may start a server on the same port the moment it is free)
    assert [pid for pid in servers if _alive(pid)] == []


def _children(pid: int) -> list[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def _alive(pid: int) -> bool:
    """Whether process ``pid`` still runs (a zombie, ended but not yet reaped, is not)."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_import_kin_does_not_load_meshcat():
    """`import kin` and importing the preview command load no meshcat module."""
    code = (
        "import sys, kin, kin.commands.preview; "
        "print(sorted(m for m in sys.modules if m.startswith(('meshcat', 'kin.viewer'))))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and done.stdout.strip() == "[]", done.stderr


def test_viewer_all_is_sorted_and_exists():
    """kin.viewer.__all__: sorted, no duplicates, every name defined (9 public names)."""
    names = list(viewer_module.__all__)
    assert names == sorted(set(names)) and len(names) == 9
    assert all(hasattr(viewer_module, name) for name in names)


def path_json(tmp_path: Path, capsys, argv: list[str]) -> Path:
    """Write ``kin path ... --json`` to a file (exit 0 asserted)."""
    from kin.commands import path as path_command

    assert path_command.main([*argv, "--json"]) == 0
    file = tmp_path / "path.json"
    file.write_text(capsys.readouterr().out, encoding="utf-8")
    return file


@pytest.mark.parametrize("timed", [False, True])
def test_path_file_animates_the_path_and_draws_the_tool_trace(timed, tmp_path, capsys):
    """--path: tool keyframes run from FK(q first) to FK(q last); the trace is FK of every q."""
    import json

    argv = ["--robot", "ur5", "--from", "0.4", "0", "0.3", "--rpy", "180", "0", "0"]
    argv += ["--to", "0.4", "0.2", "0.3", "--rpy", "180", "0", "0", "--deg", "--steps", "20"]
    file = path_json(tmp_path, capsys, [*argv, *(["--time"] if timed else [])])
    document = json.loads(file.read_text(encoding="utf-8"))
    robot = load_robot("ur5")
    tool = [
        Configuration(robot, q).transform_frame_to_world("tool").translation for q in document["q"]
    ]
    commands = page_commands(write_page(tmp_path, capsys, ["--robot", "ur5", "--path", str(file)]))
    keys = np.array(animation_tracks(commands)["/meshcat/scene/frames/tool"])
    np.testing.assert_allclose(keys[0], tool[0], atol=1e-6)
    np.testing.assert_allclose(keys[-1], tool[-1], atol=1e-6)
    np.testing.assert_allclose(keys[-1], [0.4, 0.2, 0.3], atol=1e-4)  # the path's --to
    # timed: real time at 30 frames/s; untimed: one frame per sample over --duration
    expected_frames = int(np.ceil(document["t_s"][-1] * 30)) + 1 if timed else 21
    assert len(keys) == expected_frames
    np.testing.assert_allclose(cloud_points(commands, "trace"), tool, atol=1e-6)  # float32


def test_workspace_cloud_lies_within_the_reach_of_the_table(tmp_path, capsys):
    """--workspace N: N tool points, none farther from DH frame 0 than the sum of |a| + |d|."""
    html = write_page(tmp_path, capsys, ["--robot", "scorbot", "--workspace", "3000"])
    points = cloud_points(page_commands(html), "workspace")
    table = load_robot("scorbot").table
    reach = sum(abs(row.a) + abs(row.d) for row in table.rows) + np.linalg.norm(
        table.T_last_tool[:3, 3]
    )
    origin = table.T_world_base[:3, 3]
    assert points.shape == (3000, 3)
    assert np.linalg.norm(points - origin, axis=1).max() <= reach + 1e-6
    assert np.ptp(points, axis=0).min() > 0.1 * reach  # a cloud, not a point


@pytest.mark.parametrize(
    "content, needle",
    [
        ("not json", "not JSON"),
        ('{"x": 1}', "no 'q' list"),
        ('{"q": [[0, 0, 0, 0, 0, 0]]}', "at least 2 joint vectors of 6 values"),
        ('{"robot": "panda", "q": [[0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0]]}', "for 'panda'"),
        ('{"q": [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, null]]}', "non-finite"),
        ('{"q": [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 1]], "t_s": [1, 0]}', "increasing times"),
    ],
)
def test_bad_path_file_exits_2_with_one_line(content, needle, tmp_path, capsys):
    """A malformed --path file: exit 2, one line naming the file and the field, no page."""
    file = tmp_path / "bad.json"
    file.write_text(content, encoding="utf-8")
    argv = ["--robot", "ur5", "--path", str(file), "--html", str(tmp_path / "page.html")]
    err = (call(command.main, argv), capsys.readouterr().err)
    assert_one_line_error(*err, needle)
    assert "bad.json" in err[1] and not (tmp_path / "page.html").exists()


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--path", "p.json", "--target", "0.3", "0", "0.3", "--ik"], "--path or --ik"),
        (["--workspace", "0"], "--workspace: expected 1 to"),
    ],
)
def test_path_and_workspace_argument_errors(argv, needle, tmp_path, capsys):
    """Conflicting or out-of-range --path / --workspace: exit 2 with one line."""
    full = ["--robot", "ur5", *argv, "--html", str(tmp_path / "page.html")]
    assert_one_line_error(call(command.main, full), capsys.readouterr().err, needle)


def test_a_path_of_another_robot_is_refused(tmp_path, capsys):
    """kin preview --robot ur3 --path <a ur5 path>: one line naming both robots, exit 2, no page."""
    from kin.commands import path as path_command

    joint_path = tmp_path / "ur5.json"
    argv = ["--robot", "ur5", "--from", "0.4", "0", "0.3", "--rpy", "180", "0", "0", "--deg"]
    argv += ["--to", "0.4", "0.2", "0.3", "--rpy", "180", "0", "0", "--steps", "5", "--json"]
    assert path_command.main(argv) == 0
    joint_path.write_text(capsys.readouterr().out)
    page = tmp_path / "p.html"
    code = call(command.main, ["--robot", "ur3", "--path", str(joint_path), "--html", str(page)])
    assert_one_line_error(code, capsys.readouterr().err, "computed for 'ur5', not 'ur3'")
    assert not page.exists()
