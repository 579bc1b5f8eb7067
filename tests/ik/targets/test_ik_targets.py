"""Bad and singular targets, structure recognition, results ordering and the solve_ik.py CLI."""

import json
import math

import numpy as np
import pytest
from support.scripts_helper import exit_code, load_script
from support.solver_caps import NO_CAP

import kin
import kin.ik as ik
from dh2urdf import DHRow, DHTable
from kin.ik import (
    ClosedFormSolver,
    PitchTarget,
    PoseTarget,
    PositionTarget,
    StructureError,
    TargetError,
)
from kin.ik.analytic.five_joint.five_dof import FiveDof
from kin.ik.analytic.registry import recognise


def test_all_names_exist_and_sorted():
    """Every name of ik.__all__ exists and the list is sorted."""
    assert ik.__all__ == sorted(ik.__all__)
    assert all(hasattr(ik, name) for name in ik.__all__)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("name", ["planar2", "pickplace3", "lab5"])
def test_non_finite_target_is_a_target_error_naming_the_field(name, value):
    """NaN or infinite target values are refused when the target is built, the field named."""
    with pytest.raises(TargetError, match=r"position\[\d\] is"):
        PositionTarget([value, 0, 0]) if name != "lab5" else PitchTarget([0.2, value, 0.1], 0.0)
    with pytest.raises(TargetError, match="pitch is"):
        PitchTarget([0.2, 0.0, 0.1], value)
    with pytest.raises(TargetError, match=r"rotation\[1\]\[2\] is"):
        PoseTarget([0.2, 0.0, 0.1], [[1, 0, 0], [0, 1, value], [0, 0, 1]])


def test_target_changed_after_it_was_built_is_an_invalid_target_result():
    """A closed-form target overwritten with a NaN after it was built: status invalid_target."""
    solver = ClosedFormSolver(kin.load_robot("planar2"))
    target = PositionTarget([0.3, 0.1, 0.0])
    with pytest.raises(ValueError, match="read-only"):  # a target cannot change after its check
        target.position[0] = math.inf
    target.position.flags.writeable = True  # unless its array is made writeable again
    target.position[0] = math.inf
    result = solver.solve(target)
    assert not result.success and result.status == "invalid_target"


def test_nearly_orthonormal_rotation_is_snapped_and_a_far_one_refused():
    """A rotation printed with 6 decimals becomes the nearest rotation; a sheared one is refused."""
    angle = 0.7
    exact = np.array(
        [[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]]
    )
    printed = np.round(exact, 6)
    snapped = PoseTarget([0.3, 0, 0.2], printed).rotation
    np.testing.assert_allclose(snapped.T @ snapped, np.eye(3), atol=1e-14)
    assert np.linalg.det(snapped) == pytest.approx(1.0, abs=1e-14)
    assert np.abs(snapped - exact).max() < 1e-6
    with pytest.raises(TargetError, match="not a rotation matrix"):
        PoseTarget([0.3, 0, 0.2], exact + [[0, 0.1, 0], [0, 0, 0], [0, 0, 0]])
    with pytest.raises(TargetError, match="det"):
        PoseTarget([0.3, 0, 0.2], np.diag([1.0, 1.0, -1.0]))


def test_out_of_reach_says_how_far():
    """planar2 (0.3 + 0.2 m) asked for 0.7 m: out of reach by 0.2 m."""
    result = ClosedFormSolver(kin.load_robot("planar2")).solve(PositionTarget([0.7, 0, 0]))
    assert result.status == "out_of_reach"
    assert result.distance_to_workspace == pytest.approx(0.2, abs=1e-12)


def test_inside_inner_hole_and_shoulder_offset_are_out_of_reach():
    """Inside planar2's inner radius (0.1 m) and inside pickplace3's 10 mm offset cylinder."""
    result = ClosedFormSolver(kin.load_robot("planar2")).solve(PositionTarget([0.05, 0, 0]))
    assert result.status == "out_of_reach" and result.distance_to_workspace == pytest.approx(0.05)
    result = ClosedFormSolver(kin.load_robot("pickplace3")).solve(PositionTarget([0.0, 0.004, 0.3]))
    assert result.status == "out_of_reach" and result.distance_to_workspace == pytest.approx(0.006)


def test_fully_stretched_is_singular_with_one_solution():
    """planar2 at exactly 0.5 m: one merged branch, status singular."""
    result = ClosedFormSolver(kin.load_robot("planar2")).solve(PositionTarget([0.5, 0, 0]))
    assert result.status == "singular" and len(result.solutions) == 1
    np.testing.assert_allclose(result.solutions[0].q, [0, 0], atol=1e-12)


def test_on_base_axis_keeps_seed_yaw():
    """lab5 straight up on the base axis: base yaw free, the seed's kept, status singular."""
    solver = ClosedFormSolver(kin.load_robot("lab5"))
    result = solver.solve(PitchTarget([0, 0, 0.46], -math.pi / 2, roll=0.0), seed=[0.3, 0, 0, 0, 0])
    assert result.status == "singular" and result.success
    assert all(s.q[0] == pytest.approx(0.3) for s in result.solutions)
    assert all(s.position_error < 1e-9 for s in result.solutions)


def test_five_dof_pose_out_of_plane_is_reported():
    """A pose whose approach axis leaves the arm plane is out of reach, with the angle named."""
    solver = ClosedFormSolver(kin.load_robot("ned5"))
    result = solver.solve(PoseTarget.from_rpy([0.3, 0, 0.05], [0.3, 1.0, 0.0]))
    assert result.status == "out_of_reach" and "approach axis" in result.message


def test_outside_limits_is_kept_apart():
    """pickplace3 behind itself: only branches with q1 outside [-120, 120] deg: outside_limits."""
    result = ClosedFormSolver(kin.load_robot("pickplace3")).solve(PositionTarget([-0.3, -0.2, 0.1]))
    assert result.status == "outside_limits" and not result.solutions and result.rejected
    assert not any(s.within_limits for s in result.rejected)


def test_wrong_target_kind_raises_target_error():
    """A pitch target for a three-joint arm is a TargetError naming the kinds it takes, in words
    (a full pose is taken: solved where the arm reaches it, else the nearest pose is reported)."""
    robot = kin.load_robot("pickplace3")
    pose = PoseTarget([0.2, 0.0, 0.2], np.eye(3))
    result = ClosedFormSolver(robot).solve(pose)  # its bounded search: not_found
    assert not result.success and "the nearest pose found is" in result.message
    with pytest.raises(TargetError, match="takes a position, ") as raised:
        ik.solve_ik(robot, PitchTarget([0.2, 0.0, 0.2], 0.3))
    assert "PitchTarget" not in str(raised.value) and "position with pitch" in str(raised.value)


def test_position_target_on_a_five_joint_arm_goes_to_the_numeric_solver():
    """A position on a five-joint arm (no closed form for it) is answered by the numeric solver."""
    robot = kin.load_robot("scorbot")
    q = np.array([0.3, -0.4, 0.5, -0.2, 0.1])
    position = kin.Configuration(robot).fk(q).translation
    solver = ik.get_solver(robot)
    assert solver.name == "closed_form:fivedof"
    result = solver.solve(PositionTarget(position), timeout=NO_CAP)
    assert result.success and result.solver == "numeric", f"{result.message=}"
    solution = result.solutions[0]
    assert solution.position_error < 1e-5 and solution.rotation_error is None
    reached = kin.Configuration(robot).fk(solution.q).translation
    assert np.linalg.norm(reached - position) < 1e-5


def _row(i, a=0.0, alpha=0.0, d=0.0):
    return DHRow(i, f"j{i}", "revolute", a, alpha, d, 0.0, -3.0, 3.0, 1.0, 1.0)


def test_structure_error_names_row_and_parameter():
    """A five-joint table with alpha2 = 90 deg is refused, naming row 2 and alpha."""
    rows = (
        _row(1, alpha=math.pi / 2, d=0.1),
        _row(2, a=0.1, alpha=math.pi / 2),
        _row(3, a=0.1),
        _row(4, alpha=math.pi / 2),
        _row(5, d=0.1),
    )
    table = DHTable("bad5", "", "", "standard", rows)
    with pytest.raises(StructureError, match=r"row 2 \('j2'\): alpha = 90 deg"):
        FiveDof.recognise(table)
    with pytest.raises(StructureError, match="4 joints"):
        recognise(DHTable("four", "", "", "standard", rows[:4]))


def test_other_lengths_work_unchanged():
    """A lab5-like table with other lengths is recognised and reads its lengths from the table."""
    rows = (
        _row(1, alpha=math.pi / 2, d=0.2),
        _row(2, a=0.3),
        _row(3, a=0.25),
        _row(4, alpha=math.pi / 2),
        _row(5, d=0.05),
    )
    structure = FiveDof.recognise(DHTable("big5", "", "", "standard", rows))
    assert (structure.link2.length, structure.link3.length, structure.reach) == (0.3, 0.25, 0.05)


def test_cli_json_and_exit_codes(capsys):
    """--json has success, solver and solutions in SI units; 1 when unreachable, 2 for bad input."""
    solve = load_script("solve_ik").main
    assert (
        solve(["--robot", "pickplace3", "--target", "390", "80", "300", "--unit", "mm", "--json"])
        == 0
    )
    out = json.loads(capsys.readouterr().out)
    assert out["success"] and "unit" not in out and out["solver"].startswith("closed_form")
    assert set(out["solutions"][0]) == {
        "q",
        "branch",
        "within_limits",
        "position_error_m",
        "rotation_error_rad",
    }
    assert out["solutions"][0]["rotation_error_rad"] is None  # no orientation was asked for
    assert out["q_units"] == ["rad", "rad", "rad"] and out["time_s"] > 0
    assert solve(["--robot", "planar2", "--target", "2", "0", "0", "--json"]) == 1
    capsys.readouterr()
    for argv in (
        ["--robot", "nope", "--target", "1", "2", "3"],
        ["--robot", "lab5", "--target", "1", "2"],
        ["--robot", "lab5", "--target", "1", "nan", "3", "--pitch", "0"],
        ["--robot", "lab5", "--target", "1", "2", "3", "--unit", "km", "--pitch", "0"],
        ["--robot", "lab5", "--target", "0.2", "0", "0.2", "--pitch", "0", "--seed-q", "1"],
        ["--robot", "pickplace3", "--target", "0.3", "0", "0.2", "--pitch", "0"],
    ):
        assert exit_code(solve, argv) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err, argv


def test_cli_table_all_deg(capsys):
    """--all --deg prints the four pickplace3 branches of 003 Table 5, limits flagged."""
    solve = load_script("solve_ik").main
    assert (
        solve(
            [
                "--robot",
                "pickplace3",
                "--target",
                "390",
                "80",
                "300",
                "--unit",
                "mm",
                "--deg",
                "--all",
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "10.1529" in out and "-166.9685" in out and out.count("OUT") == 2
