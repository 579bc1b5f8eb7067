"""Task-shaped targets (a free tool axis, a mask) on every shipped robot and on real URDF arms.

Issue #32 item 1: an :class:`AxisTarget` and a masked :class:`PoseTarget` of a reachable pose are
solved, with no false success, on every shipped robot and on example-robot-data's Panda, Kinova
Jaco 2, UR5, Z1, xArm7, TIAGo arm and Baxter arm, through the library, ``kin ik`` and
``kin ik --stdin`` with the same answers; closed-form arms answer from their closed form (a sweep
of the free rotation), not from the numeric fallback.

The targets are the tool poses of random joint vectors inside the limits, made by an independent
forward kinematics: the plain NumPy DH product of ``tests/support/dh_reference.py`` for a shipped table,
Pinocchio on the maker's original URDF (``tests/support/urdf_reference.py``) for a URDF arm. Every answer
is judged again by that same reference. ``scripts/bench_task_targets.py`` measures the success
rate over thousands of targets per arm (the 99.9 % of the issue); here a sample of each.
"""

from __future__ import annotations

import io
import json

import numpy as np
import pytest
from support.task_targets_reference import KINDS, ROBOTS, arm_of

from kin.ik import get_solver
from kin.ik.analytic.closed_form import ClosedFormSolver


def _stdin_answers(monkeypatch, capsys, argv: list[str], lines: list[dict]) -> list[dict]:
    from kin.commands import ik

    text = "".join(json.dumps(line) + "\n" for line in lines)
    monkeypatch.setattr("sys.stdin", io.StringIO(text))
    ik.main([*argv, "--stdin"])
    captured = capsys.readouterr()
    assert captured.err == ""
    return [json.loads(line) for line in captured.out.splitlines()]


def _command_answer(capsys, argv: list[str], line: dict) -> dict:
    from kin.commands import ik

    argv = [*argv, "--target", *map(repr, line["target"]), "--json"]
    if "axis" in line:
        argv += ["--axis", *map(repr, line["axis"])]
    else:
        argv += ["--rpy", *map(repr, line["rpy"]), "--mask", *map(str, line["mask"])]
    ik.main(argv)
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("name", ROBOTS)
def test_reachable_task_targets_are_solved_alike_by_every_route(name, kind, monkeypatch, capsys):
    """12 reachable targets: all solved, judged by the reference; the same q by the three routes."""
    arm = arm_of(name)
    targets = arm.targets(kind, 12, seed=sum(map(ord, name + kind)))
    library = [arm.solver.solve(target) for target, _ in targets]
    for (target, _), result in zip(targets, library):
        assert result.success, f"{name} {kind}: {result.status}: {result.message}"
        for solution in result.solutions:
            arm.check(target, solution.q)
    streamed = _stdin_answers(monkeypatch, capsys, arm.argv, [line for _, line in targets])
    assert len(streamed) == len(targets)
    for result, answer in zip(library, streamed):
        assert answer["success"], answer
        np.testing.assert_allclose(answer["solutions"][0]["q"], result.best.q, atol=1e-9)
    for (_, line), result in list(zip(targets, library))[:2]:
        answer = _command_answer(capsys, arm.argv, line)
        assert answer["success"], answer
        np.testing.assert_allclose(answer["solutions"][0]["q"], result.best.q, atol=1e-9)


def _closed_form_cases() -> list[tuple[str, str]]:
    """(robot, kind) of the closed-form arms, but a five-joint arm's world-axis masks.

    A six-joint arm meets each swept rotation exactly; a tool axis on a five-joint arm is its
    closed form's own target (position and approach). A mask that frees one world rotation on
    a five-joint arm leaves a finite set of answers, which no swept rotation meets exactly: its
    closed form refuses the swept poses, and least squares answers.
    """
    cases = []
    for name in ROBOTS:
        robot = arm_of(name).robot
        if isinstance(get_solver(robot), ClosedFormSolver):
            cases += [(name, kind) for kind in KINDS if robot.nq >= 6 or kind == "axis"]
    return cases


@pytest.mark.parametrize(("name", "kind"), _closed_form_cases())
def test_closed_form_arms_answer_by_their_closed_form(name, kind):
    """On a closed-form arm, the free rotation is swept by the closed form, not searched."""
    arm = arm_of(name)
    expected = {"closed_form"}
    for target, _ in arm.targets(kind, 12, seed=3):
        result = arm.solver.solve(target)
        assert result.success and result.method in expected, (result.status, result.method)


def test_the_sweep_finds_a_roll_the_seed_does_not_give():
    """Z1's tool z is not its last joint's axis: the seed's roll misses, a grid roll is named."""
    arm = arm_of("erd:z1")
    named = set()
    for target, _ in arm.targets("axis", 20, seed=1):
        result = arm.solver.solve(target)
        assert result.success and result.method == "closed_form"
        arm.check(target, result.best.q)
        named.add(result.best.branch.rsplit(", ", 1)[-1])
    assert "seed's roll" in named and any(name.startswith("roll ") for name in named), named
