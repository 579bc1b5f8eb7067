"""A table file that is not UTF-8 or not TOML: one line naming the file and the byte, exit 2."""

from __future__ import annotations

import pytest
from support.cli_helper import assert_one_line_error

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


def _ur5_bytes() -> bytes:
    return get_robot("ur5").table_path.read_bytes()


def test_utf8_with_a_byte_order_mark_loads_as_without(tmp_path):
    """A UTF-8 file with a BOM (as Windows Notepad saves it) gives the same table."""
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + _ur5_bytes())
    table, reference = load_table(path), get_robot("ur5").load_table()
    assert table.rows == reference.rows and table.description == reference.description


def test_utf16_is_named_as_such(tmp_path):
    """A UTF-16 file (Windows 'Unicode'): the error says UTF-16 and the fix."""
    path = tmp_path / "utf16.toml"
    path.write_bytes(_ur5_bytes().decode("utf-8").encode("utf-16"))
    with pytest.raises(TableError, match="the file is UTF-16; save it as UTF-8"):
        load_table(path)


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
@pytest.mark.parametrize("bom", [b"", b"\xef\xbb\xbf"])
def test_toml_error_gives_the_byte_of_its_line_and_column(tmp_path, newline, bom):
    """Not TOML: the byte offset given is the first byte of the bad value (multi-byte text before)."""
    text = newline.join(['name = "caf\u00e9 \u20ac"', "convention = = 2", ""])
    raw = bom + text.encode("utf-8")
    path = tmp_path / "bad.toml"
    path.write_bytes(raw)
    with pytest.raises(TableError) as err:
        load_table(path)
    message = str(err.value)
    offset = raw.index(b"= 2")
    assert f"at byte {offset} (line 2, column 14)" in message and str(path) in message, message


def test_toml_error_at_the_end_gives_the_file_length(tmp_path):
    """An unterminated string: 'at the end of the file (byte N)', N the file's length."""
    path = tmp_path / "cut.toml"
    path.write_bytes(b'name = "abc')
    with pytest.raises(TableError, match=r"at the end of the file \(byte 11\)"):
        load_table(path)
