"""A position target on a 6R arm with a closed form: the answer near the seed (issue 43, item 8).

The reference is an independent damped least-squares step sequence from the seed, in plain NumPy
on the table's DH product (``dh_reference``, central finite differences for the Jacobian):
``dq = J^T (J J^T + 0.05^2 I)^-1 e``, each step cut to 0.1 rad and clipped into the limits. The
solver's answer must be on target (1e-6 m, by the NumPy product), inside the limits, and no
farther from the seed (Euclidean joint distance) than the reference's end + :data:`SLACK`.
Before the fix the numeric solver answered, from a seed-table sample: with no seed (zero), UR5's
target (0.627, 0.136, 0.266) m gave q = (3.44, -3.18, 0.89, -4.96, -2.31, -4.93) rad, 8.8 rad
from zero, where the steps from zero end 1.2 rad away.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference

from dh2urdf import get_robot
from kin import load_robot
from kin.commands import ik as ik_command
from kin.ik import PositionTarget, solve_ik

#: How much farther than the reference's end the answer may be [rad].
SLACK = 1e-3
#: Random seeds (and targets) per robot and distance.
CASES = 6


def _position(table, q: np.ndarray) -> np.ndarray:
    """Tool positions (N, 3) [m] of joint vectors (N, 6) by the NumPy DH product."""
    return fk_frames(table, q)[:, -1, :3, 3]


def reference_dls(table, seed: np.ndarray, target: np.ndarray) -> np.ndarray | None:
    """The damped least-squares steps from ``seed`` to ``target``; their end, or None."""
    q = seed.copy()
    h = 1e-6
    for _ in range(3000):
        probes = np.vstack([q, q + h * np.eye(6), q - h * np.eye(6)])
        positions = _position(table, probes)
        error = target - positions[0]
        if np.linalg.norm(error) < 1e-10:
            return q
        jacobian = (positions[1:7] - positions[7:]).T / (2 * h)
        step = jacobian.T @ np.linalg.solve(jacobian @ jacobian.T + 0.05**2 * np.eye(3), error)
        norm = np.linalg.norm(step)
        if norm > 0.1:
            step *= 0.1 / norm
        q = np.clip(q + step, table.lower, table.upper)
    return None


def _cases(name: str, far: bool):
    table = load_reference(get_robot(name).table_path)
    rng = np.random.default_rng(43 + far)
    low, high = np.maximum(table.lower, -np.pi), np.minimum(table.upper, np.pi)
    for _ in range(CASES):
        seed = rng.uniform(low, high)
        other = rng.uniform(low, high) if far else seed + rng.normal(0.0, 0.3, 6)
        yield table, seed, _position(table, np.clip(other, table.lower, table.upper)[None])[0]


def _check(name, table, seed, target, q):
    assert q is not None, f"{name=} {seed=} {target=}: no answer"
    reached = _position(table, q[None])[0]
    assert np.linalg.norm(reached - target) < 1e-6, f"{name=} {q=} {reached=} {target=}"
    assert np.all(q >= table.lower) and np.all(q <= table.upper), f"{name=} {q=}"
    walked = reference_dls(table, seed, target)
    if walked is not None:
        ours, theirs = np.linalg.norm(q - seed), np.linalg.norm(walked - seed)
        assert ours <= theirs + SLACK, f"{name=} {seed=} {target=}: {ours=} {theirs=} rad"


@pytest.mark.parametrize("far", [False, True], ids=["near", "far"])
@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_answer_no_farther_than_the_damped_steps_from_the_seed(name, far):
    """Random reachable targets near the seed's tool and far from it: the answer is on target,
    inside the limits and at most the reference steps' joint distance from the seed."""
    robot = load_robot(name)
    for table, seed, target in _cases(name, far):
        result = solve_ik(robot, PositionTarget(target), seed)
        assert result.success and result.method == "near_seed", f"{name=} {result.message}"
        _check(name, table, seed, target, result.best.q)


def test_no_seed_starts_from_zero():
    """The issue's reproducer: UR5, no seed, target (0.627, 0.136, 0.266) m: near zero now."""
    table = load_reference(get_robot("ur5").table_path)
    target = np.array([0.627, 0.136, 0.266])
    result = solve_ik(load_robot("ur5"), PositionTarget(target))
    assert result.success and result.solver == "closed_form:ur_wrist", result.message
    _check("ur5", table, np.zeros(6), target, result.best.q)
    assert np.linalg.norm(result.best.q) < 1.5, result.best.q


def test_kin_ik_position_only_answers_near_the_seed(capsys):
    """kin ik --target only (a position) with --seed-q: the JSON answer is the near one."""
    seed = [0.0, -1.5, 1.5, 0.0, 0.0, 0.0]
    argv = ["--robot", "ur5", "--target", "0.4", "0.1", "0.3", "--seed-q", *map(str, seed)]
    assert ik_command.main([*argv, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["method"] == "near_seed", record["message"]
    q = np.array(record["solutions"][0]["q"])
    table = load_reference(get_robot("ur5").table_path)
    _check("ur5", table, np.array(seed), np.array([0.4, 0.1, 0.3]), q)
