"""Ctrl-C on `kin preview` exits 130 with one line, whenever it comes, and leaves no server.

While the scene is built, meshcat, pyzmq, trimesh and networkx are imported on first use;
trimesh wraps its optional imports in ``except BaseException``: a Ctrl-C that landed there was
swallowed (the server then served until a second one), and one inside pyzmq's finalizer printed
an "Exception ignored" traceback. The build holds the signal and raises it after.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from kin.commands import preview


class _SwallowingViewer:
    """A stand-in for RobotViewer whose construction imports like trimesh: a Ctrl-C that
    arrives meanwhile is caught by ``except BaseException`` and dropped."""

    url = "http://127.0.0.1:0/static/"
    arm_length = 1.0
    closed = False

    def __init__(self, robot, *, serve=False):  # noqa: ANN001
        self.robot = robot
        try:  # trimesh: try: import networkx / except BaseException as E: ...
            signal.raise_signal(signal.SIGINT)
        except BaseException:  # noqa: BLE001, S110 - what the library does
            pass

    def close(self) -> None:
        _SwallowingViewer.closed = True

    def __getattr__(self, name: str):  # noqa: ANN204 - show_frames, display, fit_camera...
        return lambda *args, **kwargs: None


def test_a_ctrl_c_during_the_build_is_not_lost_in_a_library(monkeypatch, capsys):
    """SIGINT raised inside a library's ``except BaseException`` while the viewer is built:
    exit 130, 'kin preview: interrupted', no URL, the viewer closed, never served."""
    import kin.viewer

    def served(seconds: float) -> None:
        raise AssertionError("the server waited: the Ctrl-C was lost")

    monkeypatch.setattr(kin.viewer, "RobotViewer", _SwallowingViewer)
    monkeypatch.setattr(preview.time, "sleep", served)
    _SwallowingViewer.closed = False
    assert preview.main(["--robot", "planar2"]) == 130
    captured = capsys.readouterr()
    assert captured.err == "kin preview: interrupted\n" and captured.out == ""
    assert _SwallowingViewer.closed


def test_a_ctrl_c_while_writing_a_page_still_exits_130(monkeypatch, tmp_path, capsys):
    """--html: a Ctrl-C noted while the page is built gives 130 after it is written whole."""
    import kin.viewer

    monkeypatch.setattr(kin.viewer, "RobotViewer", _SwallowingViewer)
    monkeypatch.setattr(kin.viewer, "write_page", lambda path, page: path)
    assert preview.main(["--robot", "planar2", "--html", str(tmp_path / "p.html")]) == 130
    assert capsys.readouterr().err == "kin preview: interrupted\n"


#: Runs `kin preview`, saying "ready" on stderr once the command has taken the signals (inside
#: run_guarded): before that, a Ctrl-C is the interpreter's start-up's, not the command's.
_LAUNCH = """
import sys
from kin.commands import preview

guarded = preview.run_guarded


def announced(prog, body, extra=()):
    def ready():
        sys.stderr.write("ready\\n")
        sys.stderr.flush()
        return body()

    return guarded(prog, ready, extra)


preview.run_guarded = announced
sys.exit(preview.main(["--robot", "planar2"]))
"""


def _server_children(pid: int) -> list[int]:
    """Process ids of the meshcat servers whose parent is ``pid``."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat", encoding="utf-8") as file:
                parent = int(file.read().rsplit(")", 1)[1].split()[1])
            with open(f"/proc/{entry}/cmdline", "rb") as file:
                command = file.read()
        except (OSError, IndexError, ValueError):
            continue
        if parent == pid and b"meshcat.servers.zmqserver" in command:
            found.append(int(entry))
    return found


@pytest.mark.slow
@pytest.mark.skipif(sys.platform != "linux", reason="reads /proc")
@pytest.mark.parametrize("delay", [0.0, 0.1, 0.25, 0.5, 0.8, 1.2, 2.0, "served"])
def test_ctrl_c_at_any_moment_exits_130_with_one_line(delay):
    """SIGINT at several moments from the end of `import kin` to the server waiting: exit 130
    within 20 s, exactly 'kin preview: interrupted' on stderr (no traceback, no 'Exception
    ignored'), at most the URL on stdout, and no meshcat server left behind."""
    process = subprocess.Popen(
        [sys.executable, "-c", _LAUNCH],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    servers: list[int] = []
    try:
        assert process.stderr.readline() == "ready\n"
        if delay == "served":
            assert process.stdout.readline().startswith("http://")
        else:
            time.sleep(delay)
        servers = _server_children(process.pid)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=20)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 130, err
    assert err == "kin preview: interrupted\n", err
    assert out in ("", "http://127.0.0.1:7000/static/\n") or out.startswith("http://"), out
    time.sleep(0.2)
    for pid in servers:
        assert (
            not os.path.exists(f"/proc/{pid}")
            or b"Z" in open(f"/proc/{pid}/stat", "rb").read().split(b")")[1][:3]
        ), pid  # noqa: E501, SIM115
