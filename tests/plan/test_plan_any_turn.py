"""kin.plan.plan(any_turn=True) and ``kin plan --any-turn``: a joint goal's whole-turn copies.

Judged apart from the planner: the end of the path against the goal by the joint values (whole
turns apart) and by Pinocchio's FK of the maker's URDF (every frame in the same place); the path
by the benchmark's reference (scripts/plan_reference.py: Pinocchio + coal built apart from kin)
at every 0.005 rad of joint motion. The problem is one of scripts/bench_plan_problems.json that no planner solves on the
literal goal within 10 s (docs/benchmarks.md): UR5 in the benchmark's table cell.
"""

from __future__ import annotations

import io
import json
import math
import sys

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import call
from support.scripts_helper import SCRIPTS, load_script

from kin.collision.requests import CONTACT_TOLERANCE
from kin.commands import plan as plan_command
from kin.plan import plan
from kin.plan.goals import MOST_TURNS, joint_goal


@pytest.fixture(scope="module")
def blocked(tmp_path_factory):
    """UR5, its cell, the reference, and a problem solved only a turn away (ur5-table-00)."""
    if str(SCRIPTS) not in sys.path:  # the scripts import each other by bare name
        sys.path.insert(0, str(SCRIPTS))
    plan_problems = load_script("plan_problems")
    Problem, Cell = plan_problems.Problem, plan_problems.Cell
    problems = json.loads((SCRIPTS / "bench_plan_problems.json").read_text())["problems"]
    problem = Problem.from_json(next(p for p in problems if p["id"] == "ur5-table-00"))
    arm = plan_problems.ARMS[problem.arm]
    robot = plan_problems.load_arm(arm)
    cell = Cell(arm, robot, problem.boxes, tmp_path_factory.mktemp("turns"))
    return robot, cell, problem


def test_the_goal_copies_are_whole_turns_within_the_limits_nearest_the_start(blocked):
    robot, cell, problem = blocked
    start, goal = np.array(problem.start), np.array(problem.goal)
    goals = joint_goal(robot, goal, cell.checker, start, any_turn=True).q
    assert 1 < len(goals) <= MOST_TURNS and any((g == goal).all() for g in goals)
    turns = (goals - goal) / (2 * math.pi)
    assert np.allclose(turns, np.round(turns), atol=1e-12)
    assert ((goals >= robot.lower - 1e-10) & (goals <= robot.upper + 1e-10)).all()
    distances = np.linalg.norm(goals - start, axis=1)
    assert (np.diff(distances) >= 0).all()  # nearest the start first
    assert len(joint_goal(robot, goal, cell.checker, start).q) == 1  # without: the goal alone


def test_a_goal_only_a_turn_away_is_planned_and_certified(blocked):
    robot, cell, problem = blocked
    start, goal = np.array(problem.start), np.array(problem.goal)
    result = plan(
        robot, start, goal, collisions=cell.checker, seed=60, any_turn=True, time_limit=math.inf
    )
    assert result.status == "ok", result.message
    end = result.path[-1]
    assert np.array_equal(end, result.goals[result.goal_index])
    turns = (end - goal) / (2 * math.pi)
    assert np.allclose(turns, np.round(turns), atol=1e-12) and np.abs(turns).max() > 0.5
    # the same place of the arm: every link frame of the reference's Pinocchio model (the maker's
    # URDF, read apart from kin) at the goal and at the end
    reference = cell.reference
    placements = []
    for q in (goal, end):
        pin.framesForwardKinematics(reference.model, reference.data, reference._full(q))
        placements.append(np.array([f.homogeneous for f in reference.data.oMf]))
    assert np.allclose(placements[0], placements[1], atol=1e-9)
    verdict = reference.judge(result.path)  # every 0.005 rad of joint motion
    assert verdict.free and verdict.smallest > -CONTACT_TOLERANCE, verdict.first


UR5 = ["--robot", "ur5", "--start", "0", "-1.5", "1.5", "0", "0", "0", "--json"]


def test_the_command_lists_the_copies_and_ends_at_one(capsys):
    goal = ["3", "-1.5", "1.5", "0", "0", "0"]
    assert call(plan_command.main, [*UR5, "--goal", *goal, "--any-turn"]) == 0
    record = json.loads(capsys.readouterr().out)
    goals = np.array(record["goals"])
    assert record["status"] == "ok" and len(goals) > 1
    assert np.array_equal(record["path"][-1], goals[record["goal_index"]])
    turns = (goals - np.array(goal, dtype=float)) / (2 * math.pi)
    assert np.allclose(turns, np.round(turns), atol=1e-12)
    assert call(plan_command.main, [*UR5, "--goal", *goal]) == 0  # without: the goal alone
    assert len(json.loads(capsys.readouterr().out)["goals"]) == 1


def test_a_stream_line_says_any_turn_true_or_false(monkeypatch, capsys):
    lines = [
        json.dumps({"goal": [3, -1.5, 1.5, 0, 0, 0], "any_turn": True}),
        json.dumps({"goal": [3, -1.5, 1.5, 0, 0, 0], "any_turn": "yes"}),
    ]
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(line + "\n" for line in lines)))
    assert call(plan_command.main, [*UR5[:-1], "--stdin"]) == 1
    first, second = (json.loads(line) for line in capsys.readouterr().out.splitlines())
    assert first["status"] == "ok" and len(first["goals"]) > 1
    assert (
        set(second) == {"line", "error"} and '"any_turn" must be true or false' in second["error"]
    )
