"""Scripts of the foundation: export_urdf, generate_urdfs --check, fk (output and bad input)."""

import json

import numpy as np
import pytest
from support.scripts_helper import exit_code, load_script

from dh2urdf import robot_names


def test_generate_urdfs_check_passes_on_committed_files(capsys):
    """The committed urdf/*.urdf are what the tables produce."""
    assert load_script("generate_urdfs").main(["--check"]) == 0


def test_generate_urdfs_check_fails_on_stale_file(tmp_path, monkeypatch):
    """--check exits 1 when a committed URDF differs from its table."""
    from dh2urdf import ROBOTS

    robot = ROBOTS["planar2"]
    stale = tmp_path / "planar2.urdf"
    stale.write_text(robot.urdf_path.read_text().replace("0.3", "0.31", 1))
    monkeypatch.setattr(
        type(robot), "urdf_path", property(lambda self: tmp_path / f"{self.name}.urdf")
    )
    for name in robot_names():
        if name != "planar2":
            (tmp_path / f"{name}.urdf").write_text(ROBOTS[name].load_table().name)
    assert load_script("generate_urdfs").main(["--check"]) == 1


def test_export_urdf_from_table_path_matches_committed(tmp_path):
    """Exporting a table file gives the same text as the committed URDF of that robot."""
    from dh2urdf import ROBOTS

    out = tmp_path / "scorbot.urdf"
    assert load_script("export_urdf").main([str(ROBOTS["scorbot"].table_path), "-o", str(out)]) == 0
    assert out.read_text() == ROBOTS["scorbot"].urdf_path.read_text()


def test_fk_json_home_pose_of_scorbot(capsys):
    """fk.py --json at q = 0 gives the SCORBOT home (603, 0, 349) mm with approach along +x."""
    assert (
        load_script("fk").main(
            ["--robot", "scorbot", "--q", "0", "0", "0", "0", "0", "--unit", "mm", "--json"]
        )
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert "unit" not in out and out["q_units"] == ["rad"] * 5  # JSON is SI, and says so
    np.testing.assert_allclose(out["position_m"], [0.603, 0.0, 0.349], atol=1e-12)
    np.testing.assert_allclose(np.array(out["rotation"])[:, 2], [1.0, 0.0, 0.0], atol=1e-12)


def test_fk_degrees_equal_radians(capsys):
    """--deg converts revolute joint values: 90 deg gives the same pose as pi/2 rad."""
    fk = load_script("fk")
    fk.main(["--robot", "ur5", "--q", "0", "90", "0", "0", "0", "0", "--deg", "--json"])
    deg = json.loads(capsys.readouterr().out)
    fk.main(["--robot", "ur5", "--q", "0", str(np.pi / 2), "0", "0", "0", "0", "--json"])
    rad = json.loads(capsys.readouterr().out)
    np.testing.assert_allclose(deg["position_m"], rad["position_m"], atol=1e-12)
    np.testing.assert_allclose(deg["q"], rad["q"], atol=1e-15)  # radians under "rad"


def test_fk_warns_outside_limits(capsys):
    """A joint value outside its limits is computed but warned about on stderr."""
    assert (
        load_script("fk").main(
            ["--robot", "humanoid7", "--q", "2", "0", "0", "0", "0", "0", "0", "--json"]
        )
        == 0
    )
    captured = capsys.readouterr()
    assert "shoulder_yaw" in captured.err and "outside its limits" in captured.err
    assert json.loads(captured.out)["within_limits"] is False


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["--robot", "nope", "--q", "0"], "known robots: humanoid7"),
        (["--robot", "ur5", "--q", "0", "0"], "--q needs 6 values for 'ur5'"),
        (["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "nan"], "not a finite number"),
        (["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "x"], "not a number"),
        (["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0", "--unit", "km"], "invalid choice"),
        (
            ["--robot", "ur5", "--q", "0", "0", "0", "0", "0", "0", "--frame", "nope"],
            "available frames",
        ),
        (["--robot", "missing.toml", "--q", "0"], "missing.toml"),
    ],
)
def test_fk_bad_input_exits_2_with_one_line(argv, needle, capsys):
    """Bad input: exit code 2, exactly one line on stderr naming the problem, no traceback."""
    assert exit_code(load_script("fk").main, argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert needle in err and "Traceback" not in err and err.startswith("fk.py: error:")
