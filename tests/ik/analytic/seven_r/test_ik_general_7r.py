"""Any 7R arm: an end joint held, the 6R closed forms for the rest (kin/ik/analytic/seven_r/general_7r.py).

- seeded random 7R tables with offsets everywhere, both conventions, random base and tool: at the
  held joint's true value, every branch reaches the pose (the plain NumPy DH product of
  ``tests/support/dh_reference.py``) to 1e-9 and the q the pose came from is among them;
- the numeric solver's first stage answers with it on such arms (joint limits +-pi), every answer
  verified by Pinocchio on the arm's URDF, no false success;
- the end joint that leaves a special 6R family is the one held;
- the special 7R forms keep their arms (humanoid7's, Panda's, and a Kinova Gen3 table, which is of
  humanoid7's structure).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pinocchio as pin
import pytest
from support.arm_tables import wrapped_gap
from support.dh_reference import fk_frames, rotation_angle
from support.general_arms import random_7r_arm as random_arm

import kin
from dh2urdf import DHTable, get_robot, load_table
from kin.ik import PoseTarget
from kin.ik.analytic.seven_r.general_7r import General7RIK
from kin.ik.analytic.six_r.general_6r import General6R
from kin.ik.numeric.solver import NumericIK

PI = math.pi
TABLES = 12
POSES = 25
TOL = 1e-9


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_random_7r_every_branch_on_target_and_q_among_them(convention):
    """At the held joint's true value: every branch on target by the NumPy DH product, the q
    among the branches (modulo 2 pi), on every pose of every table."""
    for seed in range(TABLES):
        table, reference = random_arm(seed, convention)
        closed = General7RIK(table, table.lower, table.upper)
        q = np.random.default_rng(100 + seed).uniform(-PI, PI, (POSES, 7))
        poses = fk_frames(reference, q)[:, -1]
        branches = closed.branches(poses, q[:, closed.free])
        assert branches.shape[2] == 7
        for k in range(POSES):
            exist = branches[k][~np.isnan(branches[k]).any(axis=1)]
            assert len(exist), f"{table.name} pose {k}"
            assert np.all(exist[:, closed.free] == q[k, closed.free])
            reached = fk_frames(reference, exist)[:, -1]
            position = np.linalg.norm(reached[:, :3, 3] - poses[k, :3, 3], axis=1)
            rotation = rotation_angle(reached[:, :3, :3], poses[k, :3, :3])
            assert position.max() < TOL and rotation.max() < TOL, f"{table.name} pose {k}"
            assert wrapped_gap(exist, q[k]).min() < 1e-6, f"{table.name} pose {k} q={q[k]}"


def yaw_puma() -> DHTable:
    """Joints 2-7 a PUMA 560 (spherical wrist), joint 1 a random row, limits +-pi."""
    puma = load_table(get_robot("puma560").table_path)
    first = dataclasses.replace(puma.rows[0], a=0.1, alpha=0.7, d=0.2, theta=0.3)
    rows = tuple(
        dataclasses.replace(row, index=i + 1, name=f"j{i + 1}", lower=-PI, upper=PI)
        for i, row in enumerate((first, *puma.rows))
    )
    return dataclasses.replace(puma, rows=rows, name="yaw_puma")


def puma_roll() -> DHTable:
    """Joints 1-6 a PUMA 560 (spherical wrist), joint 7 a random row, limits +-pi: no special 7R
    form fits (axes 1-3 do not meet, nor axes 5-7)."""
    puma = load_table(get_robot("puma560").table_path)
    last = dataclasses.replace(puma.rows[5], index=7, name="j7", a=0.05, alpha=0.9, d=0.1)
    rows = tuple(dataclasses.replace(row, lower=-PI, upper=PI) for row in (*puma.rows, last))
    return dataclasses.replace(puma, rows=rows, name="puma_roll")


def _stage_answers(robot, solver, count: int, seed: int) -> int:
    """Solve ``count`` poses from the zero seed; every answer verified by Pinocchio (the judge's
    1e-5 m, 1e-4 rad), inside the limits; returns how many the free-joint closed form answered."""
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.tool_frame)
    answered = 0
    for q in np.random.default_rng(seed).uniform(-PI, PI, (count, 7)):
        pin.framesForwardKinematics(model, data, q)
        pose = data.oMf[frame].copy()
        result = solver.solve(PoseTarget(pose.translation, pose.rotation), np.zeros(7))
        assert result.success, f"{robot.name}: {result.message}"
        answered += result.method == "closed_form_free_joint"
        found = result.solutions[0].q
        assert np.all(found >= -PI) and np.all(found <= PI)
        pin.framesForwardKinematics(model, data, found)
        error = pin.log6(data.oMf[frame].actInv(pose)).vector
        assert np.abs(error[:3]).max() < 1e-5 and np.abs(error[3:]).max() < 1e-4
    return answered


def test_stage_zero_answers_a_7r_whose_rest_is_a_family():
    """A 7R whose joints 1-6 are a spherical-wrist 6R: the numeric solver's stage 0 is this form
    (joint 7 held, the family for the rest) and answers nearly every pose from the zero seed."""
    robot = kin.robot_from_table(puma_roll())
    solver = NumericIK(robot)
    assert isinstance(solver.closed_form, General7RIK) and not solver.closed_form.costly
    assert solver.stages[0].name == "closed_form_free_joint"
    assert _stage_answers(robot, solver, 60, 1) >= 57


def test_a_general_7r_asks_the_form_after_the_seed_table():
    """Random 7R arms (limits +-pi): the form takes the general elimination (about 1 ms a
    solve), so the solver asks it after the seed-table stage (damped Newton answers in a
    fraction of that); put first, it answers nearly every pose from the zero seed."""
    answered = total = 0
    for seed in range(4):
        table, _ = random_arm(seed, "standard" if seed % 2 else "modified")
        rows = tuple(dataclasses.replace(r, lower=-PI, upper=PI) for r in table.rows)
        robot = kin.robot_from_table(dataclasses.replace(table, rows=rows))
        solver = NumericIK(robot)
        assert isinstance(solver.closed_form, General7RIK) and solver.closed_form.costly
        assert [stage.name for stage in solver.stages[:2]] == [
            "seed_table",
            "closed_form_free_joint",
        ]
        _stage_answers(robot, solver, 10, seed)  # every answer verified, whichever stage
        solver.stages = (solver.stages[1], solver.stages[0], *solver.stages[2:])
        answered += _stage_answers(robot, solver, 20, 10 + seed)
        total += 20
    assert answered >= 0.95 * total, f"{answered} of {total} from the closed form"


def test_the_end_that_leaves_a_special_family_is_held():
    """Joints 2-7 a PUMA 560 (spherical wrist), joint 1 a random row: joint 1 is held and the
    rest is the spherical-wrist family; a random arm holds joint 7 over the general form."""
    table = yaw_puma()
    closed = General7RIK(table, table.lower, table.upper)
    assert closed.free == 0 and not isinstance(closed.structure, General6R)
    random, _ = random_arm(3, "standard")
    assert isinstance(General7RIK(random, random.lower, random.upper).structure, General6R)


@pytest.mark.parametrize(
    ("name", "form"),
    [("humanoid7", "SevenDofIK"), ("panda", "SphericalShoulder7RIK"), ("gen3", "SevenDofIK")],
)
def test_the_special_forms_keep_their_arms(name, form):
    """humanoid7's and Panda's forms are asked first; Kinova's Gen3 (its classic DH table) is of
    humanoid7's structure (joint 1 held, a closed form for the other six)."""
    from pathlib import Path

    path = Path(__file__).parents[3] / "data" / "seven_r" / "gen3.toml"
    robot = kin.load_robot(path if name == "gen3" else name)
    assert type(NumericIK(robot).closed_form).__name__ == form


def test_positions_and_bad_tables_are_refused():
    """A position is not taken (None: the next stages answer); a 6R or prismatic table raises."""
    from kin.ik.exceptions import StructureError

    table, _ = random_arm(1, "standard")
    closed = General7RIK(table, table.lower, table.upper)
    assert closed.prepare(np.zeros(3), None) is None
    assert closed.first(None, np.zeros((1, 7)), np.empty(7), 0.05) == -1
    with pytest.raises(StructureError):
        General7RIK(load_table(get_robot("ur5").table_path), -np.ones(6), np.ones(6))
    prismatic = dataclasses.replace(
        table, rows=(dataclasses.replace(table.rows[0], joint_type="prismatic"), *table.rows[1:])
    )
    with pytest.raises(StructureError):
        General7RIK(prismatic, table.lower, table.upper)


def test_solve_batch_answers_together_as_one_by_one():
    """kin.ik.solve_batch on a 7R whose rest is a family: the free-joint form answers the poses in
    one batched 6R solve; every success verified by Pinocchio, the same joint vectors as the solver's call
    from the same seed where that call answers from the closed form."""
    from kin.ik import get_solver, solve_batch

    robot = kin.robot_from_table(puma_roll())
    rng = np.random.default_rng(9)
    q = rng.uniform(-PI, PI, (60, 7))
    model, data = robot.model, robot.model.createData()
    frame = model.getFrameId(robot.tool_frame)
    poses = []
    for qk in q:
        pin.framesForwardKinematics(model, data, qk)
        poses.append(data.oMf[frame].homogeneous.copy())
    poses = np.array(poses)
    seeds = np.clip(q + rng.normal(0.0, 0.2, q.shape), -PI, PI)
    result = solve_batch(robot, poses[:, :3, 3], poses[:, :3, :3], seeds)
    assert result.success.all()
    together = [k for k, stage in enumerate(result.stage) if stage == "closed_form_free_joint"]
    assert len(together) >= 0.9 * len(q)
    solver = get_solver(robot)
    for k in range(len(q)):
        pin.framesForwardKinematics(model, data, result.q[k])
        assert np.abs(pin.log6(data.oMf[frame].actInv(pin.SE3(poses[k]))).vector).max() < 1e-9
    for k in together[:10]:
        alone = solver.solve(PoseTarget(poses[k, :3, 3], poses[k, :3, :3]), seeds[k])
        assert alone.method == "closed_form_free_joint"
        np.testing.assert_allclose(alone.solutions[0].q, result.q[k], atol=1e-9)
