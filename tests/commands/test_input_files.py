"""Input files that are not regular files, or too large, or hold a 5000-digit integer (issue 42).

``--scene /dev/zero``, ``--srdf /dev/zero`` and ``--robot /dev/zero`` (or a link to it) read
until a MemoryError; a FIFO without a writer blocked forever; a 5000-digit integer in a scene,
a DH table, a URDF or a path file was a traceback. Each is now one line naming the file, exit 2.
Commands run in subprocesses with a memory cap and a timeout: a hang or a read without end fails
the test instead of stopping pytest.
"""

from __future__ import annotations

import errno
import os
import resource
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from support.cli_helper import kin_command

import dh2urdf
import kin
from dh2urdf.exceptions import UrdfChainError
from dh2urdf.input_file import MAX_INPUT_BYTES, open_input, read_input
from dh2urdf.urdf_chain import urdf_text
from kin.audit.samples import read_samples
from kin.collision.scene import read_scene
from kin.collision.srdf import read_srdf
from kin.exceptions import CollisionModelError, KinError
from kin.path import read_joint_path
from kin.reach.map_file import load_reach_map

ROOT = Path(__file__).resolve().parents[2]
#: The shipped UR5 table, where the package is installed (a wheel's tests run from a tree
#: without the package sources).
UR5_TABLE = Path(dh2urdf.__file__).resolve().parent / "tables" / "ur5.toml"
#: A hang (a FIFO opened for reading) is caught by this timeout [s]; the commands answer in
#: about 1 s on an idle machine, the margin is for a busy one.
TIMEOUT_S = 60
#: Address-space cap of a command run here [bytes]: reading /dev/zero hits it in seconds.
MEMORY_CAP = 3 * 2**30
#: An integer longer than Python converts (its limit is 4300 digits).
DIGITS = "1" * 5000
CHECK = ["check", "--robot", "ur5", "--q", "0", "-1.5", "1.5", "0", "0", "0"]


def _capped() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP, MEMORY_CAP))


def _run(argv: list[str], cwd: Path, program: list[str] | None = None) -> tuple[int, str]:
    """Exit code and stderr of a command, with the memory cap and the timeout."""
    command = (program or kin_command()) + argv
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    done = subprocess.run(
        command,
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
        preexec_fn=_capped,
        env=env,
        stdin=subprocess.DEVNULL,
    )
    return done.returncode, done.stderr


def _dh2urdf() -> list[str]:
    script = Path(sys.executable).with_name("dh2urdf")
    return [str(script)] if script.exists() else [sys.executable, "-m", "dh2urdf"]


def _assert_one_line(code: int, err: str, *needles: str) -> None:
    assert code == 2, (code, err[-2000:])
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err[-2000:]
    assert all(needle in lines[0] for needle in needles), (needles, lines[0][:500])
    assert len(lines[0]) < 600, lines[0][:600]  # the value is not repeated whole


@pytest.fixture
def specials(tmp_path: Path) -> dict[str, Path]:
    """A FIFO, a link to /dev/zero, a link loop and a folder, each with an input's suffix."""
    os.mkfifo(tmp_path / "fifo.toml")
    (tmp_path / "zero.urdf").symlink_to("/dev/zero")
    (tmp_path / "loop.toml").symlink_to(tmp_path / "loop2.toml")
    (tmp_path / "loop2.toml").symlink_to(tmp_path / "loop.toml")
    (tmp_path / "folder.toml").mkdir()
    return {
        "device": Path("/dev/zero"),
        "link to a device": tmp_path / "zero.urdf",
        "FIFO": tmp_path / "fifo.toml",
        "link loop": tmp_path / "loop.toml",
        "folder": tmp_path / "folder.toml",
    }


#: What the message says of each special file.
SAID = {
    "device": "a character device",
    "link to a device": "a character device",
    "FIFO": "a FIFO",
    "link loop": "a loop of symbolic links",
    "folder": "a folder",
}


@pytest.mark.parametrize(
    "option",
    ["--scene", "--srdf", "--robot"],
)
@pytest.mark.parametrize("kind", sorted(SAID))
def test_kin_check_refuses_special_inputs(option, kind, specials, tmp_path):
    """kin check with a device, a FIFO, a link loop or a folder as an input: one line, exit 2."""
    argv = [*CHECK, option, str(specials[kind])]
    if option == "--robot":
        argv = ["check", "--robot", str(specials[kind]), "--q", "0", "0", "0", "0", "0", "0"]
    code, err = _run(argv, tmp_path)
    _assert_one_line(code, err, str(specials[kind]), SAID[kind])


@pytest.mark.parametrize("kind", ["device", "FIFO", "link to a device"])
def test_dh2urdf_and_kin_fk_refuse_special_tables(kind, specials, tmp_path):
    """dh2urdf TABLE and kin fk --robot TABLE on a device or FIFO: one line, exit 2, no output."""
    path = str(specials[kind])
    code, err = _run([path, "-o", str(tmp_path / "out.urdf")], tmp_path, _dh2urdf())
    _assert_one_line(code, err, path, SAID[kind])
    assert not (tmp_path / "out.urdf").exists()
    code, err = _run(["fk", "--robot", path, "--q", "0", "0", "0"], tmp_path)
    _assert_one_line(code, err, path, SAID[kind])


def _readers() -> dict[str, tuple[Callable[[Path], object], type[Exception]]]:
    """Every library reader of a user's file, with the exception it raises for a bad one."""
    return {
        "load_table": (dh2urdf.load_table, dh2urdf.TableError),
        "urdf_text": (urdf_text, UrdfChainError),
        "read_scene": (read_scene, CollisionModelError),
        "read_srdf": (lambda p: read_srdf(p, "ur5", (), ()), CollisionModelError),
        "read_joint_path": (lambda p: read_joint_path(p, 6), KinError),
        "load_reach_map": (load_reach_map, KinError),
        "read_samples": (lambda p: read_samples(p, 6), KinError),
        "load_robot": (kin.load_robot, Exception),
    }


@pytest.mark.parametrize("reader", sorted(_readers()))
@pytest.mark.parametrize("kind", ["folder", "link loop"])
def test_every_reader_names_what_the_file_is(reader, kind, specials):
    """Each reader of a user's file: its package's error naming the file and what it is."""
    read, error = _readers()[reader]
    with pytest.raises(error) as caught:
        read(specials[kind])
    message = str(caught.value)
    assert str(specials[kind]) in message and SAID[kind] in message, message
    assert "\n" not in message, message


def test_a_file_larger_than_the_cap_is_refused_not_read(tmp_path):
    """A regular file above the cap: refused from its size, before it is read."""
    path = tmp_path / "huge.toml"
    with path.open("wb") as handle:
        handle.truncate(MAX_INPUT_BYTES + 1)  # sparse: no disk used
    with pytest.raises(OSError) as caught:
        read_input(path)
    assert caught.value.errno == errno.EFBIG and "64 MiB" in caught.value.strerror
    with pytest.raises(dh2urdf.TableError, match=r"huge\.toml: cannot read the file .*64 MiB"):
        dh2urdf.load_table(path)
    assert read_input(path, MAX_INPUT_BYTES + 1) == bytes(MAX_INPUT_BYTES + 1)


def test_a_file_grown_past_the_cap_while_read_is_refused(tmp_path, monkeypatch):
    """A file that grows beyond the cap after its size was checked: refused, not cut."""
    import dh2urdf.input_file

    path = tmp_path / "table.toml"
    path.write_bytes(b"x" * 10)
    monkeypatch.setattr(dh2urdf.input_file, "_checked", lambda *args: None)  # checked at 0 bytes
    with pytest.raises(OSError) as caught:
        read_input(path, limit=5)
    assert caught.value.errno == errno.EFBIG


def test_a_regular_file_is_read_whole(tmp_path):
    """A regular file (and a link to one) is read as it is."""
    (tmp_path / "a.toml").write_bytes(b"name = 'x'\n")
    (tmp_path / "b.toml").symlink_to(tmp_path / "a.toml")
    assert read_input(tmp_path / "b.toml") == b"name = 'x'\n"
    with open_input(tmp_path / "a.toml") as handle:
        assert handle.read() == b"name = 'x'\n"


# --- a 5000-digit integer --------------------------------------------------------------------


def test_5000_digit_integer_in_a_scene(tmp_path):
    """kin check --scene with a 5000-digit size: one line naming the file and the line, exit 2."""
    scene = tmp_path / "scene.toml"
    scene.write_text(f"[[box]]\nsize = [{DIGITS}, 1, 1]\n")
    code, err = _run([*CHECK, "--scene", str(scene)], tmp_path)
    _assert_one_line(code, err, str(scene), "line 2", "5000 digits")


def test_5000_digit_integer_in_a_table(tmp_path):
    """dh2urdf and kin fk on a DH table with a 5000-digit value: one line, exit 2."""
    text = UR5_TABLE.read_text().replace("d = ", f"d = {DIGITS} #", 1)
    table = tmp_path / "arm.toml"
    table.write_text(text)
    line = text[: text.index(DIGITS)].count("\n") + 1
    code, err = _run([str(table), "-o", str(tmp_path / "arm.urdf")], tmp_path, _dh2urdf())
    _assert_one_line(code, err, str(table), f"line {line}", "5000 digits")
    code, err = _run(["fk", "--robot", str(table), "--q", "0", "0", "0", "0", "0", "0"], tmp_path)
    _assert_one_line(code, err, str(table), f"line {line}", "5000 digits")


@pytest.mark.parametrize("where", ["joint origin", "inertial origin", "joint limit"])
def test_5000_digit_number_in_a_urdf(where, tmp_path):
    """A URDF number urdfdom cannot read: one line naming the file, not its C++ lines, exit 2."""
    text = (ROOT / "urdf" / "ur5.urdf").read_text()
    attribute = {"joint origin": "<joint", "inertial origin": "<inertial", "joint limit": "<limit"}
    start = text.index(attribute[where])
    key = 'upper="' if where == "joint limit" else 'xyz="'
    at = text.index(key, start) + len(key)
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(
        text[:at] + DIGITS + ("" if key == 'upper="' else " 0 0") + text[text.index('"', at) :]
    )
    code, err = _run(["fk", "--robot", str(urdf), "--q", "0", "0", "0", "0", "0", "0"], tmp_path)
    _assert_one_line(code, err, str(urdf), "1111111111")
    assert "pose.cpp" not in err and "at line" not in err, err


def test_5000_digit_integer_on_the_command_line_and_in_a_stream(tmp_path):
    """kin fk --q with 5000 digits and a --stdin line with one: one line each, not a traceback."""
    code, err = _run(["fk", "--robot", "ur5", "--q", DIGITS, "0", "0", "0", "0", "0"], tmp_path)
    _assert_one_line(code, err, "--q")
    done = subprocess.run(
        [*kin_command(), "ik", "--robot", "ur5", "--stdin"],
        input=f'{{"target": [{DIGITS}, 0, 0]}}\n',
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
    )
    assert "Traceback" not in done.stderr and "set_int_max_str_digits" not in done.stdout
    assert "5000 digits" in done.stdout, done.stdout[:500]


def test_5000_digit_integer_in_a_path_file(tmp_path):
    """A joint path file with a 5000-digit value: a PathError naming the file and the line."""
    path = tmp_path / "path.json"
    path.write_text(f'{{"q": [[{DIGITS}, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0]]}}')
    with pytest.raises(KinError, match=r"path\.json: line 1, column 9: an integer of 5000"):
        read_joint_path(path, 6)


def test_a_reach_map_is_still_read(tmp_path):
    """The reach map reader, now through open_input, reads what save_reach_map wrote."""
    from kin.reach.grid import ReachMap
    from kin.reach.map_file import save_reach_map

    centers = np.zeros((1, 1, 1, 3))
    reach_map = ReachMap(
        robot="ur5",
        voxel_m=0.1,
        centers_m=centers,
        index=np.ones((1, 1, 1)),
        orientations=4,
        rotations=np.zeros((0, 3, 3)),
        max_reach_m=1.0,
        time_s=0.5,
        collisions="",
    )
    loaded = load_reach_map(save_reach_map(reach_map, tmp_path / "map.npz"))
    assert loaded.voxel_m == 0.1 and loaded.index.shape == (1, 1, 1)
