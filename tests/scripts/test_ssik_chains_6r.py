"""The general 6R closed form on ssik's own chains of its 18 general 6R arms, read as URDFs.

ssik's prebuilt modules (``ssik.prebuilt.<maker>.<arm>_ik``) carry each arm's chain as ssik baked
it from the maker's URDF; ``scripts/ssik_chains.py`` writes it as a URDF that ``kin`` loads as a
user's ``--robot FILE.urdf``. Judged by Pinocchio on that URDF (not by the closed form's chain):

- the documented call gives ``closed_form:general_6r``, every branch (valid or rejected by the
  limits) on target, the sampled q among the valid ones;
- the valid branches are as many as ssik's distinct solutions modulo 2 pi (ssik returns every
  ``2 pi`` copy inside the limits) on every regular pose (the smallest singular value of the
  Jacobian above 1e-5: near a singularity the solutions cluster and neither count is defined);
- every solution that 300 least-squares starts (no limits) find is one of our branches (slow).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from support.arm_tables import wrapped_gap
from support.least_squares_solutions import least_squares_solutions

from kin import load_robot
from kin.ik import PoseTarget, get_solver

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from ssik_chains import GENERAL_6R, distinct_mod_2pi, write_ssik_arm  # noqa: E402

pytestmark = pytest.mark.peer
PI = math.pi
TOL = 1e-9
NEAR_SINGULAR = 1e-5


class Arm:
    """An arm of ssik's written as a URDF: our solver, ssik's module, Pinocchio's FK of the URDF."""

    def __init__(self, name: str, folder: Path):
        import pinocchio as pin

        self.pin = pin
        path, self.module = write_ssik_arm(name, folder)
        self.robot = load_robot(path)
        self.solver = get_solver(self.robot)
        self.model = pin.buildModelFromUrdf(str(path))
        self.data = self.model.createData()
        self.frame = self.model.getFrameId(self.module.EE_LINK)
        self.lower = np.maximum(self.robot.lower, -PI)
        self.upper = np.minimum(self.robot.upper, PI)

    def configuration(self, q: np.ndarray) -> np.ndarray:
        """Pinocchio's configuration of joint angles (a continuous joint takes cos, sin)."""
        out = []
        for joint, angle in zip(self.model.joints[1:], q):
            out += [math.cos(angle), math.sin(angle)] if joint.nq == 2 else [angle]
        return np.array(out)

    def tool(self, q: np.ndarray):
        """The tool pose (pin.SE3) of joint angles ``q`` [rad]."""
        self.pin.framesForwardKinematics(self.model, self.data, self.configuration(q))
        return self.data.oMf[self.frame].copy()

    def sigma_min(self, q: np.ndarray) -> float:
        """The Jacobian's smallest singular value at ``q``."""
        pin = self.pin
        c = self.configuration(q)
        J = pin.computeFrameJacobian(self.model, self.data, c, self.frame, pin.LOCAL)
        return float(np.linalg.svd(J, compute_uv=False).min())


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    pytest.importorskip("ssik")
    pytest.importorskip("pinocchio")
    return tmp_path_factory.mktemp("ssik_chains")


@pytest.mark.parametrize("name", GENERAL_6R)
def test_branches_on_target_and_counts_match_ssik(name, folder):
    """200 poses inside the limits: every branch on target (Pinocchio), q among the valid ones,
    as many valid branches as ssik's distinct solutions on every regular pose."""
    arm = Arm(name, folder)
    assert arm.solver.name == "closed_form:general_6r", name
    rng = np.random.default_rng(3)
    regular = same = 0
    for q in rng.uniform(arm.robot.lower, arm.robot.upper, (200, 6)):
        pose = arm.tool(q)
        result = arm.solver.solve(PoseTarget(pose.translation, pose.rotation))
        assert result.success, f"{name} {q=}: {result.message}"
        valid = np.array([s.q for s in result.solutions]).reshape(-1, 6)
        for branch in [s.q for s in result.solutions + result.rejected]:
            error = arm.pin.log6(arm.tool(branch).actInv(pose)).vector
            assert np.abs(error).max() < TOL, f"{name} {q=} {branch=}"
        if arm.sigma_min(q) < NEAR_SINGULAR:
            continue
        assert wrapped_gap(valid, q).min() < 1e-6, f"{name} {q=}: q is not among the branches"
        theirs = distinct_mod_2pi([s.q for s in arm.module.solve(pose.homogeneous)])
        regular += 1
        same += theirs == len(valid)
    assert regular >= 190 and same == regular, f"{name}: {same=} of {regular=}"


@pytest.mark.slow
@pytest.mark.parametrize("name", GENERAL_6R)
def test_every_least_squares_solution_is_a_branch(name, folder):
    """Two poses: each distinct solution of 300 least-squares starts (no limits) is a branch, and
    we have as many branches as they found distinct solutions or more."""
    arm = Arm(name, folder)
    rng = np.random.default_rng(5)
    for q in rng.uniform(arm.lower, arm.upper, (2, 6)):
        pose = arm.tool(q)
        result = arm.solver.solve(PoseTarget(pose.translation, pose.rotation))
        branches = np.array([s.q for s in result.solutions + result.rejected])  # every branch

        def residual(x, pose=pose):
            return arm.pin.log6(arm.tool(x).actInv(pose)).vector

        solutions = least_squares_solutions(residual, rng, 300)
        assert solutions, name
        for solution in solutions:
            assert wrapped_gap(branches, solution).min() < 1e-6, f"{name}: {solution=}"
        assert len(branches) >= len(solutions), name
