"""The seed-table cache: a damaged file rebuilt with one warning, special files skipped without
waiting, the folder trimmed least recently used first, and ``kin cache`` (a temporary cache)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
from pathlib import Path

import numpy as np
import pytest
from support.cli_helper import kin_command, run

from kin.commands import cache
from kin.ik.numeric import seed_cache
from kin.ik.numeric.seed_cache import CacheWarning

#: A humanoid7 target the numeric solver answers from its seed table.
IK_ARGV = ["ik", "--robot", "humanoid7", "--target", "0.2", "0.1", "-0.1", "--json"]


@pytest.fixture()
def folder(tmp_path, monkeypatch) -> Path:
    """A fresh cache folder ($XDG_CACHE_HOME in tmp_path), the cache on."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.delenv("DH_KINEMATICS_NO_CACHE", raising=False)
    return tmp_path / "xdg" / "dh-kinematics"


def _kin(argv: list[str], timeout: float = 120) -> subprocess.CompletedProcess:
    """``kin argv`` in a subprocess (the environment's cache folder), text output."""
    return subprocess.run([*kin_command(), *argv], capture_output=True, text=True, timeout=timeout)


def _answer(done: subprocess.CompletedProcess) -> dict:
    """A `kin ik --json` answer without its time."""
    assert done.returncode == 0, done.stderr
    answer = json.loads(done.stdout)
    answer.pop("time_s")
    return answer


def _arrays(n: int = 50) -> dict[str, np.ndarray]:
    """Arrays of a tiny, consistent seed table (:data:`seed_cache.CACHED_ARRAYS`), ~``n`` kB."""
    rng = np.random.default_rng(n)
    return {
        "q": rng.uniform(-1, 1, (n * 16, 7)),
        "positions": rng.uniform(-1, 1, (n * 16, 3)),
        "rotations": rng.uniform(-1, 1, (n * 16, 9)),
        "keys": np.arange(4),
        "spans": np.array([[0, 1], [1, 2], [2, 3], [3, 4]]),
        "owners": np.arange(4),
        "origin": np.zeros(3),
        "shape": np.array([2, 2, 1]),
    }


def test_a_damaged_file_is_rebuilt_with_one_warning(folder):
    """A real cache file cut in half: `kin ik` prints one warning line naming it, rebuilds the
    table (valid again: the next run is silent) and answers as with a fresh cache."""
    fresh = _kin(IK_ARGV)
    assert fresh.stderr == ""
    (path,) = folder.glob("seed_table_*.npz")
    size = path.stat().st_size
    with path.open("r+b") as file:
        file.truncate(size // 2)
    damaged = _kin(IK_ARGV)
    lines = damaged.stderr.splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and "damaged" in lines[0], damaged.stderr
    assert lines[0].startswith("kin ik: warning: ")
    assert _answer(damaged) == _answer(fresh)
    assert path.stat().st_size == size and seed_cache.load(path.stem[11:]) is not None
    again = _kin(IK_ARGV)
    assert again.stderr == "" and _answer(again) == _answer(fresh)


def test_a_fifo_at_the_path_is_skipped_without_waiting(folder):
    """A FIFO where the table's file goes: one warning line naming it, the answer of a fresh
    cache, within the timeout (no reader waits for a writer); the FIFO is left as it was."""
    fresh = _kin(IK_ARGV)
    (path,) = folder.glob("seed_table_*.npz")
    path.unlink()
    os.mkfifo(path)
    done = _kin(IK_ARGV, timeout=60)
    lines = done.stderr.splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and "FIFO" in lines[0], done.stderr
    assert _answer(done) == _answer(fresh)
    assert path.is_fifo()


def _alarm(signum, frame):  # noqa: ANN001, ANN202
    raise TimeoutError("load() waited")


@pytest.mark.parametrize("kind", ["fifo", "directory", "device link", "fifo link"])
def test_special_files_are_skipped_with_one_warning(kind, folder, tmp_path):
    """load() of a FIFO, a directory, a link to a device or to a FIFO: None, one CacheWarning
    naming the path and what it is, at once (an alarm after 5 s would fail the test)."""
    folder.mkdir(parents=True)
    path = seed_cache.path_for("0" * 32)
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "directory":
        path.mkdir()
    elif kind == "device link":
        path.symlink_to("/dev/zero")
    else:
        os.mkfifo(tmp_path / "elsewhere")
        path.symlink_to(tmp_path / "elsewhere")
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(5)
    try:
        with pytest.warns(CacheWarning) as caught:
            assert seed_cache.load("0" * 32) is None
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    assert len(caught) == 1, [str(w.message) for w in caught]
    word = {"fifo": "FIFO", "directory": "directory", "device link": "device"}.get(kind, "FIFO")
    assert str(path) in str(caught[0].message) and f"is a {word}" in str(caught[0].message)
    seed_cache.store("0" * 32, _arrays())  # not written over
    assert path.is_symlink() or not path.is_file()


def test_trim_removes_the_least_recently_used_first(folder):
    """Tables of 40, 30, 20, 10 kB last used in that order (oldest first) and a file of
    another name: trimmed to 35 kB, the 10 and 20 kB (newest) stay, the others go; the newest
    stays even alone above the limit; other files are never removed."""
    folder.mkdir(parents=True)
    other = folder / "notes.txt"
    other.write_text("mine")
    for age, (name, size) in enumerate([("d", 10), ("c", 20), ("b", 30), ("a", 40)]):
        path = folder / f"seed_table_{name}.npz"
        path.write_bytes(b"x" * size * 1000)
        os.utime(path, (1e9 - age * 100, 1e9 - age * 100))
    assert seed_cache.trim(35_000) == 2
    assert sorted(p.name for p in folder.iterdir()) == [
        "notes.txt",
        "seed_table_c.npz",
        "seed_table_d.npz",
    ]
    assert seed_cache.trim(5_000) == 1  # the newest (10 kB) stays
    assert sorted(p.name for p in folder.iterdir()) == ["notes.txt", "seed_table_d.npz"]


def test_a_read_keeps_a_table_and_each_write_trims(folder, monkeypatch):
    """Three stored tables, the first two made old; reading the first touches it; the next store
    (limit: three tables' bytes) removes the second, least recently used."""
    for key in ("a" * 32, "b" * 32, "c" * 32):
        seed_cache.store(key, _arrays())
    sizes = {p.name: p.stat().st_size for p in folder.iterdir()}
    assert len(sizes) == 3 and len(set(sizes.values())) == 1
    for key in ("a" * 32, "b" * 32):
        os.utime(seed_cache.path_for(key), (1e9, 1e9))
    assert seed_cache.load("a" * 32) is not None
    assert seed_cache.path_for("a" * 32).stat().st_mtime > 1e9 + 1e6  # touched now
    monkeypatch.setattr(seed_cache, "MAX_BYTES", 3 * max(sizes.values()) + 100)
    seed_cache.store("d" * 32, _arrays())
    assert sorted(p.name[11:12] for p in folder.iterdir()) == ["a", "c", "d"]


def test_kin_cache_shows_and_clears(folder, capsys):
    """`kin cache`: the folder, 3 files, 4.5 MB (text and --json, in bytes); --clear removes the
    three (a temporary one included) and leaves other files; then 0 files."""
    folder.mkdir(parents=True)
    (folder / "notes.txt").write_text("mine")
    for name in ("seed_table_a.npz", "seed_table_b.npz", ".seed_table_x.npz"):
        with (folder / name).open("wb") as file:
            file.truncate(1_500_000)
    assert cache.main([]) == 0
    assert capsys.readouterr().out == (
        f"folder: {folder}\nfiles:  3 (4.5 MB; kept under 100.0 MB)\n"
    )
    assert cache.main(["--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record == {
        "folder": str(folder),
        "files": 3,
        "bytes": 4_500_000,
        "max_bytes": seed_cache.MAX_BYTES,
        "enabled": True,
    }
    assert cache.main(["--clear"]) == 0
    assert capsys.readouterr().out == f"removed 3 files (4.5 MB) from {folder}\n"
    assert [p.name for p in folder.iterdir()] == ["notes.txt"]
    assert cache.main(["--clear", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record == {"folder": str(folder), "removed_files": 0, "removed_bytes": 0}


def test_kin_cache_command_line(folder):
    """`python -m kin cache --json` is registered (the environment's folder); a bad option is
    one line, exit 2; with the cache off it says so."""
    done = run(["cache", "--json"])
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["folder"] == str(folder)
    bad = run(["cache", "--bogus"])
    assert bad.returncode == 2 and len(bad.stderr.splitlines()) == 1, bad.stderr
    off = subprocess.run(
        [*kin_command(), "cache"],
        capture_output=True,
        text=True,
        env={**os.environ, "DH_KINEMATICS_NO_CACHE": "1"},
        timeout=60,
    )
    assert off.returncode == 0 and "DH_KINEMATICS_NO_CACHE" in off.stdout
