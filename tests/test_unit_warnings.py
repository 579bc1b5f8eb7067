"""Unit slips give one warning line that names the value and the likely fix (not an error)."""

from __future__ import annotations

import warnings

import pytest

from dh2urdf import get_robot, load_table
from dh2urdf.exceptions import UnitWarning
from kin.commands import fk, ik


def _table(tmp_path, old: str, new: str):
    text = get_robot("scorbot").table_path.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / "slip.toml"
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def _one_warning(err: str, *needles: str) -> None:
    # A joint value beyond a turn is beyond the limits too: that warning is its own line.
    lines = [line for line in err.splitlines() if "warning:" in line and "limits" not in line]
    assert len(lines) == 1, err
    assert all(needle in lines[0] for needle in needles), lines[0]


def test_degrees_in_a_radian_table(tmp_path, capsys):
    """scorbot's degree values with angle_unit = "rad": alpha -90 rad is named, with the fix."""
    path = _table(tmp_path, 'angle_unit = "deg"', 'angle_unit = "rad"')
    with pytest.warns(UnitWarning, match="field 'alpha': -90 rad"):
        load_table(path)
    assert fk.main(["--robot", str(path), "--q", "0", "0", "0", "0", "0"]) == 0
    _one_warning(capsys.readouterr().err, "kin fk: warning:", 'angle_unit = "deg"')


def test_millimeters_in_a_meter_table(tmp_path, capsys):
    """scorbot's millimeters with length_unit = "m": a 952 m arm, length_unit = "mm" suggested."""
    path = _table(tmp_path, 'length_unit = "mm"', 'length_unit = "m"')
    assert fk.main(["--robot", str(path), "--q", "0", "0", "0", "0", "0", "--deg"]) == 0
    _one_warning(capsys.readouterr().err, "952 m", 'length_unit = "mm"')


@pytest.mark.parametrize(
    ("main", "argv", "needle"),
    [
        (
            ik.main,
            ["--robot", "ur5", "--target", "0.4", "0.1", "0.3", "--rpy", "180", "0", "0"],
            "--rpy value 180",
        ),
        (fk.main, ["--robot", "ur5", "--q", "0", "0", "0", "0", "6.5", "0"], "--q value 6.5"),
    ],
)
def test_degrees_without_deg(main, argv, needle, capsys):
    """--rpy 180 or --q 7 without --deg: one warning line that says --deg; the command runs."""
    assert main(argv) in (0, 1)
    _one_warning(capsys.readouterr().err, needle, "--deg")


def test_shipped_tables_and_radian_values_warn_nothing(capsys):
    """No warning for any shipped table, nor for a turn or less without --deg."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        for name in ("humanoid7", "lab5", "ned5", "panda", "pickplace3", "planar2", "puma560"):
            load_table(get_robot(name).table_path)
        for name in ("scorbot", "ur3", "ur5", "ur10", "xarm7"):
            load_table(get_robot(name).table_path)
    assert (
        ik.main(["--robot", "ur5", "--target", "0.4", "0.1", "0.3", "--rpy", "3.14", "0", "0"]) == 0
    )
    assert "warning" not in capsys.readouterr().err
