"""Numeric IK of redundant targets starts from the caller's seed: the answer is the one near it.

A position target on a 5-, 6- or 7-joint arm has many solutions; a caller that gives its current
joint vector (a user, a Cartesian path) expects the nearest one, not a seed-table sample's branch.
Every answer is re-checked by :func:`kin.batch_forward_kinematics` (NumPy DH products, not the
solver's Pinocchio model).
"""

from __future__ import annotations

import numpy as np
import pytest
from support.solver_caps import NO_CAP

from kin import batch_forward_kinematics, load_robot
from kin.ik import ClosedFormSolver, PoseTarget, PositionTarget
from kin.ik.numeric.numeric_target import NumericTarget
from kin.ik.numeric.solver import NumericIK, numeric_ik_for

TIMEOUT = NO_CAP  # [s]: no load decides an answer; the first start answers
#: Targets per robot.
COUNT = 50
#: Largest change of a joint from the seed to the joint vector whose tool is the target [rad].
PERTURBATION = 0.05
#: Largest change of a joint from the seed to the answer [rad].
NEAR = 0.5
#: Largest tool position error of an answer, by the independent FK [m].
POSITION_TOL = 1e-5
#: Largest tool rotation error of an answer, by the independent FK (Frobenius norm) [1].
ROTATION_TOL = 1e-4
#: 7-joint arms with a free-joint closed form (stage 0 answers first from the seed).
SEVEN_JOINT = ("humanoid7", "panda", "xarm7")


def seeds_and_poses(
    robot, seed: int, perturbation: float = PERTURBATION
) -> tuple[np.ndarray, np.ndarray]:
    """Seeds inside the limits and the tool poses (4 x 4) of the seeds moved by ``perturbation``.

    The moved joint vectors stay inside the limits: each target has a solution within
    ``perturbation`` [rad] of its seed (checked here by the independent FK).
    """
    rng = np.random.default_rng(seed)
    margin = 2 * perturbation
    seeds = rng.uniform(robot.lower + margin, robot.upper - margin, size=(COUNT, robot.nq))
    near = seeds + rng.uniform(-perturbation, perturbation, size=seeds.shape)
    assert np.all(near >= robot.lower) and np.all(near <= robot.upper)
    return seeds, batch_forward_kinematics(robot.table, near)


def seeds_and_targets(robot, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Seeds inside the limits and the tool positions [m] of the seeds moved by PERTURBATION."""
    seeds, poses = seeds_and_poses(robot, seed)
    return seeds, poses[:, :3, 3]


def check_near_seed(robot, result, seed: np.ndarray, position: np.ndarray) -> None:
    """A verified answer inside the limits, near the seed, on the target by the independent FK."""
    assert result.success, f"{robot.name=} {result.message=}"
    q = result.solutions[0].q
    assert np.all(q >= robot.lower) and np.all(q <= robot.upper), f"{robot.name=} {q=}"
    moved = float(np.abs(q - seed).max())
    assert moved < NEAR, f"{robot.name=} {seed=} {q=} {moved=} {result.message=}"
    tool = batch_forward_kinematics(robot.table, q)[0, :3, 3]
    error = float(np.linalg.norm(tool - position))
    assert error < POSITION_TOL, f"{robot.name=} {q=} {error=}"


@pytest.mark.parametrize("name", ["ur5", "lab5", "panda", "xarm7"])
def test_seed_is_the_first_start_of_a_position_target(name):
    """A position target near the seed's tool gives the answer near the seed, not a sample's."""
    robot = load_robot(name)
    solver = numeric_ik_for(name)
    seeds, positions = seeds_and_targets(robot, 11)
    for seed, position in zip(seeds, positions, strict=True):
        result = solver.solve(PositionTarget(position), seed=seed, timeout=TIMEOUT)
        check_near_seed(robot, result, seed, position)
        assert result.method == "damped_newton", f"{robot.name=} {result.message=}"


@pytest.mark.parametrize("perturbation", [0.05, 0.3])
@pytest.mark.parametrize("kind", ["position", "pose"])
@pytest.mark.parametrize("name", SEVEN_JOINT)
def test_seven_joint_answer_stays_near_the_seed(name, kind, perturbation):
    """On a 7R arm with a free-joint closed form, a target near the seed's tool is answered near it.

    The target is a position or a full pose: the tool of the seed moved by up to ``perturbation``
    per joint, a joint vector inside the limits (so a solution that near exists). The answer is
    within NEAR of the seed, or 2.5 ``perturbation`` (damped Newton's minimum-norm steps from the
    seed land up to about 2 ``perturbation`` away, largest joint change), not on a far branch
    of the closed form (the seed's free joint kept) or a seed-table sample's. Full poses (and
    humanoid7's positions) are answered by the closed-form stage, checked with ``near_seed``.
    """
    robot = load_robot(name)
    # Panda's and xArm7's closed form takes full poses only: their positions go to damped Newton,
    # near the seed by default; the closed-form stage checks its answer with near_seed.
    default = kind == "position" and name != "humanoid7"
    solver = numeric_ik_for(name) if default else NumericIK(robot, near_seed=True)
    seeds, poses = seeds_and_poses(robot, 13, perturbation)
    near = max(NEAR, 2.5 * perturbation)
    far = []
    for seed, pose in zip(seeds, poses, strict=True):
        position, rotation = pose[:3, 3], pose[:3, :3]
        target = PositionTarget(position) if kind == "position" else PoseTarget(position, rotation)
        result = solver.solve(target, seed=seed, timeout=TIMEOUT)
        assert result.success, f"{name=} {seed=} {result.message=}"
        q = result.solutions[0].q
        assert np.all(q >= robot.lower) and np.all(q <= robot.upper), f"{name=} {q=}"
        tool = batch_forward_kinematics(robot.table, q)[0]
        assert float(np.linalg.norm(tool[:3, 3] - position)) < POSITION_TOL, f"{name=} {q=}"
        if kind == "pose":
            assert float(np.linalg.norm(tool[:3, :3] - rotation)) < ROTATION_TOL, f"{name=} {q=}"
        moved = float(np.abs(q - seed).max())
        if moved >= near:
            far.append((round(moved, 2), result.message))
    assert not far, f"{name=} {kind=} {perturbation=}: {len(far)} of {COUNT} far: {far}"


@pytest.mark.parametrize("name", ["ur5", "lab5"])
def test_seed_and_posture_of_the_closed_form_solver(name):
    """The closed-form solver's numeric fallback (seed = posture) answers near the seed."""
    robot = load_robot(name)
    solver = ClosedFormSolver(robot)
    seeds, positions = seeds_and_targets(robot, 12)
    for seed, position in zip(seeds, positions, strict=True):
        result = solver.solve(PositionTarget(position), seed=seed, timeout=TIMEOUT)
        check_near_seed(robot, result, seed, position)


def test_far_target_is_reached_from_the_seed():
    """A target 1 m from the seed's tool is reached from the seed itself, within its budget.

    The seed table's branch was 7.3 rad from the seed; the nearest solution that 3000 random
    starts find is 2.03 rad away (largest joint change).
    """
    robot = load_robot("ur5")
    seed = np.array([0.0, -1.0, 1.0, 0.0, 1.0, 0.0])
    position = np.array([0.3, 0.2, 0.4])
    result = ClosedFormSolver(robot).solve(PositionTarget(position), seed=seed, timeout=TIMEOUT)
    assert result.success, f"{result.message=}"
    assert result.method == "near_seed", f"{result.message=}"  # issue 43: the closed form's route
    q = result.solutions[0].q
    assert float(np.abs(q - seed).max()) < 2.5, f"{q=}"
    tool = batch_forward_kinematics(robot.table, q)[0, :3, 3]
    assert float(np.linalg.norm(tool - position)) < POSITION_TOL, f"{q=}"


def test_posture_start_converges_within_its_budget():
    """With a posture, the run from the posture converges where it used to stall (1 cm pull)."""
    robot = load_robot("ur5")
    solver = numeric_ik_for("ur5")
    seed = np.array([0.0, -1.0, 1.0, 0.0, 1.0, 0.0])
    target = NumericTarget.from_arrays([0.3, 0.2, 0.4], None, posture=seed)
    result = solver.solve(target, timeout=TIMEOUT)
    assert result.success, f"{result.message=}"
    assert "preferred posture" in result.message, f"{result.message=}"
    assert result.iterations <= solver.newton_iterations, f"{result.iterations=}"
    q = result.solutions[0].q
    tool = batch_forward_kinematics(robot.table, q)[0, :3, 3]
    assert float(np.linalg.norm(tool - target.position)) < POSITION_TOL, f"{q=}"


def test_kin_ik_seed_q_answers_near_the_seed():
    """``kin ik --seed-q`` uses near_seed: a humanoid7 position whose default answer (the
    closed form at the seed's free joint) lies more than 1 rad from the seed comes back near it."""
    import json

    from support.cli_helper import run

    robot = load_robot("humanoid7")
    seeds, poses = seeds_and_poses(robot, 13, 0.3)
    default = NumericIK(robot)
    for seed, pose in zip(seeds, poses, strict=True):
        answer = default.solve(PositionTarget(pose[:3, 3]), seed=seed, timeout=TIMEOUT)
        if float(np.abs(answer.solutions[0].q - seed).max()) > 1.0:
            break
    else:
        pytest.fail("no target whose default answer is far from the seed: the test shows nothing")
    argv = ["ik", "--robot", "humanoid7", "--target", *map(repr, pose[:3, 3].tolist()),
            "--seed-q", *map(repr, seed.tolist()), "--json"]  # fmt: skip
    done = run(argv)
    assert done.returncode == 0, done.stderr
    q = np.array(json.loads(done.stdout)["solutions"][0]["q"])
    assert float(np.abs(q - seed).max()) < NEAR, f"{seed=} {q=}"
    tool = batch_forward_kinematics(robot.table, q)[0, :3, 3]
    assert float(np.linalg.norm(tool - pose[:3, 3])) < POSITION_TOL


def test_commands_and_paths_ask_for_answers_near_the_seed():
    """The kin commands' and the paths' numeric solvers have near_seed; solve_ik's default not."""
    from kin.commands.solver_choice import choose_solver
    from kin.ik import get_solver
    from kin.path.follow import path_solver

    robot = load_robot("panda")
    assert choose_solver(robot).near_seed and choose_solver(robot, "mink").near_seed
    assert path_solver(robot).near_seed and path_solver(robot, "differential").near_seed
    assert not get_solver(robot).near_seed
