"""The 6R families' twins on their special cases (``_three_parallel.c``'s UR case, ``_pieper_arms.c``'s
spherical wrist) against Python.

- ``solve``: the twin's 8 branches equal the Python module's (``compiled=False``) to 1e-12 rad,
  NaN rows alike, on the shipped arms and on random tables of each family in both conventions
  (moved base, tool, joint offsets), targets in and out of reach;
- ``solve_batch``: the twin's equals the NumPy one to 1e-9 rad;
- ``verify`` (the path :class:`ClosedFormSolver` takes for a pose): the same solutions, order,
  labels, limit flags and rejected branches as the Python path that measures with Pinocchio, with
  random seeds (some beyond the fast-path range) and narrow limits that force the ``2 pi`` copies
  and rejections;
- the twin's DH product (the judge of the compiled path) against Pinocchio's FK at random q, on a
  table other than the one the branches came from (so the errors are not zero);
- the layout each twin declares matches the Python parameter fields.

Skipped when the twins are not built (no C compiler at install).
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pytest
from support import TESTS
from support.arm_tables import Reference, assert_layout_matches, make_table, random_pose
from support.six_r_twin_parity import assert_same_result, narrow_limits, targets
from support.spherical_wrist_arms import ARMS as PIEPER_ARMS
from support.spherical_wrist_arms import arm_table as pieper_table
from support.ur_wrist_arms import UR5 as UR_ARMS
from support.ur_wrist_arms import arm_table as ur_table

import kin
from dh2urdf import get_robot, load_table
from kin._native import twin as built_twin
from kin.ik import ClosedFormSolver, PoseTarget
from kin.ik.analytic.six_r.six_r_twin import OFF_TARGET, OUTSIDE_LIMITS, TwinVerifier, check_params
from kin.ik.analytic.six_r.spherical_wrist import SphericalWrist6R
from kin.ik.analytic.six_r.ur_wrist import URWrist6R
from kin.ik.result import IKResult, IKSolution

PI = math.pi
BUILT = URWrist6R.compiled_twin is not None and SphericalWrist6R.compiled_twin is not None
pytestmark = pytest.mark.skipif(not BUILT, reason="the 6R compiled twins are not built")

CASES = [("ur", arm) for arm in UR_ARMS] + [("pieper", arm) for arm in PIEPER_ARMS]


def case(kind: str, arm: str):
    """The table and its structure."""
    if kind == "ur":
        table = ur_table(arm)
        return table, URWrist6R.recognise(table)
    table = pieper_table(arm)
    return table, SphericalWrist6R.recognise(table)


@pytest.mark.parametrize(("kind", "arm"), CASES)
def test_twin_solve_equals_python(kind, arm):
    """The twin's branches are the Python solve's, target by target (1e-12 rad, NaN alike)."""
    table, structure = case(kind, arm)
    poses = targets(table, 300, 5)
    for T in poses:
        python = structure.solve(T[:3, 3], T[:3, :3], compiled=False)
        twin = structure.solve(T[:3, 3], T[:3, :3])
        np.testing.assert_array_equal(np.isnan(twin), np.isnan(python))
        np.testing.assert_allclose(twin, python, rtol=0.0, atol=1e-12, equal_nan=True)


@pytest.mark.parametrize(("kind", "arm"), CASES)
def test_twin_batch_equals_numpy_batch(kind, arm):
    """The twin's solve_batch equals the NumPy solve_batch (1e-9 rad: NumPy's own vector libm)."""
    table, structure = case(kind, arm)
    poses = targets(table, 2000, 6)
    twin = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3])
    numpy = structure.solve_batch(poses[:, :3, 3], poses[:, :3, :3], compiled=False)
    assert twin.shape == numpy.shape == (2000, 8, 6)
    np.testing.assert_array_equal(np.isnan(twin), np.isnan(numpy))
    np.testing.assert_allclose(twin, numpy, rtol=0.0, atol=1e-9, equal_nan=True)
    assert np.isnan(twin[:200]).mean() > 0.5
    assert not np.isnan(twin[200:, 0]).all()


@pytest.mark.parametrize(("kind", "arm"), CASES)
def test_compiled_solver_equals_python_solver(kind, arm):
    """ClosedFormSolver's compiled path returns what its Python path (Pinocchio judge) returns."""
    table, _ = case(kind, arm)
    rng = np.random.default_rng(17)
    for variant in range(2):
        arm_table = table if variant == 0 else narrow_limits(table, rng)
        robot = kin.robot_from_table(arm_table)
        compiled = ClosedFormSolver(robot)
        python = ClosedFormSolver(robot, compiled=False)
        assert compiled._twin is not None and python._twin is None
        rejected = 0
        for k, T in enumerate(targets(arm_table, 120, 7 + variant)):
            target = PoseTarget(T[:3, 3], T[:3, :3])
            seed = None if k % 4 == 0 else rng.uniform(-2 * PI, 2 * PI, 6)
            if seed is not None and k % 9 == 2:
                seed = seed + 2e5  # beyond the fast path: every angle takes the exact copy
            ours, theirs = compiled.solve(target, seed), python.solve(target, seed)
            assert_same_result(ours, theirs, f"{arm=} {variant=} {k=}")
            rejected += len(ours.rejected)
        assert variant == 0 or rejected > 0, "the narrow limits rejected no branch"


def test_compiled_solver_reports_like_python_for_bad_targets():
    """Non-finite targets, wrong seeds and far targets: the same statuses and errors."""
    robot = kin.robot_from_table(load_table(get_robot("ur5").table_path))
    compiled, python = ClosedFormSolver(robot), ClosedFormSolver(robot, compiled=False)
    overwritten = PoseTarget([0.0, 0, 0], np.eye(3))
    overwritten.position.flags.writeable = True  # read-only after the constructor's check
    overwritten.position[0] = math.nan
    for target in (overwritten, PoseTarget([5.0, 0, 0], np.eye(3))):
        assert_same_result(compiled.solve(target), python.solve(target), str(target.position))
    with pytest.raises(kin.ik.TargetError, match="must have 6 values"):
        compiled.solve(PoseTarget([0.3, 0.1, 0.3], np.eye(3)), [0.0] * 5)
    with pytest.raises(kin.ik.TargetError, match="finite"):
        compiled.solve(PoseTarget([0.3, 0.1, 0.3], np.eye(3)), [math.nan] * 6)


@pytest.mark.parametrize(("kind", "arm"), [CASES[1], CASES[4], CASES[-3], CASES[-1]])
def test_twin_fk_agrees_with_pinocchio(kind, arm):
    """The twin's judge (the table's DH product in C) measures like Pinocchio's FK.

    The check block is built from a perturbed table (other d, theta, base, tool): every branch of
    the original table is then off target by a finite amount that the twin reports, and that
    Pinocchio's FK of the perturbed table must give too.
    """
    table, structure = case(kind, arm)
    rng = np.random.default_rng(29)
    rows = tuple(
        dataclasses.replace(row, d=row.d + rng.uniform(-0.05, 0.05), theta=row.theta + 0.1)
        for row in table.rows
    )
    other = dataclasses.replace(
        table, rows=rows, T_world_base=random_pose(rng), T_last_tool=random_pose(rng)
    )
    twin = structure.compiled_twin
    lower, upper = [-2 * PI] * 6, [2 * PI] * 6
    verifier = TwinVerifier(
        twin, structure.c_params, check_params(twin, other, lower, upper, 1e-9, 1e-9)
    )
    reference = Reference(other)
    checked = 0
    for T in targets(table, 60, 31)[6:]:
        found, q, info = verifier(T[:3, 3].copy(), T[:3, :3].copy(), np.zeros(6))
        for b in range(8):
            if np.isnan(q[b, 0]):
                continue
            position_error, rotation_error = reference.errors(q[b], _se3(T))
            assert info[b][0] == OFF_TARGET
            assert abs(info[b][1] - position_error) < 1e-12
            assert abs(info[b][2] - rotation_error) < 1e-9 * max(1.0, rotation_error)
            checked += 1
    assert checked > 100


def _se3(T):
    import pinocchio as pin

    return pin.SE3(T[:3, :3].copy(), T[:3, 3].copy())


def test_outside_limits_status_is_reported():
    """A UR5 with joint 2 limited to [0, 0.1] rad: branches on target outside it are rejected."""
    table = load_table(get_robot("ur5").table_path)
    rows = list(table.rows)
    rows[1] = dataclasses.replace(rows[1], lower=0.0, upper=0.1)
    narrow = dataclasses.replace(table, rows=tuple(rows))
    structure = URWrist6R.recognise(narrow)
    twin = structure.compiled_twin
    verifier = TwinVerifier(
        twin, structure.c_params, check_params(twin, narrow, [r.lower for r in rows],
                                               [r.upper for r in rows], 1e-9, 1e-9)
    )  # fmt: skip
    T = kin.batch_forward_kinematics(table, np.array([[0.3, -1.2, 1.4, -0.8, 1.1, 0.4]]))[0]
    found, q, info = verifier(T[:3, 3].copy(), T[:3, :3].copy(), np.zeros(6))
    assert found == 8
    assert [row[0] for row in info] == [OUTSIDE_LIMITS] * 8
    assert max(row[1] for row in info) < 1e-9
    assert not q.flags.writeable


@pytest.mark.parametrize("structure_class", [URWrist6R, SphericalWrist6R])
def test_layout_matches_python_fields(structure_class):
    """Each twin's LAYOUT names the structure's c_fields, at the offsets c_params uses."""
    name = "ur5" if structure_class is URWrist6R else "puma560"
    structure = structure_class.recognise(load_table(get_robot(name).table_path))
    assert_layout_matches(structure, structure.compiled_twin)
    twin = structure.compiled_twin
    assert [n for n, _, _ in twin.CHECK_LAYOUT][:4] == ["modified", "a", "cos_alpha", "sin_alpha"]
    assert sum(size for _, _, size in twin.CHECK_LAYOUT) == twin.CHECK_COUNT


def test_table_of_either_convention_gives_the_same_check():
    """A modified table's check block describes the same arm: the twin finds FK(q)'s q."""
    table = make_table([0, 0, 0.3, 0.25, 0, 0], [0, PI / 2, 0, 0, PI / 2, -PI / 2],
                       [0.1, 0, 0, 0.11, 0.09, 0.08], [0] * 6, "modified")  # fmt: skip
    structure = URWrist6R.recognise(table)
    q0 = np.array([0.4, -1.0, 1.2, -0.5, 0.8, 0.3])
    T = kin.batch_forward_kinematics(table, q0[None])[0]
    twin = structure.compiled_twin
    lower, upper = [-2 * PI] * 6, [2 * PI] * 6
    verifier = TwinVerifier(
        twin, structure.c_params, check_params(twin, table, lower, upper, 1e-9, 1e-9)
    )
    found, q, info = verifier(T[:3, 3].copy(), T[:3, :3].copy(), q0)
    best = int(np.argmin([row[3] for row in info]))
    assert found == 8 and info[best][0] == 1
    np.testing.assert_allclose(q[best], q0, atol=1e-9)


def _flipped_ur5():
    """UR5 with joints 1 and 4 written reversed (``direction = -1``) and joint 1 limited."""
    table = load_table(get_robot("ur5").table_path)
    rows = list(table.rows)
    rows[0] = dataclasses.replace(rows[0], direction=-1, lower=-1.0, upper=2.5)
    rows[3] = dataclasses.replace(rows[3], direction=-1)
    return dataclasses.replace(table, rows=tuple(rows), name="ur5_flipped")


@pytest.mark.parametrize("form", ["array", "list", "int", "row", "none"])
def test_compiled_solver_with_reversed_joints_equals_python_solver(form):
    """The twin's whole answer (directions mapped in C) equals the Python path, any seed form."""
    table = _flipped_ur5()
    robot = kin.robot_from_table(table)
    compiled, python = ClosedFormSolver(robot), ClosedFormSolver(robot, compiled=False)
    assert compiled._solutions is not None and compiled.arm.directions is not None
    rng = np.random.default_rng(5)
    for k, T in enumerate(targets(table, 60, 11)):
        target = PoseTarget(T[:3, 3], T[:3, :3])
        values = rng.uniform(-PI, PI, 6)
        seed = {
            "array": values,
            "list": values.tolist(),
            "int": np.rint(values).astype(int),
            "row": values[None, :],
            "none": None,
        }[form]
        ours, theirs = compiled.solve(target, seed), python.solve(target, seed)
        assert_same_result(ours, theirs, f"{form=} {k=}")
        for solution in (*ours.solutions, *ours.rejected):
            assert not solution.q.flags.writeable, f"{form=} {k=}"


def arrays(position: np.ndarray, rotation: np.ndarray) -> SimpleNamespace:
    """A target of two arrays as they are (unchecked, unpacked): what the twin reads of one."""
    return SimpleNamespace(position=position, rotation=rotation, _packed=None)


def test_solutions_refuses_malformed_arguments():
    """Wrong blocks, targets or classes: a Python error (never a crash); odd seeds: -2."""
    table = load_table(get_robot("ur5").table_path)
    solver = ClosedFormSolver(kin.robot_from_table(table))
    bound = solver._solutions
    twin, fixed = bound.func, bound.args
    p, r = np.array([0.4, 0.1, 0.3]), np.diag([1.0, -1.0, -1.0])
    result = bound(PoseTarget(p, r), None, 0.0)
    assert bound(arrays(p, r), None, 0.0).solutions[0].branch == result.solutions[0].branch
    assert isinstance(result, IKResult) and result.success and result.time > 0.0
    assert [f.name for f in dataclasses.fields(IKResult)] == list(IKResult.__slots__)
    assert all(hasattr(result, f.name) for f in dataclasses.fields(IKResult))
    for seed in ([0.0] * 6, np.zeros(5), np.zeros(6, dtype=np.float32), np.full(6, np.nan)):
        assert bound(arrays(p, r), seed, 0.0) == -2, seed
    assert bound(arrays(np.array([np.inf, 0, 0]), r), None, 0.0) == -1
    assert bound(arrays(np.array([50.0, 0, 0]), r), None, 0.0) == 0
    with pytest.raises(TypeError, match="position, rotation"):
        bound(arrays(p.astype(np.float32), r), None, 0.0)
    with pytest.raises(TypeError, match="position, rotation"):
        bound(arrays(p, np.asfortranarray(r[:, ::-1])), None, 0.0)
    with pytest.raises(TypeError, match="must be real number"):
        bound(arrays(p, r), None, "now")
    with pytest.raises(TypeError, match="solutions"):
        twin(*fixed[:2])
    changes = {
        0: fixed[0][:-8],
        1: fixed[1] + b"\0" * 8,
        2: b"\0" * 8,
        3: "IKSolution",
        4: fixed[4][:7],
        5: None,
        7: fixed[7][:3],
        8: "perf_counter",
    }
    for index, value in changes.items():
        args = list(fixed)
        args[index] = value
        with pytest.raises(ValueError, match="bytes of the blocks"):
            twin(*args, arrays(p, r), None, 0.0)


def test_result_made_in_c_equals_the_python_result_field_by_field():
    """The IKResult the twin makes: every field as the Python path gives it (time aside)."""
    table = load_table(get_robot("ur5").table_path)
    robot = kin.robot_from_table(table)
    compiled, python = ClosedFormSolver(robot), ClosedFormSolver(robot, compiled=False)
    for k, T in enumerate(targets(table, 40, 3)[4:]):
        target = PoseTarget(T[:3, 3], T[:3, :3])
        ours, theirs = compiled.solve(target), python.solve(target)
        assert ours.success, k
        fields = [field.name for field in dataclasses.fields(IKResult)]
        mine = {name: getattr(ours, name) for name in fields}  # every slot filled
        other = {name: getattr(theirs, name) for name in fields}
        for key in ("success", "solver", "status", "message", "distance_to_workspace",
                    "iterations", "method", "free"):  # fmt: skip
            assert mine[key] == other[key] and type(mine[key]) is type(other[key]), (k, key)
        assert type(ours.solutions) is tuple and type(ours.rejected) is tuple
        assert all(type(s) is IKSolution for s in (*ours.solutions, *ours.rejected))
        names = [field.name for field in dataclasses.fields(IKSolution)]
        for s, o in zip(ours.solutions, theirs.solutions, strict=True):
            for name in names:  # every slot filled, with the Python path's types
                assert type(getattr(s, name)) is type(getattr(o, name)), (k, name)
            assert s.branch == o.branch and np.allclose(s.q, o.q, atol=1e-12), k
        assert 0.0 < ours.time < 1.0


def test_off_target_branches_are_logged_and_dropped(caplog):
    """A check block of another arm: every branch is off target, none returned, each logged."""
    table, structure = case("ur", UR_ARMS[0])
    other = dataclasses.replace(table, T_last_tool=random_pose(np.random.default_rng(3)))
    twin = structure.compiled_twin
    verifier = TwinVerifier(
        twin, structure.c_params, check_params(twin, other, [-2 * PI] * 6, [2 * PI] * 6, 1e-9, 1e-9)
    )
    bound = verifier.solutions(None, structure.branch_labels, "ur_wrist")
    T = kin.batch_forward_kinematics(table, np.array([[0.3, -1.2, 1.4, -0.8, 1.1, 0.4]]))[0]
    valid, rejected, off = bound(arrays(T[:3, 3].copy(), T[:3, :3].copy()), np.zeros(6), 0.0)
    assert valid == () and rejected == () and len(off) == 8
    assert {label for label, _, _ in off} == set(structure.branch_labels)
    assert all(position > 1e-6 for _, position, _ in off)


def test_solutions_made_in_c_pickle_copy_and_stay_frozen():
    """The twin's IKSolution (slots written in C) behaves as one made in Python."""
    import copy
    import pickle

    table = load_table(get_robot("ur5").table_path)
    solver = ClosedFormSolver(kin.robot_from_table(table))
    T = targets(table, 1, 5)[0]
    solution = solver.solve(PoseTarget(T[:3, 3], T[:3, :3])).solutions[0]
    for twin in (
        pickle.loads(pickle.dumps(solution)),
        copy.copy(solution),
        copy.deepcopy(solution),
    ):
        assert type(twin) is IKSolution and twin.branch == solution.branch
        assert np.array_equal(twin.q, solution.q)
        assert twin.rotation_error == solution.rotation_error
    with pytest.raises(dataclasses.FrozenInstanceError):
        solution.q = np.zeros(6)  # type: ignore[misc]


@pytest.mark.parametrize(
    ("module", "family", "arms", "arm"),
    [
        ("_pieper_arms", "pieper.Pieper6R", "pieper_arms", "general_standard_0"),
        ("_three_parallel", "three_parallel.ThreeParallel6R", "three_parallel_arms",
         "general_standard_0"),
    ],
)  # fmt: skip
def test_a_twin_called_before_its_lapack_is_loaded_raises_instead_of_crashing(
    module, family, arms, arm
):
    """A general arm's quartic met before ``load_lapack``: a RuntimeError, not a jump to NULL.

    In a fresh process whose twin never loads LAPACK (its ``load_lapack`` replaced), the family's
    solve of a pose of a general arm (one with a quartic) raises.
    """
    if built_twin(module) is None:
        pytest.skip("the compiled twin is not built")
    structure_module, structure = family.split(".")
    code = f"""
import sys
sys.path.insert(0, {str(TESTS)!r})
import numpy as np
import kin
from kin.ik.analytic.six_r import {module} as twin
twin.load_lapack = lambda *args: None  # never loaded
from kin.ik.analytic.six_r.{structure_module} import {structure}
from support.{arms} import arm_table
table = arm_table({arm!r})
pose = kin.batch_forward_kinematics(table, np.full((1, 6), 0.3))[0]
try:
    {structure}.recognise(table).solve(pose[:3, 3], pose[:3, :3])
except RuntimeError as error:
    assert "load_lapack" in str(error), error
    print("raised")
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert (done.returncode, done.stdout.strip()) == (0, "raised"), done.stderr
