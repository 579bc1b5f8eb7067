"""Numeric IK of humanoid7: round trips judged by Pinocchio, limits, mink, the paper's NR."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from support.solver_caps import NO_CAP

from kin import Configuration, load_robot
from kin.ik.exceptions import TargetError
from kin.ik.numeric.damped_newton import damped_newton
from kin.ik.numeric.differential_ik import DifferentialIK, tool_pose_mujoco
from kin.ik.numeric.newton_raphson import newton_raphson
from kin.ik.numeric.numeric_target import (
    POSITION_TOLERANCE,
    ROTATION_TOLERANCE,
    NumericTarget,
    measure,
)
from kin.ik.numeric.seed_table import build_seed_table
from kin.ik.numeric.solver import NumericIK, numeric_ik_for, solve_numeric

ROBOT = "humanoid7"
TIMEOUT = NO_CAP  # [s]: no load decides an answer; the first solution returns at once
#: The stages of the numeric pipeline (``IKResult.method``).
METHODS = ("closed_form_free_joint", "seed_table", "damped_newton", "random_restart", "mink_qp")


@pytest.fixture(scope="module")
def robot():
    return load_robot(ROBOT)


@pytest.fixture(scope="module")
def solver():
    return numeric_ik_for(ROBOT)


def random_q(robot, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(robot.lower, robot.upper, size=(n, robot.nq))


def tool_pose(robot, q: np.ndarray) -> pin.SE3:
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, q)
    return pin.updateFramePlacement(robot.model, data, robot.model.getFrameId("tool")).copy()


def check_solution(robot, result, target: NumericTarget) -> None:
    """The result is a success that Pinocchio confirms independently."""
    assert result.success, f"{result.message=}"
    q = result.solutions[0].q
    verdict = measure(robot, robot.model.createData(), q, target)
    assert verdict.within_limits, f"{q=}"
    assert verdict.position_error < POSITION_TOLERANCE, f"{verdict=}"
    assert verdict.rotation_error < ROTATION_TOLERANCE, f"{verdict=}"
    expected = None if target.position_only else pytest.approx(verdict.rotation_error, abs=1e-12)
    assert result.solutions[0].rotation_error == expected
    assert result.solutions[0].position_error == pytest.approx(verdict.position_error, abs=1e-12)


def test_mujoco_tool_pose_matches_pinocchio(robot):
    """MuJoCo's tool pose on the same URDF equals Pinocchio's (joint order included)."""
    ik = DifferentialIK(robot)
    names = tuple(ik.mj_model.joint(i).name for i in range(ik.mj_model.njnt))
    assert names == robot.joint_names
    for q in random_q(robot, 50, 1):
        expected = tool_pose(robot, q)
        got = tool_pose_mujoco(ik, q)
        assert np.abs(got.homogeneous - expected.homogeneous).max() < 1e-9, f"{q=}"


@pytest.mark.parametrize("position_only", [False, True])
def test_round_trip_reaches_every_target(robot, solver, position_only):
    """FK(q) -> IK from q = 0 gives a verified solution inside the limits, for 50 random q."""
    for q in random_q(robot, 50, 2):
        target = NumericTarget.from_se3(tool_pose(robot, q), position_only=position_only)
        result = solver.solve(target, seed=np.zeros(robot.nq), timeout=TIMEOUT)
        check_solution(robot, result, target)
        assert result.solver == "numeric"
        assert result.method in METHODS, f"{result.method=}"
        assert 0.0 < result.time < TIMEOUT
        if result.method == "closed_form_free_joint":
            assert result.iterations == 0, f"{result.iterations=}"
        else:
            assert result.iterations >= 1, f"{result.method=} {result.iterations=}"
        if position_only:
            assert result.solutions[0].rotation_error is None
        else:
            assert result.solutions[0].rotation_error < ROTATION_TOLERANCE


def test_accepts_the_closed_form_target_types(robot, solver):
    """ik.target's PoseTarget and PositionTarget are solved like a NumericTarget."""
    from kin.ik.targets.target import PoseTarget, PositionTarget

    pose = tool_pose(robot, random_q(robot, 1, 3)[0])
    full = solver.solve(PoseTarget.from_matrix(pose), timeout=TIMEOUT)
    check_solution(robot, full, NumericTarget.from_se3(pose))
    position = solver.solve(PositionTarget(pose.translation), timeout=TIMEOUT)
    check_solution(robot, position, NumericTarget.from_se3(pose, position_only=True))


def test_posture_preference_pulls_the_redundancy(robot, solver):
    """Two posture preferences give two solutions of the same target, each nearer its own."""
    q_true = np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2])
    pose = tool_pose(robot, q_true)
    postures = (
        np.array([0.8, 0.4, -0.8, 0.8, 0.6, -0.3, 0.2]),
        np.array([-0.2, 0.4, 0.4, 0.8, -0.4, -0.3, 0.2]),
    )
    solutions = []
    for posture in postures:
        target = NumericTarget.from_arrays(pose.translation, None, posture)
        result = solver.solve(target, timeout=TIMEOUT)
        check_solution(robot, result, target)
        solutions.append(result.solutions[0].q)
    assert np.linalg.norm(solutions[0] - postures[0]) < np.linalg.norm(solutions[1] - postures[0])
    assert np.linalg.norm(solutions[1] - postures[1]) < np.linalg.norm(solutions[0] - postures[1])


def test_out_of_reach_target_fails_honestly(robot, solver):
    """A target beyond the links laid end to end is out_of_reach at once, with the distance."""
    result = solver.solve(NumericTarget.from_arrays([1.2, 0.0, 0.0]), timeout=0.05)
    assert not result.success
    assert result.status == "out_of_reach"
    # humanoid7 stretched: 9.65 + 28.774 + 27.98 + 20 cm (Table I) from the shoulder point
    assert result.distance_to_workspace == pytest.approx(1.2 - 0.86404, abs=1e-9)
    assert result.best is None and result.iterations == 0


def test_out_of_reach_within_the_bound_gives_the_best_configuration():
    """ur5 at 1.1 m (reach 1.038 m, links end to end 1.19 m): searched; the closest attempt."""
    ur5 = load_robot("ur5")
    result = NumericIK(ur5).solve(NumericTarget.from_arrays([1.1, 0.0, 0.1]))  # the default cap
    assert result.status == "out_of_reach"
    best = result.best
    assert best is not None and best.within_limits
    assert best.position_error >= result.distance_to_workspace - 1e-9
    stretched = Configuration(ur5, best.q).transform_frame_to_world("tool").translation
    assert np.linalg.norm(stretched - [1.1, 0.0, 0.1]) == pytest.approx(best.position_error)


def test_solve_numeric_one_call(robot):
    """solve_numeric takes a position [m] and a rotation and returns a verified result."""
    pose = tool_pose(robot, random_q(robot, 1, 4)[0])
    result = solve_numeric(ROBOT, pose.translation, pose.rotation, timeout=TIMEOUT)
    check_solution(robot, result, NumericTarget.from_se3(pose))


def test_invalid_targets_raise(robot, solver):
    """A non-rotation matrix or a wrong-size position is a TargetError naming the value."""
    with pytest.raises(TargetError, match="rotation"):
        NumericTarget.from_arrays([0.3, 0.0, 0.0], np.ones((3, 3)))
    with pytest.raises(TargetError, match="shape"):
        NumericTarget.from_arrays([0.3, 0.0])
    with pytest.raises(TargetError, match="finite"):
        NumericTarget.from_arrays([0.3, np.nan, 0.0])


def test_damped_newton_stays_inside_the_limits(robot):
    """Clamped damped Newton never leaves the limits, even toward an out-of-limits answer."""
    model, data = robot.model, robot.model.createData()
    fid = model.getFrameId("tool")
    for q in random_q(robot, 20, 5):
        q_far = q * 1.8  # mostly outside the limits
        pose = tool_pose(robot, q_far)
        outcome = damped_newton(model, data, fid, q, pose.translation, pose.rotation)
        assert np.all(outcome.q >= model.lowerPositionLimit)
        assert np.all(outcome.q <= model.upperPositionLimit)


def test_damped_newton_converges_near_a_solution(robot):
    """From 0.1 rad away, damped Newton converges within 10 steps below the tolerances."""
    model, data = robot.model, robot.model.createData()
    fid = model.getFrameId("tool")
    for q in random_q(robot, 20, 6) * 0.8:
        pose = tool_pose(robot, q)
        outcome = damped_newton(
            model, data, fid, q + 0.1, pose.translation, pose.rotation, max_iterations=10
        )
        assert outcome.converged, f"{outcome=}"
        assert outcome.position_error < 1e-6 and outcome.rotation_error < 1e-5


@pytest.mark.parametrize("qp_solver", ["daqp", "osqp"])
def test_mink_converges_within_max_iter(robot, qp_solver):
    """mink QP steps alone reach a nearby target below the tolerances, inside the limits."""
    ik = DifferentialIK(robot, solver=qp_solver)
    q_true = np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2])
    pose = tool_pose(robot, q_true)
    ik.set_target(NumericTarget.from_se3(pose))
    outcome = ik.solve(q_true + 0.15, max_iterations=60)
    assert outcome.converged, f"{qp_solver=} {outcome=}"
    assert np.all(np.abs(outcome.q) <= np.pi / 2)


def test_velocity_limited_step(robot):
    """step() moves every joint at most velocity_limit * dt; a reached target stays put."""
    ik = DifferentialIK(robot, velocity_limit=1.0)
    q0 = np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2])
    ik.set_target(NumericTarget.from_se3(tool_pose(robot, q0 + 0.3)))
    q1 = ik.step(q0, dt=0.01)
    assert np.abs(q1 - q0).max() <= 0.01 + 1e-9
    assert np.abs(q1 - q0).max() > 1e-4
    ik.set_target(NumericTarget.from_se3(tool_pose(robot, q0)))
    ik.posture_task.set_target(q0)
    q2 = ik.step(q0, dt=0.01)
    assert np.abs(q2 - q0).max() < 1e-8


def test_seed_table_finds_its_own_samples(robot):
    """Querying a sample's own pose returns that sample first (pose and position queries)."""
    table = build_seed_table(robot, size=500, seed=7)
    for i in (0, 123, 499):
        rotation = table.rotations[i].reshape(3, 3)
        assert table.nearest(table.positions[i], rotation, k=3)[0] == i
        assert table.nearest(table.positions[i], None, k=1)[0] == i


def test_newton_raphson_reproduces_the_paper_outside_the_limits(robot):
    """The paper's NR reaches Table IX case 2's position (|e| < 1e-5 cm) but outside the limits."""
    result = newton_raphson(robot, np.array([-25.0268, -1.213, 7.236]) * 0.01)
    assert not result.success
    assert result.status == "outside_limits"
    best = result.best
    assert best is not None and not best.within_limits
    assert best.position_error < 1e-7  # 1e-5 cm
    assert np.isfinite(best.q).all()


def test_newton_raphson_at_the_singular_home_does_not_blow_up(robot):
    """From q = 0, a target on the stretched line gives a 'singular' stop with finite q."""
    result = newton_raphson(robot, [0.5, 0.0, 0.0])
    assert result.status == "singular"
    assert np.isfinite(result.best.q).all()
    assert np.abs(result.best.q).max() < 1e-9
    off_line = newton_raphson(robot, [0.5, 0.2, 0.1])
    assert np.isfinite(off_line.best.q).all()
    assert off_line.best.position_error < 1e-7, f"{off_line.message=}"


def test_numeric_solver_registered_for_humanoid7(robot):
    """ik.dispatch gives humanoid7 the numeric solver."""
    from kin.ik.dispatch import get_solver

    solver = get_solver(robot)
    assert isinstance(solver, NumericIK)
    assert solver.name == "numeric"
    assert solver.closed_form is not None


def test_robot_from_a_table_file_gets_its_own_seed_table(tmp_path):
    """A robot loaded from a table path builds its own table (not the registry's)."""
    from dh2urdf import get_robot

    path = tmp_path / "arm7.toml"
    path.write_text(get_robot(ROBOT).table_path.read_text().replace('"humanoid7"', '"arm7"'))
    robot = load_robot(str(path))
    solver = NumericIK(robot, table_size=2000)
    pose = tool_pose(robot, np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2]))
    result = solver.solve(NumericTarget.from_se3(pose), timeout=TIMEOUT)
    check_solution(robot, result, NumericTarget.from_se3(pose))
    assert len(solver.table) == 2000


def _solve_ik_main():
    from support.scripts_helper import load_script

    return load_script("solve_ik").main


def test_cli_humanoid7_full_pose_json(capsys):
    """solve_ik.py --robot humanoid7 --rpy --json: success, q in radians, errors in m / rad."""
    import json

    robot = load_robot(ROBOT)
    pose = tool_pose(robot, np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2]))
    rpy = pin.rpy.matrixToRpy(pose.rotation)
    argv = [
        "--robot",
        ROBOT,
        "--target",
        *map(str, pose.translation * 100),
        "--unit",
        "cm",
        "--rpy",
        *map(str, rpy),
        "--timeout",
        "500",
        "--json",
    ]
    assert _solve_ik_main()(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["success"] and "unit" not in out and out["q_units"] == ["rad"] * 7
    solution = out["solutions"][0]
    assert solution["within_limits"] and solution["position_error_m"] < 1e-5
    assert solution["rotation_error_rad"] < 1e-4
    assert out["time_s"] > 0
    # iterations count Newton steps: none when the closed form with a free joint answered
    newton = ("seed_table", "damped_newton", "random_restart", "mink_qp")
    assert (out["iterations"] > 0) == (out["method"] in newton), out


def test_cli_humanoid7_unreachable_exits_1_with_best(capsys):
    """An unreachable target prints the best configuration and its error, exit code 1."""
    assert _solve_ik_main()(["--robot", ROBOT, "--target", "1.2", "0", "0", "--timeout", "20"]) == 1
    out = capsys.readouterr().out
    assert "out_of_reach" in out and "iterations:" in out and " ms" in out
    assert "distance to the workspace: 0.33" in out  # 1.2 m against a 0.864 m reach


def test_cli_nr_reports_the_limits(capsys):
    """--solver nr reaches Table IX case 1 outside the limits: exit 1, status outside_limits."""
    argv = [
        "--robot",
        ROBOT,
        "--target",
        "-37.457",
        "-2.759",
        "18.861",
        "--unit",
        "cm",
        "--solver",
        "nr",
        "--json",
    ]
    import json

    assert _solve_ik_main()(argv) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "outside_limits" and out["solver"] == "nr"
    assert out["rejected"][0]["position_error_m"] < 1e-7


@pytest.mark.parametrize(
    "extra",
    [
        ["--quat", "1", "0", "0", "0", "--rpy", "0", "0", "0"],
        ["--position-only", "--rpy", "0", "0", "0"],
        ["--quat", "0", "0", "0", "0"],
        ["--solver", "nr", "--rpy", "0", "0", "0"],
    ],
)
def test_cli_bad_input_exits_2(capsys, extra):
    """Contradictory or invalid orientation options: exit 2, one line on stderr."""
    argv = ["--robot", ROBOT, "--target", "0.5", "0", "0", *extra]
    from support.scripts_helper import exit_code

    assert exit_code(_solve_ik_main(), argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_cli_quaternion_equals_rpy(capsys):
    """--quat and the equivalent --rpy give the same verified target."""
    import json

    robot = load_robot(ROBOT)
    pose = tool_pose(robot, np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2]))
    quat = pin.Quaternion(pose.rotation)
    position = list(map(str, pose.translation))
    argv = [
        "--robot",
        ROBOT,
        "--target",
        *position,
        "--timeout",
        "500",
        "--json",
        "--quat",
        *map(str, (quat.w, quat.x, quat.y, quat.z)),
    ]
    assert _solve_ik_main()(argv) == 0
    solution = json.loads(capsys.readouterr().out)["solutions"][0]
    verdict = measure(
        robot, robot.model.createData(), np.array(solution["q"]), NumericTarget.from_se3(pose)
    )
    assert verdict.on_target() and verdict.within_limits


def test_bench_runs_on_a_few_targets(capsys):
    """bench_ik_humanoid7.py prints a table with our four rows (peers skipped)."""
    from support.scripts_helper import load_script

    assert load_script("bench_ik_humanoid7").main(["--n", "5", "--peers", "none"]) == 0
    out = capsys.readouterr().out
    rows = [line for line in out.splitlines() if line.startswith("ours")]
    assert len(rows) == 4 and all("100.0%" in row for row in rows)


def test_reproduction_section_has_four_rows_per_case():
    """The Table IX section: 5 cases x 4 rows; cases 1 and 5 reachable inside the limits."""
    from reproduction.ik_humanoid7 import humanoid7_ik_sections

    (section,) = humanoid7_ik_sections()
    assert len(section.rows) == 20
    ours = [row for row in section.rows if "our solver" in row.label]
    assert [row.verdict for row in ours] == [
        "reproduced",
        "flagged",
        "flagged",
        "flagged",
        "reproduced",
    ]


def test_non_finite_target_is_a_target_error_naming_the_field(solver):
    """A PositionTarget with a NaN is refused when built: a TargetError naming position[1]."""
    from kin.ik.targets.target import PositionTarget

    with pytest.raises(TargetError, match=r"position\[1\] is nan"):
        PositionTarget([0.3, float("nan"), 0.0])


def test_target_changed_after_it_was_built_is_an_invalid_target_result(solver):
    """A target whose array is overwritten with a NaN later gives status invalid_target."""
    from kin.ik.targets.target import PositionTarget

    target = PositionTarget([0.3, 0.0, 0.0])
    with pytest.raises(ValueError, match="read-only"):  # a target cannot change after its check
        target.position[1] = float("nan")
    target.position.flags.writeable = True  # unless its array is made writeable again
    target.position[1] = float("nan")
    result = solver.solve(target)
    assert not result.success and result.status == "invalid_target"


def test_pitch_target_is_rejected(solver):
    """A PitchTarget (five-joint arms) is a TargetError naming the accepted kinds."""
    from kin.ik.targets.target import PitchTarget

    with pytest.raises(
        TargetError, match=r"takes a position, .*full pose target, not a position with pitch"
    ):
        solver.solve(PitchTarget([0.3, 0.0, 0.0], 0.5))


def test_bench_targets_are_not_seed_table_samples(robot):
    """The seed table draws from a stream of its own: a default_rng(seed) target is never a sample."""
    table = numeric_ik_for(ROBOT).table
    for seed in (0, 1):
        for q in random_q(robot, 20, seed):
            pose = tool_pose(robot, q)
            (i,) = table.nearest(pose.translation, pose.rotation, k=1)
            assert np.abs(table.q[i] - q).max() > 1e-3, f"{seed=} {q=}"


def test_seed_table_ranking_equals_the_embedding_distance(robot):
    """The grid's one-product ranking gives the plain embedding distances (pose and position)."""
    table = build_seed_table(robot, 4000)
    rng = np.random.default_rng(7)
    for i in rng.choice(len(table), 20, replace=False):
        position = table.positions[i] + rng.normal(0.0, 0.01, 3)
        rotation = pin.exp3(rng.normal(0.0, 1.0, 3))
        for target_rotation in (rotation, None):
            found = table.ranked(position, target_rotation)
            assert found is not None, f"{position=}"
            indices, distances = found
            expected = np.sum((table.positions[indices] - position) ** 2, axis=1)
            if target_rotation is not None:
                r = table.rotations[indices] - target_rotation.reshape(-1)
                expected += table.rotation_weight**2 * np.sum(r * r, axis=1)
            np.testing.assert_allclose(distances, expected, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize("position_only", [False, True])
def test_success_errors_are_pinocchios_at_the_returned_q(robot, solver, position_only):
    """The reported errors of a success are Pinocchio's at the returned q, which is a copy."""
    for q in random_q(robot, 20, 8):
        pose = tool_pose(robot, q)
        target = NumericTarget.from_se3(pose, position_only=position_only)
        seed = np.zeros(robot.nq)
        result = solver.solve(target, seed=seed, timeout=TIMEOUT)
        check_solution(robot, result, target)
        solution = result.solutions[0]
        verdict = measure(robot, robot.model.createData(), solution.q, target)
        expected = None if position_only else pytest.approx(verdict.rotation_error, abs=1e-12)
        assert solution.rotation_error == expected
        assert solution.q is not seed and not np.shares_memory(solution.q, seed)
        assert not np.shares_memory(solution.q, solver.table.q)
        np.testing.assert_array_equal(seed, np.zeros(robot.nq))


def test_damped_newton_gives_up_when_the_error_stops_halving(robot):
    """With patience, a start whose error stalls (target out of reach) stops early."""
    model, data = robot.model, robot.model.createData()
    fid = model.getFrameId(robot.tool_frame)
    far = np.array([5.0, 0.0, 0.0])  # [m], far outside the reach
    q0 = np.zeros(robot.nq)
    patient = damped_newton(model, data, fid, q0, far, None, max_iterations=30, patience=3)
    stubborn = damped_newton(model, data, fid, q0, far, None, max_iterations=30)
    assert not patient.converged and not stubborn.converged
    assert patient.iterations < 30, f"{patient.iterations=}"
    assert stubborn.iterations == 30, f"{stubborn.iterations=}"


@pytest.mark.parametrize("position_only", [False, True])
def test_damped_newton_leaves_the_start_untouched(robot, position_only):
    """The start array is neither written nor returned (table rows are starts)."""
    model, data = robot.model, robot.model.createData()
    fid = model.getFrameId(robot.tool_frame)
    q_goal = random_q(robot, 1, 9)[0]
    pose = tool_pose(robot, q_goal)
    q0 = q_goal + 0.05
    before = q0.copy()
    rotation = None if position_only else pose.rotation
    outcome = damped_newton(model, data, fid, q0, pose.translation, rotation, max_iterations=20)
    assert outcome.converged, f"{outcome=}"
    assert outcome.q is not q0
    np.testing.assert_array_equal(q0, before)


def test_posture_of_the_wrong_size_is_a_target_error(solver):
    """A posture with 3 values for a 7-joint arm: TargetError naming the size, no NumPy error."""
    target = NumericTarget.from_arrays([0.3, 0.1, 0.2], posture=[0.1, 0.2, 0.3])
    with pytest.raises(TargetError, match="posture of 'humanoid7' must have 7 values, got 3"):
        solver.solve(target)
