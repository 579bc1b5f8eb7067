"""A table file that is not UTF-8 or not TOML: one line naming the file and the byte, exit 2."""

from __future__ import annotations

import pytest
from cli_helper import assert_one_line_error

from dh2urdf import TableError, get_robot, load_table
from dh2urdf.command import main as dh2urdf_main
from kin.commands import fk


def _latin1_table(tmp_path):
    """ur5's table with a Latin-1 'cafe' in its description, as a Windows editor saves it."""
    text = get_robot("ur5").table_path.read_text(encoding="utf-8")
    text = text.replace('description = "', 'description = "caf\u00e9 ', 1)
    path = tmp_path / "latin.toml"
    path.write_bytes(text.encode("latin-1"))
    return path, text.encode("latin-1").index(b"\xe9")


def test_latin1_table_names_the_byte_line_and_column(tmp_path):
    """The library's TableError gives the byte offset, its line and column, and the fix."""
    path, offset = _latin1_table(tmp_path)
    with pytest.raises(TableError, match=rf"byte {offset} \(line \d+, column \d+\) is 0xe9") as err:
        load_table(path)
    assert str(path) in str(err.value) and "save the file as UTF-8" in str(err.value)


@pytest.mark.parametrize("content", ["latin1", "random", "not toml"])
def test_commands_answer_one_line_exit_2(content, tmp_path, capsys):
    """kin fk and dh2urdf on such a file: exit 2, one line on stderr, nothing written."""
    if content == "latin1":
        path, _ = _latin1_table(tmp_path)
        needle = "not UTF-8"
    elif content == "random":
        path = tmp_path / "random.toml"
        path.write_bytes(bytes(range(128, 256)) * 3)
        needle = "not UTF-8"
    else:
        path = tmp_path / "broken.toml"
        path.write_text("name = \n[[joints\n")
        needle = "not valid TOML"
    code = fk.main(["--robot", str(path), "--q", "0", "0", "0", "0", "0", "0"])
    assert_one_line_error(code, capsys.readouterr().err, needle)
    out = tmp_path / "out.urdf"
    code = dh2urdf_main([str(path), "-o", str(out)])
    assert_one_line_error(code, capsys.readouterr().err, needle)
    assert not out.exists()
