"""Extreme finite values through every command (1e308 joint values, 1e6 m links, tiny and huge
targets and voxels): a finite answer or one clear line, never a traceback (hypothesis)."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from dh2urdf import ROBOTS, get_robot
from dh2urdf.command import main as dh2urdf_main
from kin import load_robot
from kin.commands import fk, path, preview, workspace

NAMES = tuple(ROBOTS)
EXTREME = st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 0.3, -2.5, 1e3, -1e6, 1e200, 1e308, -1e308])
SETTINGS = settings(
    max_examples=8,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)


def _run(main, argv: list[str], capsys) -> int:
    try:
        code = main(argv)
    except SystemExit as exit:  # argparse's one-line errors
        code = exit.code
    captured = capsys.readouterr()
    assert code in (0, 1, 2), f"{argv=} {code=}"
    assert "Traceback" not in captured.err, captured.err
    if code == 2:
        errors = [line for line in captured.err.splitlines() if "error" in line]
        assert len(errors) == 1, captured.err
    for token in ("nan", "inf"):
        assert f" {token} " not in captured.out.lower(), captured.out
    return code


def _numbers(values) -> list[str]:
    return [repr(float(v)) for v in values]


@pytest.mark.parametrize("name", NAMES)
@SETTINGS
@given(data=st.data())
def test_fk_with_extreme_joint_values(name, data, capsys):
    """kin fk at 1e308 rad and friends: a finite pose (cos and sin of any finite angle)."""
    dof = load_robot(name).nq
    q = data.draw(st.lists(EXTREME, min_size=dof, max_size=dof))
    _run(fk.main, ["--robot", name, "--q", *_numbers(q), "--json"], capsys)


@pytest.mark.parametrize("name", NAMES)
@SETTINGS
@given(
    start=st.lists(EXTREME, min_size=3, max_size=3), end=st.lists(EXTREME, min_size=3, max_size=3)
)
def test_path_between_extreme_points(name, start, end, capsys):
    """kin path between any two points: a path, an unreachable sample (1) or one line (2)."""
    argv = ["--robot", name, "--from", *_numbers(start), "--to", *_numbers(end), "--steps", "4"]
    _run(path.main, [*argv, "--timeout", "5"], capsys)


@pytest.mark.parametrize("voxel", ["1e-300", "1e-3", "0.05", "1e6", "1e300"])
def test_workspace_with_extreme_voxels(voxel, capsys):
    """kin workspace --voxel from 1e-300 to 1e300 m: statistics or one line."""
    _run(workspace.main, ["--robot", "ur5", "--n", "2000", "--voxel", voxel, "--json"], capsys)


@pytest.mark.parametrize("name", ["ur5", "humanoid7", "planar2"])
@SETTINGS
@given(data=st.data())
def test_preview_page_with_extreme_joint_values(name, data, tmp_path_factory, capsys):
    """kin preview --html at extreme joint values: a page or one line."""
    dof = load_robot(name).nq
    q = data.draw(st.lists(EXTREME, min_size=dof, max_size=dof))
    page = tmp_path_factory.mktemp("page") / "p.html"
    _run(preview.main, ["--robot", name, "--q", *_numbers(q), "--html", str(page)], capsys)


@pytest.mark.parametrize("value", ["1e6", "-1e6", "1e12", "1e-300"])
def test_tables_with_giant_links(value, tmp_path, capsys):
    """A table with a 1e6 m (or 1e12 m, 1e-300 m) offset: a URDF and a finite FK, or one line."""
    text = (
        get_robot("ur5")
        .table_path.read_text(encoding="utf-8")
        .replace("d = 0.089159", f"d = {value}")
    )
    table = tmp_path / "giant.toml"
    table.write_text(text, encoding="utf-8")
    out = tmp_path / "giant.urdf"
    code = _run(dh2urdf_main, [str(table), "-o", str(out)], capsys)
    assert (code == 0) == out.exists()
    _run(fk.main, ["--robot", str(table), "--q", *(["0.1"] * 6)], capsys)
    _run(workspace.main, ["--robot", str(table), "--n", "2000", "--json"], capsys)
    assert math.isfinite(float(value))
