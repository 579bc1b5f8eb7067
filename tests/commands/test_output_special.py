"""Outputs go only to regular files or new paths, whole or not at all.

A device (``/dev/full``, ``/dev/null``), a FIFO, a socket or a folder at an output path is one line
and exit 2 before any work; a full disk (write, fsync or rename failing with ENOSPC, EDQUOT or EIO)
is one line naming the path and exit 1, with the old file unchanged and no temporary file left.
Every command with an output option is run in-process through its ``main``.
"""

from __future__ import annotations

import contextlib
import errno
import io
import os
import signal
import socket
import stat
import subprocess
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from support.cli_helper import assert_one_line_error

import dh2urdf.robots
import dh2urdf.urdf_to_dh
import kin.reach.map
import kin.robot_model
from dh2urdf.command import main as dh2urdf_main
from kin.commands import path, preview, reach, workspace

ROOT = Path(__file__).resolve().parents[2]
URDF = str(ROOT / "urdf" / "planar2.urdf")
PATH_ARGS = ["--robot", "ur5", "--from", "0.4", "0", "0.3", "--rpy", "180", "0", "0"]
PATH_ARGS += ["--to", "0.4", "0.2", "0.3", "--rpy", "180", "0", "0", "--deg", "--steps", "10"]
REACH_ARGS = ["--robot", "ur5", "--voxel", "0.3", "--orientations", "4", "--quiet"]

#: Command -> (main, argv with {out} for the output and {tmp} for the test folder, suffix).
COMMANDS: dict[str, tuple[Callable[[list[str]], int], list[str], str]] = {
    "dh2urdf -o": (dh2urdf_main, ["--robot", "ur5", "-o", "{out}"], ".urdf"),
    "dh2urdf from-urdf -o": (dh2urdf_main, ["from-urdf", URDF, "-o", "{out}"], ".toml"),
    "kin reach -o": (reach.main, [*REACH_ARGS, "-o", "{out}"], ".npz"),
    "kin reach --png": (reach.main, [*REACH_ARGS, "-o", "{tmp}/map.npz", "--png", "{out}"], ".png"),
    "kin workspace -o": (
        workspace.main,
        ["--robot", "planar2", "--n", "2000", "-o", "{out}"],
        ".png",
    ),
    "kin path --csv": (path.main, [*PATH_ARGS, "--csv", "{out}"], ".csv"),
    "kin preview --html": (preview.main, ["--robot", "planar2", "--html", "{out}"], ".html"),
}


def _argv(name: str, out: Path, folder: Path) -> list[str]:
    return [a.replace("{out}", str(out)).replace("{tmp}", str(folder)) for a in COMMANDS[name][1]]


def _listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


@pytest.fixture
def no_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """Loading a robot, a table or a URDF fails the test: the refusal must come first."""

    def started(*_: object, **__: object) -> None:
        raise AssertionError("work started before the output path was checked")

    monkeypatch.setattr(kin.robot_model, "load_robot", started)
    monkeypatch.setattr(dh2urdf.robots.RobotDescription, "load_table", started)
    monkeypatch.setattr(dh2urdf.urdf_to_dh, "table_from_urdf", started)


@contextlib.contextmanager
def _deadline(seconds: int) -> Iterator[None]:
    """Fail (instead of hanging) when the body runs longer than ``seconds`` (opening a FIFO)."""

    def expired(*_: object) -> None:
        raise TimeoutError(f"still running after {seconds} s: a FIFO was opened")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _special(kind: str, folder: Path, suffix: str) -> tuple[Path, Callable[[int], bool], str]:
    """A non-regular file of ``kind`` (or a link to one), its ``stat`` test and the message part."""
    if kind == "/dev/full":
        return Path("/dev/full"), stat.S_ISCHR, "character device"
    if kind == "/dev/null":
        return Path("/dev/null"), stat.S_ISCHR, "to discard the output"
    target = folder / f"out{suffix}"
    if kind == "link to /dev/full":
        target.symlink_to("/dev/full")
        return target, stat.S_ISCHR, "character device"
    if kind == "fifo":
        os.mkfifo(target)
        return target, stat.S_ISFIFO, "FIFO"
    target.mkdir()
    return target, stat.S_ISDIR, "is a folder"


@pytest.mark.parametrize("kind", ["/dev/full", "/dev/null", "link to /dev/full", "fifo", "folder"])
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_non_regular_output_is_refused_before_any_work(name, kind, tmp_path, capsys, no_work):
    """A device, a link to one, a FIFO or a folder: exit 2, one line naming it, the node kept."""
    main, _, suffix = COMMANDS[name]
    target, is_kind, needle = _special(kind, tmp_path, suffix)
    before = _listing(tmp_path)
    keep_open = os.open(target, os.O_RDWR | os.O_NONBLOCK) if kind == "fifo" else None
    try:
        with _deadline(60):
            code = main(_argv(name, target, tmp_path))
    finally:
        if keep_open is not None:
            os.close(keep_open)
    err = capsys.readouterr().err
    assert_one_line_error(code, err, needle)
    assert str(target) in err, f"{name=} {err=}"
    assert is_kind(os.stat(target).st_mode), f"{name=}: {target} was replaced"
    assert _listing(tmp_path) == before, f"{name=}"


def test_socket_at_the_output_path_is_refused(capsys, no_work):
    """A Unix socket at -o: exit 2, one line, the socket kept."""
    with tempfile.TemporaryDirectory(dir="/tmp") as folder:  # short: a socket path is <= 107 bytes
        target = Path(folder) / "arm.urdf"
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as server:
            server.bind(str(target))
            code = dh2urdf_main(["--robot", "ur5", "-o", str(target)])
            assert_one_line_error(code, capsys.readouterr().err, "socket")
            assert stat.S_ISSOCK(os.stat(target).st_mode)


def test_link_to_a_regular_file_is_written_through(tmp_path, capsys):
    """-o LINK to a regular file: the file gets the output, the link stays a link, mode kept."""
    real = tmp_path / "real.urdf"
    real.write_text("old", encoding="utf-8")
    real.chmod(0o640)
    link = tmp_path / "link.urdf"
    link.symlink_to(real.name)
    assert dh2urdf_main(["--robot", "ur5", "-o", str(link)]) == 0
    assert link.is_symlink() and os.readlink(link) == real.name
    assert real.read_text(encoding="utf-8").startswith("<?xml")
    assert stat.S_IMODE(real.stat().st_mode) == 0o640
    assert _listing(tmp_path) == ["link.urdf", "real.urdf"]


class _FullRaw(io.FileIO):
    """A file whose every write meets a full disk."""

    def write(self, data: object) -> int:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))


def _fail(point: str, monkeypatch: pytest.MonkeyPatch) -> str:
    """Make the write, the fsync or the rename of an output fail; the error's text."""
    if point == "write":
        real_fdopen = os.fdopen

        def full_fdopen(fd: int, mode: str = "r", *args: object, **kwargs: object) -> object:
            if mode == "wb":
                return io.BufferedWriter(_FullRaw(fd, "wb"))
            return real_fdopen(fd, mode, *args, **kwargs)

        monkeypatch.setattr(os, "fdopen", full_fdopen)
        return os.strerror(errno.ENOSPC)
    code = errno.EDQUOT if point == "fsync" else errno.EIO

    def refuse(*_: object) -> None:
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(os, "fsync" if point == "fsync" else "replace", refuse)
    return os.strerror(code)


@pytest.mark.parametrize("point", ["write", "fsync", "replace"])
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_full_disk_is_one_line_exit_1_and_the_old_file_stays(
    name, point, tmp_path, capsys, monkeypatch
):
    """ENOSPC at write, EDQUOT at fsync, EIO at rename: exit 1, one line, old file unchanged."""
    main, _, suffix = COMMANDS[name]
    target = tmp_path / f"out{suffix}"
    target.write_bytes(b"old")
    argv = _argv(name, target, tmp_path)
    if name == "kin reach --png":  # the map is not written: only the figure meets the full disk
        monkeypatch.setattr(kin.reach.map, "save_reach_map", lambda *_: None)
    before = _listing(tmp_path)
    reason = _fail(point, monkeypatch)
    code = main(argv)
    monkeypatch.undo()
    err = capsys.readouterr().err
    assert code == 1, f"{name=} {point=} {err=}"
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert str(target) in err and reason in err, f"{name=} {err=}"
    assert target.read_bytes() == b"old", f"{name=} {point=}"
    assert _listing(tmp_path) == before, f"{name=} {point=}"


@contextlib.contextmanager
def _small_tmpfs(folder: Path) -> Iterator[Path]:
    """A 64 KiB tmpfs at ``folder`` (skips unless mount is permitted), unmounted after."""
    folder.mkdir()
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root")
    done = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(folder)],
        capture_output=True,
        text=True,
        timeout=30,
    )
    if done.returncode != 0:
        pytest.skip(f"mount not permitted here: {done.stderr.strip()}")
    try:
        yield folder
    finally:
        subprocess.run(["umount", str(folder)], check=True, timeout=30)


@pytest.mark.parametrize("name", ["dh2urdf -o", "kin path --csv", "kin workspace -o"])
def test_really_full_disk_is_one_line_exit_1(name, tmp_path, capsys):
    """On a tmpfs filled up to the last page: exit 1, one line, old file and nothing else."""
    main, _, suffix = COMMANDS[name]
    with _small_tmpfs(tmp_path / "small") as small:
        target = small / f"out{suffix}"
        target.write_bytes(b"old")
        filler = os.open(small / "filler", os.O_WRONLY | os.O_CREAT)  # take every free page
        with contextlib.suppress(OSError):
            while True:
                os.write(filler, b"\0" * 4096)
        os.close(filler)
        before = _listing(small)
        code = main(_argv(name, target, tmp_path))
        err = capsys.readouterr().err
        assert code == 1, f"{name=} {err=}"
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
        assert str(target) in err and os.strerror(errno.ENOSPC) in err, err
        assert target.read_bytes() == b"old" and _listing(small) == before
