"""`kin cache --clear` removes whatever holds the cache's names and counts it right.

A FIFO (or a link, a socket) put at a seed table's name was left in place while the command said
"removed 0 files"; now every entry at a cache file's name is removed (a link's target is kept)
and counted by kind, a directory there is named and left, and nothing else is touched.
"""

from __future__ import annotations

import json
import os
import socket
from pathlib import Path

import numpy as np
import pytest

from kin.commands import cache
from kin.ik.numeric import seed_cache


@pytest.fixture()
def folder(tmp_path, monkeypatch) -> Path:
    """A cache folder in tmp_path ($XDG_CACHE_HOME), the cache on, created."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.delenv("DH_KINEMATICS_NO_CACHE", raising=False)
    path = tmp_path / "xdg" / "dh-kinematics"
    path.mkdir(parents=True)
    return path


def test_a_fifo_at_a_tables_name_is_removed_and_counted(folder, capsys):
    """One FIFO as seed_table_*.npz: 'removed 1 file (0.0 MB; 1 FIFO among them)', gone."""
    os.mkfifo(folder / "seed_table_f.npz")
    assert cache.main(["--clear"]) == 0
    captured = capsys.readouterr()
    assert captured.out == f"removed 1 file (0.0 MB; 1 FIFO among them) from {folder}\n"
    assert captured.err == "" and list(folder.iterdir()) == []


def test_every_kind_is_removed_its_target_kept_a_directory_named(folder, tmp_path, capsys):
    """A table of 2 MB, a temporary, two FIFOs, a socket and a link to a file of the user's at
    the cache's names; a directory at one; notes of the user's: six removed and counted by
    kind, the link's target and the notes kept, the directory left with one warning line."""
    (folder / "seed_table_a.npz").write_bytes(b"\0" * 2_000_000)
    (folder / ".seed_table_t.npz").write_bytes(b"\0" * 500_000)
    os.mkfifo(folder / "seed_table_f.npz")
    os.mkfifo(folder / ".seed_table_g.npz")
    mine = tmp_path / "mine.txt"
    mine.write_text("keep me")
    (folder / "seed_table_l.npz").symlink_to(mine)
    (folder / "notes.txt").write_text("keep me too")
    (folder / "seed_table_d.npz").mkdir()
    server = socket.socket(socket.AF_UNIX)
    try:
        server.bind(str(folder / "seed_table_s.npz"))
        assert cache.main(["--clear"]) == 0
    finally:
        server.close()
    captured = capsys.readouterr()
    assert captured.out == (
        f"removed 6 files (2.5 MB; 2 FIFOs, 1 symbolic link, 1 socket among them) from {folder}\n"
    ), captured.out
    lines = captured.err.splitlines()
    assert len(lines) == 1 and "seed_table_d.npz is a directory" in lines[0], captured.err
    assert sorted(p.name for p in folder.iterdir()) == ["notes.txt", "seed_table_d.npz"]
    assert mine.read_text() == "keep me"


def test_clear_json_names_the_kinds(folder, capsys):
    """--json: removed_files counts every entry, removed_not_regular lists the others' kinds."""
    os.mkfifo(folder / "seed_table_f.npz")
    (folder / "seed_table_a.npz").write_bytes(b"\0" * 1000)
    assert cache.main(["--clear", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record == {
        "folder": str(folder),
        "removed_files": 2,
        "removed_bytes": 1000,
        "removed_not_regular": ["FIFO"],
    }


def test_one_file_is_singular(folder, capsys):
    """'removed 1 file', not '1 files'."""
    seed_cache.store("a" * 32, {"q": np.zeros((2, 2))})
    assert cache.main(["--clear"]) == 0
    assert capsys.readouterr().out.startswith("removed 1 file (")
