"""A URDF chain with mimic joints through the library as through ``kin ik`` (issue 47, item 4).

One loader, one answer: :func:`kin.load_arm` is the loader of ``kin fk`` and ``kin ik``
(:mod:`kin.commands.arm_route`), and :func:`kin.ik.get_solver` gives its arm the solver
``kin ik`` gives it, so ``get_solver(kin.load_arm(path)).solve(PoseTarget(p, R))`` returns the
command's answer. The arm is test_urdf_mimic's general 6R with a mimic joint after j3; every
answer is also judged by Pinocchio's own model of the file built with mimic joints.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import call
from support.mimic_reference import _in_limits, _pinocchio_mimic_fk, _urdf

import kin
from kin import ModelLoadError, load_robot
from kin.ik import PoseTarget, PositionTarget, TargetError, get_solver, solve_ik
from kin.mimic.solver import MimicSolver


@pytest.fixture(params=[1.0, -1.0], ids=["multiplier+1", "multiplier-1"])
def arm_file(request, tmp_path):
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(request.param), encoding="utf-8")
    return path, request.param


def _command(capsys, argv: list[str]) -> dict:
    from kin.commands import main

    code = call(main, argv)
    record = json.loads(capsys.readouterr().out)
    assert code in (0, 1), f"{argv=} {code=}"
    return record


def test_get_solver_of_the_loaded_arm_gives_kin_iks_answers(arm_file, capsys):
    """Four poses (FK of random independent q): the library's result equals ``kin ik --json``'s
    (status, method, the solution's q to the last bit: the same work), and the answer is on the target by
    Pinocchio's mimic FK (1e-5 m, 1e-4 rad) inside every joint's limits, the mimic one too."""
    path, multiplier = arm_file
    arm = kin.load_arm(path)
    assert isinstance(arm, kin.MimicArm) and arm.nq == 6
    solver = get_solver(arm)
    assert isinstance(solver, MimicSolver) and solver.name == "mimic_dls"
    rng = np.random.default_rng(23)
    for _ in range(4):
        q = rng.uniform(arm.lower, arm.upper)
        pose = _pinocchio_mimic_fk(path, q)
        p, rpy = pose[:3, 3], pin.rpy.matrixToRpy(pose[:3, :3])
        target = PoseTarget.from_rpy(p, rpy)
        ours = solver.solve(target, timeout=5.0)
        argv = ["ik", "--robot", str(path), "--target", *map(repr, p.tolist())]
        argv += ["--rpy", *map(repr, rpy.tolist()), "--json", "--timeout", "5000"]
        record = _command(capsys, argv)
        assert ours.status == record["status"] == "ok", f"{q=} {ours.message} {record=}"
        assert ours.method == record["method"], f"{q=}"
        theirs = [solution["q"] for solution in record["solutions"]]
        assert len(ours.solutions) == len(theirs) == 1, f"{q=}"
        assert ours.solutions[0].q.tolist() == theirs[0], f"{q=}"
        assert solve_ik(arm, target, timeout=5.0).solutions[0].q.tolist() == theirs[0]
        reached = _pinocchio_mimic_fk(path, ours.solutions[0].q)
        assert np.linalg.norm(reached[:3, 3] - p) < 1e-5, f"{q=}"
        cosine = (np.trace(reached[:3, :3].T @ pose[:3, :3]) - 1) / 2
        assert math.acos(min(1.0, cosine)) < 1e-4, f"{q=}"
        assert _in_limits(ours.solutions[0].q, multiplier), f"{q=}"


def test_a_position_target_and_a_seed_as_the_command_takes_them(arm_file, capsys):
    """A position from a seed (``--seed-q``): the same answer from the library and the command."""
    path, _ = arm_file
    arm = kin.load_arm(path)
    q = np.array([0.3, -0.4, 0.5, 0.2, -0.6, 0.1])
    seed = np.array([0.2, -0.3, 0.4, 0.0, -0.5, 0.0])
    p = _pinocchio_mimic_fk(path, q)[:3, 3]
    ours = get_solver(arm).solve(PositionTarget(p), seed, timeout=5.0)
    argv = ["ik", "--robot", str(path), "--target", *map(repr, p.tolist())]
    argv += ["--seed-q", *map(repr, seed.tolist()), "--json", "--timeout", "5000"]
    record = _command(capsys, argv)
    assert ours.success and record["success"]
    assert ours.solutions[0].q.tolist() == record["solutions"][0]["q"]
    reached = _pinocchio_mimic_fk(path, ours.solutions[0].q)
    assert np.linalg.norm(reached[:3, 3] - p) < 1e-5


def test_collisions_on_a_mimic_chain_are_one_clear_error(arm_file):
    """No collision model of such a chain yet: the library says so, as ``kin ik --scene`` does."""
    path, _ = arm_file
    with pytest.raises(TargetError, match="chain with mimic joints, which has no collision model"):
        get_solver(kin.load_arm(path), collisions=object())


def test_load_arm_loads_every_other_robot_as_load_robot(arm_file):
    """A shipped robot or a URDF without mimic joints: the same RobotModel as load_robot's."""
    path, _ = arm_file
    assert kin.load_arm("ur5") is load_robot("ur5")  # the registry's cached model
    with pytest.raises(ModelLoadError, match=r"kin\.load_arm in Python"):
        load_robot(path)


@pytest.mark.parametrize("multiplier", [0.5, -1.3, 2.0])
def test_the_coupling_is_the_expansion_bit_for_bit(tmp_path, multiplier):
    """``coupling @ q + expand(0)`` (the descent's affine shortcut) equals ``chain.expand(q)``
    exactly, joint for joint, over random vectors inside and beyond the limits."""
    path = tmp_path / "mimic6r.urdf"
    path.write_text(_urdf(multiplier), encoding="utf-8")
    arm = kin.load_arm(path)
    rng = np.random.default_rng(7)
    shift = arm.chain.expand(np.zeros(arm.nq))
    for q in rng.uniform(-10.0, 10.0, size=(200, arm.nq)):
        np.testing.assert_array_equal(arm.coupling @ q + shift, arm.chain.expand(q))
