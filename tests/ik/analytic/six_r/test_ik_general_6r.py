"""The general 6R closed form (kin/ik/analytic/six_r/general_6r.py): every isolated branch of any 6R arm.

- seeded random 6R tables in both conventions, random base and tool: every branch on target to
  1e-9 by the plain NumPy DH product of ``tests/support/dh_reference.py``, the q the pose came from among
  the branches (``KIN_GENERAL_6R_TABLES`` tables x ``KIN_GENERAL_6R_POSES`` poses per convention,
  default 100 x 10);
- every distinct solution found by 200 independent least-squares starts (no limits) is a branch;
- real non-Pieper arms written from the makers' parameters (``tests/data/six_r``): xArm6,
  Jaco 2 6-DOF, CRX-10iA go to this form, PiPER (spherical wrist) keeps its family; the Gen3
  lite through the URDF extraction of its maker's URDF (rounded: 1.5708, 3.1416), judged by
  Pinocchio on that URDF; the branch counts are compared with ssik's
  (``enumerate_windings=False``) when it is installed;
- the registry order, the documented solver call, the batch against the scalar solve, refusals.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
from support import TESTS
from support.arm_tables import make_table, wrapped_gap
from support.dh_reference import ReferenceTable, load_reference, rotation_angle
from support.general_arms import NEAR_SINGULAR, random_arm, reference_tool, sigma_min
from support.least_squares_solutions import least_squares_solutions

import kin
from dh2urdf import DHRow, DHTable, get_robot, load_table
from kin.ik import PoseTarget, get_solver
from kin.ik.analytic import registry
from kin.ik.analytic.six_r import general_6r
from kin.ik.analytic.six_r.general_6r import BRANCHES, General6R
from kin.ik.exceptions import StructureError

PI = math.pi
TABLES = int(os.environ.get("KIN_GENERAL_6R_TABLES", "100"))
POSES = int(os.environ.get("KIN_GENERAL_6R_POSES", "10"))
#: Round-trip tolerance [m], [rad]; a recovered q within JOINT_TOL [rad] of the sampled one.
TOL = 1e-9
JOINT_TOL = 1e-6
SIX_R = Path(__file__).parents[3] / "data" / "six_r"
#: The real arms' tables and the family the registry gives each.
REAL_ARMS = {"xarm6": "general_6r", "jaco2_6dof": "general_6r", "crx10ia": "general_6r",
             "piper": "spherical_wrist"}  # fmt: skip


def check_round_trips(structure, reference: ReferenceTable, q: np.ndarray, label: str):
    """Every branch of FK(q) on target to TOL; returns the q not among the branches."""
    poses = reference_tool(reference, q)
    found = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    assert found.shape == (len(q), BRANCHES, 6)
    missed = []
    for k, (branches, pose) in enumerate(zip(found, poses)):
        exist = branches[~np.isnan(branches[:, 0])]
        assert not np.isnan(exist).any(), f"{label} pose {k}"
        if len(exist):
            reached = reference_tool(reference, exist)
            position = np.linalg.norm(reached[:, :3, 3] - pose[:3, 3], axis=1)
            rotation = rotation_angle(reached[:, :3, :3], pose[:3, :3])
            assert position.max() < TOL and rotation.max() < TOL, f"{label} pose {k} q={q[k]}"
        if not len(exist) or wrapped_gap(exist, q[k]).min() > JOINT_TOL:
            missed.append(q[k])
    return missed, found


@pytest.mark.slow  # CI runs it; the default run stays under 5 minutes
@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_random_tables_every_branch_on_target_and_q_among_them(convention):
    """Random tables: the registry gives General6R; every branch on target to 1e-9 (plain DH
    product); the sampled q among the branches for >= 99.9 % of the poses, the misses all
    near-singular (named in the failure)."""
    total, missed = 0, []
    for seed in range(TABLES):
        table, reference = random_arm(1000 + seed, convention)
        structure = registry.recognise(table)
        assert isinstance(structure, General6R), f"{seed=}: {structure.name}"
        q = np.random.default_rng(seed).uniform(-PI, PI, (POSES, 6))
        misses, _ = check_round_trips(structure, reference, q, f"{convention} {seed=}")
        total += len(q)
        missed += [(seed, m, sigma_min(reference, m)) for m in misses]
    regular = [(seed, m.tolist(), s) for seed, m, s in missed if s >= NEAR_SINGULAR]
    assert len(missed) <= 0.001 * total and not regular, f"{total=} {missed=}"


@pytest.mark.parametrize(
    "name",
    [
        pytest.param("xarm6", marks=pytest.mark.slow),
        "jaco2_6dof",  # its 55 deg wrist: q5 = 180 deg makes axes 4 and 6 parallel
        pytest.param("crx10ia", marks=pytest.mark.slow),
    ],
)
def test_round_joint_angles(name):
    """Joint vectors of round angles (0, +-90, 180, 45, -60 deg): symmetric poses where several
    solutions share a joint angle (multiple roots). Every branch on target; the sampled q among
    the branches unless the pose is near-singular (its solutions need not be isolated)."""
    table = load_table(SIX_R / f"{name}.toml")
    reference = load_reference(SIX_R / f"{name}.toml")
    structure = General6R.recognise(table)
    angles = np.radians([0.0, 90.0, -90.0, 180.0, 45.0, -60.0])
    q = angles[np.random.default_rng(1).integers(0, len(angles), (300, 6))]
    missed, _ = check_round_trips(structure, reference, q, name)
    # Every regular q is found, also where axes 4 and 6 are parallel (q5 = 180 deg on the
    # Jaco 2's 55 deg wrist and on the CRX-10iA: other solutions of the pose form curves).
    regular = [m.tolist() for m in missed if sigma_min(reference, m) >= NEAR_SINGULAR]
    assert not regular, f"{name}: {len(missed)=} {regular=}"


@pytest.mark.slow
@pytest.mark.parametrize("kernel", ["Haswell", "Zen", "SkylakeX", "Sandybridge", "Prescott"])
def test_round_joint_angles_whatever_the_blas_kernel(kernel):
    """The round-angle poses of the CRX-10iA and the Jaco 2 with OpenBLAS's kernels of other CPUs
    (``OPENBLAS_CORETYPE``; AMD EPYC runs Zen's): the eigenvalues of a multiple root differ with
    the kernel, the branches do not (CI once lost q = (180, 45, 45, 0, 90, 0) deg on an AMD
    machine with Python 3.13's NumPy)."""
    import subprocess
    import sys

    paths = [os.path.dirname(os.path.abspath(__file__)), str(TESTS)]  # this module, support
    code = (
        f"import sys; sys.path[:0] = {paths!r}; import test_ik_general_6r as t; "
        "[t.test_round_joint_angles(name) for name in ('crx10ia', 'jaco2_6dof')]"
    )
    env = dict(os.environ, OPENBLAS_CORETYPE=kernel, OPENBLAS_VERBOSE="2")
    run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]


@pytest.mark.slow
def test_every_least_squares_solution_is_a_branch():
    """200 least-squares starts (no limits) on a few poses: each distinct solution is a branch."""
    arms = [random_arm(7, "standard"), random_arm(8, "modified")]
    arms.append((load_table(SIX_R / "xarm6.toml"), load_reference(SIX_R / "xarm6.toml")))
    for table, reference in arms:
        structure = General6R.recognise(table)
        rng = np.random.default_rng(11)
        q = rng.uniform(-PI, PI, 6)
        pose = reference_tool(reference, q[None])[0]
        branches = structure.solve(pose[:3, 3], pose[:3, :3])
        branches = branches[~np.isnan(branches[:, 0])]

        def residual(x, pose=pose, reference=reference):
            return (reference_tool(reference, x[None])[0] - pose)[:3].ravel()

        solutions = least_squares_solutions(residual, rng, 200)
        assert solutions, table.name
        for solution in solutions:
            assert wrapped_gap(branches, solution).min() < 1e-6, f"{table.name}: {solution=}"
        assert len(branches) >= len(solutions)


@pytest.mark.parametrize(
    "name", [pytest.param(n, marks=pytest.mark.slow) if n == "piper" else n for n in REAL_ARMS]
)
def test_real_arms_every_branch_and_the_family(name):
    """The makers' tables: the registry's family; General6R (asked directly) recovers q and its
    branches reach FK(q) on 300 poses; on PiPER it finds the spherical-wrist family's count."""
    table = load_table(SIX_R / f"{name}.toml")
    reference = load_reference(SIX_R / f"{name}.toml")
    family = registry.recognise(table)
    assert family.name == REAL_ARMS[name]
    structure = General6R.recognise(table)
    q = np.random.default_rng(5).uniform(-PI, PI, (300, 6))
    missed, found = check_round_trips(structure, reference, q, name)
    assert not missed, f"{name}: {missed=}"
    if family is not structure and not isinstance(family, General6R):
        poses = reference_tool(reference, q)
        theirs = family.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
        count = (~np.isnan(found[..., 0])).sum(axis=1)
        assert np.array_equal(count, (~np.isnan(theirs[..., 0])).sum(axis=1)), name


def test_gen3_lite_from_the_makers_urdf():
    """Kinova's Gen3 lite URDF (axes 2 and 3 parallel but for the rounding of pi to 3.1416):
    loaded through the URDF extraction, it gets this form; on 300 poses (FK by Pinocchio of the
    original URDF, not of the extraction) the q is among the branches and every branch, valid or
    rejected, reaches the pose on that URDF to 1e-9."""
    import pinocchio as pin

    path = SIX_R / "gen3_lite.urdf"
    robot = kin.load_robot(path)
    solver = get_solver(robot)
    assert solver.name == "closed_form:general_6r"
    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    frame = model.getFrameId("end_effector_link")

    def tool(q: np.ndarray) -> pin.SE3:
        pin.framesForwardKinematics(model, data, q)
        return data.oMf[frame].copy()

    rng = np.random.default_rng(11)
    missed = []
    for q in rng.uniform(model.lowerPositionLimit, model.upperPositionLimit, (300, 6)):
        pose = tool(q)
        result = solver.solve(PoseTarget(pose.translation, pose.rotation))
        assert result.success, result.message
        branches = np.array([s.q for s in result.solutions + result.rejected])
        for branch in branches:
            error = pin.log6(tool(branch).actInv(pose)).vector
            assert np.abs(error).max() < TOL, f"{q=} {branch=}"
        if wrapped_gap(branches, q).min() > JOINT_TOL:
            missed.append(q)
    assert not missed, f"{missed=}"


#: ssik prepares each non-Pieper arm once (a symbolic derivation, about 45 s here, cached in the
#: tests' private cache folder): the xArm6 by default, every arm with KIN_GENERAL_6R_SSIK=all.
SSIK_ARMS = list(REAL_ARMS) if os.environ.get("KIN_GENERAL_6R_SSIK") == "all" else ["xarm6"]


@pytest.mark.peer
@pytest.mark.parametrize("name", SSIK_ARMS)
def test_branch_counts_match_ssik(name):
    """ssik (enumerate_windings=False, no limits) finds as many solutions as we do per pose, each
    of its solutions among our branches (200 poses per arm)."""
    ssik = pytest.importorskip("ssik")
    from kin.ik.analytic.six_r.general_6r import chain_transforms

    table = load_table(SIX_R / f"{name}.toml")
    reference = load_reference(SIX_R / f"{name}.toml")
    structure = General6R.recognise(table)
    peer = ssik.Manipulator.from_transforms(chain_transforms(table)[0])
    q = np.random.default_rng(9).uniform(-PI, PI, (200, 6))
    poses = reference_tool(reference, q)
    ours = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    same = 0
    for pose, branches in zip(poses, ours):
        theirs = [s.q for s in peer.solve(pose, respect_limits=False, enumerate_windings=False)]
        exist = branches[~np.isnan(branches[:, 0])]
        for solution in theirs:
            assert wrapped_gap(exist, solution).min() < 1e-6, f"{name}: {solution=}"
        same += len(theirs) == len(exist)
    assert same >= 0.99 * len(poses), f"{name}: {same=}"


def test_the_documented_call_returns_every_branch():
    """get_solver(robot).solve(PoseTarget): closed_form:general_6r, every branch verified, valid
    or rejected (limits), as many as the structure gives."""
    table = load_table(SIX_R / "xarm6.toml")
    robot = kin.robot_from_table(table)
    solver = get_solver(robot)
    assert solver.name == "closed_form:general_6r"
    structure = General6R.recognise(table)
    reference = load_reference(SIX_R / "xarm6.toml")
    q = np.random.default_rng(2).uniform(reference.lower, reference.upper, (40, 6))
    for pose, start in zip(reference_tool(reference, q), q):
        result = solver.solve(PoseTarget(pose[:3, 3], pose[:3, :3]))
        assert result.success and result.method == "closed_form", result.message
        count = (~np.isnan(structure.solve(pose[:3, 3], pose[:3, :3])[:, 0])).sum()
        assert len(result.solutions) + len(result.rejected) == count
        assert min(wrapped_gap(np.array([s.q for s in result.solutions]), start)) < JOINT_TOL


@pytest.mark.parametrize("chunk", [general_6r.CHUNK, 7])
def test_batch_gives_the_same_numbers_as_solve(chunk, monkeypatch):
    """solve_batch equals solve row by row (NaN alike), reachable and unreachable targets; also
    when it takes the poses in chunks (of 7 here: 60 poses, the last chunk short)."""
    monkeypatch.setattr(general_6r, "CHUNK", chunk)
    table, reference = random_arm(3, "modified")
    structure = General6R.recognise(table)
    poses = reference_tool(reference, np.random.default_rng(4).uniform(-PI, PI, (60, 6)))
    poses[:10, :3, 3] *= 10.0  # out of reach
    batch = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    assert batch.shape == (60, BRANCHES, 6)
    scalar = np.array([structure.solve(T[:3, 3], T[:3, :3]) for T in poses])
    assert np.isnan(batch[:10]).all()
    np.testing.assert_array_equal(np.isnan(batch), np.isnan(scalar))
    np.testing.assert_allclose(batch, scalar, rtol=0.0, atol=1e-9, equal_nan=True)


def test_registry_order_and_the_families_keep_their_arms():
    """General6R is asked last; the shipped 6R arms keep their families."""
    assert registry.CLOSED_FORMS[-1] is General6R
    for name in ("ur5", "ur10", "puma560"):
        structure = registry.recognise(load_table(get_robot(name).table_path))
        assert not isinstance(structure, General6R), name


def test_refusals():
    """Not 6 revolute joints; axes 1 and 2 one line (q1 + q2 only: no isolated solutions); a
    rounded spherical-wrist table (its idealised family answers, polished)."""
    table, _ = random_arm(5, "standard")
    rows = list(table.rows)
    r = rows[2]
    rows[2] = DHRow(3, r.name, "prismatic", r.a, r.alpha, r.d, r.theta, 0.0, 1.0, 1.0, 1.0)
    with pytest.raises(StructureError, match="prismatic"):
        General6R.recognise(DHTable("p", "", "", "standard", tuple(rows)))
    with pytest.raises(StructureError, match="5 joints"):
        General6R.recognise(DHTable("five", "", "", "standard", table.rows[:5]))
    rng = np.random.default_rng(6)
    a, d = rng.uniform(-0.5, 0.5, (2, 6))
    alpha, theta = rng.uniform(-PI, PI, (2, 6))
    a[0], alpha[0] = 0.0, 0.0  # standard row 1: axis 2 is axis 1
    with pytest.raises(StructureError, match="no elimination"):
        General6R.recognise(make_table(a, alpha, d, theta))
    puma = load_table(get_robot("puma560").table_path)
    rounded = tuple(
        DHRow(
            r.index,
            r.name,
            r.joint_type,
            r.a,
            round(r.alpha, 4),
            r.d,
            r.theta,
            r.lower,
            r.upper,
            r.velocity,
            r.effort,
        )  # fmt: skip
        for r in puma.rows
    )
    rounded_table = DHTable("puma_rounded", "", "", puma.convention, rounded,
                            puma.T_world_base, puma.T_last_tool)  # fmt: skip
    with pytest.raises(StructureError, match="once rounded values are snapped"):  # given the rivals
        General6R.recognise(rounded_table, rivals=registry.CLOSED_FORMS)  # as the registry does
    assert get_solver(kin.robot_from_table(rounded_table)).name != "closed_form:general_6r"


def test_a_degenerate_table_is_no_crash():
    """Lengths of 1e-300 m overflow the elimination's companion matrix: the structure is refused
    (StructureError, the numeric solver answers), no LinAlgError; a 7R of them too."""
    for dof in (6, 7):
        table = make_table([1e-300] * dof, [0.3] * dof, [1e-300] * dof, [0.0] * dof)
        solver = get_solver(kin.robot_from_table(table))
        result = solver.solve(PoseTarget([0.0, 0.0, 0.0], np.eye(3)), timeout=0.05)
        assert result.status in ("ok", "not_found", "timeout", "out_of_reach", "singular")
    with pytest.raises(StructureError):
        General6R.recognise(make_table([1e-300] * 6, [0.3] * 6, [1e-300] * 6, [0.0] * 6))
