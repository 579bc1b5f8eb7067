"""IK for every DH table: dispatch, numeric round trips on ur5, panda and user tables, the cache.

Every returned joint vector is re-checked here by the plain NumPy DH product of
``tests/support/dh_reference.py`` (independent of dh2urdf, kin and Pinocchio).
"""

from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
from support.cli_helper import write_rrpr4
from support.dh_reference import fk_frames, load_reference, rotation_angle
from support.solver_caps import NO_CAP

import kin
import kin.ik as ik
from dh2urdf import get_robot
from kin import load_robot
from kin.ik import (
    AxisTarget,
    ClosedFormSolver,
    NumericIK,
    PitchTarget,
    PoseTarget,
    PositionTarget,
    TargetError,
    get_solver,
    solve_ik,
)

#: The paper arms a closed form solves whole (humanoid7: numeric, closed form with a free joint).
CLOSED_FORM_ARMS = ("lab5", "ned5", "pickplace3", "planar2", "scorbot")
#: The shipped 6R arms and the closed-form structure their tables fit.
SIX_R_ARMS = {
    "puma560": "spherical_wrist",
    "ur3": "ur_wrist",
    "ur5": "ur_wrist",
    "ur10": "ur_wrist",
}
#: The stages of the numeric pipeline (``IKResult.method``).
NUMERIC_METHODS = ("closed_form_free_joint", "seed_table", "damped_newton", "random_restart")
NUMERIC_METHODS += ("mink_qp",)

#: A three-joint arm of no closed-form structure (twists neither 0 nor 90 deg), in SI units.
USER_3R = """
name = "user3r"
description = "random 3R test arm"
source = "tests/ik/test_ik_any_table.py"
convention = "standard"
length_unit = "m"
angle_unit = "rad"

[[joints]]
name = "j1"
type = "revolute"
a = 0.05
alpha = 1.1
d = 0.2
theta = 0.1
limits = [-2.5, 2.5]

[[joints]]
name = "j2"
type = "revolute"
a = 0.25
alpha = -0.4
d = 0.03
theta = 0.0
limits = [-2.0, 2.0]

[[joints]]
name = "j3"
type = "revolute"
a = 0.2
alpha = 0.7
d = 0.0
theta = -0.2
limits = [-2.2, 2.2]
"""

#: A six-joint arm with a prismatic second joint (a full pose is within its reach).
USER_RPRRRR = """
name = "rprrrr"
description = "six-joint test arm with a prismatic joint"
source = "tests/ik/test_ik_any_table.py"
convention = "standard"
length_unit = "m"
angle_unit = "rad"

[[joints]]
name = "yaw"
type = "revolute"
a = 0.0
alpha = 1.5707963267948966
d = 0.3
theta = 0.0
limits = [-3.0, 3.0]

[[joints]]
name = "lift"
type = "prismatic"
a = 0.1
alpha = 1.5707963267948966
d = 0.1
theta = 0.0
limits = [0.0, 0.3]

[[joints]]
name = "elbow"
type = "revolute"
a = 0.2
alpha = 0.0
d = 0.0
theta = 0.0
limits = [-2.5, 2.5]

[[joints]]
name = "wrist1"
type = "revolute"
a = 0.0
alpha = 1.5707963267948966
d = 0.0
theta = 0.0
limits = [-3.0, 3.0]

[[joints]]
name = "wrist2"
type = "revolute"
a = 0.0
alpha = -1.5707963267948966
d = 0.15
theta = 0.0
limits = [-3.0, 3.0]

[[joints]]
name = "wrist3"
type = "revolute"
a = 0.0
alpha = 0.0
d = 0.08
theta = 0.0
limits = [-3.0, 3.0]
"""


def _write(folder: Path, name: str, text: str) -> Path:
    path = folder / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def user_tables(tmp_path_factory) -> dict[str, Path]:
    """User table files: a random 3R, a SCARA-like R-R-P-R, a six-joint arm with a prismatic."""
    folder = tmp_path_factory.mktemp("tables")
    return {
        "user3r": _write(folder, "user3r", USER_3R),
        "rrpr4": write_rrpr4(folder),
        "rprrrr": _write(folder, "rprrrr", USER_RPRRRR),
    }


def _reference_path(name: str, user_tables: dict[str, Path]) -> Path:
    return user_tables[name] if name in user_tables else get_robot(name).table_path


def _round_trip(
    path: Path, robot, full_pose: bool, count: int, seed: int, solver=None
) -> tuple[int, list]:
    """Targets from the reference FK of random q inside the limits, solved, re-checked.

    ``solver``: the robot's own (:func:`get_solver`) when None.

    Returns the number of verified answers and the methods that answered.
    """
    reference = load_reference(path)
    rng = np.random.default_rng(seed)
    qs = rng.uniform(reference.lower, reference.upper, size=(count, reference.dof))
    poses = fk_frames(reference, qs)[:, -1]
    solver = get_solver(robot) if solver is None else solver
    good, methods = 0, []
    for pose in poses:
        if full_pose:
            target: object = PoseTarget(pose[:3, 3], pose[:3, :3])
        else:
            target = PositionTarget(pose[:3, 3])
        result = solver.solve(target)
        if not result.success:
            continue
        solution = result.solutions[0]
        q = solution.q
        reached = fk_frames(reference, q)[0, -1]
        position_error = float(np.linalg.norm(reached[:3, 3] - pose[:3, 3]))
        assert position_error < 1e-5, f"{robot.name=} {q=} {position_error=}"
        assert np.all(q >= reference.lower) and np.all(q <= reference.upper), f"{q=}"
        if full_pose:
            angle = float(rotation_angle(reached[:3, :3], pose[:3, :3]))
            assert angle < 1e-4, f"{robot.name=} {q=} {angle=}"
            assert solution.rotation_error == pytest.approx(angle, abs=1e-7)
        else:
            assert solution.rotation_error is None, f"{robot.name=}"
        closed_position = not isinstance(solver, NumericIK) and (
            PositionTarget in solver.closed_form_kinds  # a SCARA's position: its free joint stated
        )
        six_r = robot.nq == 6 and all(r.joint_type == "revolute" for r in robot.table.rows)
        near_seed = not isinstance(solver, NumericIK) and six_r and not full_pose
        if near_seed and PoseTarget in solver.closed_form_kinds and not closed_position:
            # A position on a 6R closed form: the answer nearest the seed (issue 43).
            assert result.solver == solver.name and result.method == "near_seed", f"{result=}"
        elif isinstance(solver, NumericIK) or (not full_pose and not closed_position):
            assert result.solver == "numeric" and result.method in NUMERIC_METHODS, f"{result=}"
        else:
            assert result.method == "closed_form", f"{result=}"
        good += 1
        methods.append(result.method)
    return good, methods


@pytest.mark.parametrize("name", CLOSED_FORM_ARMS)
def test_dispatch_picks_the_closed_form_for_the_paper_arms(name):
    """The five paper arms a closed form fits get it; its results say method closed_form."""
    solver = get_solver(load_robot(name))
    assert isinstance(solver, ClosedFormSolver), f"{name=}"
    assert solver.name.startswith("closed_form:"), f"{name=}"


@pytest.mark.parametrize("name", sorted(SIX_R_ARMS))
def test_dispatch_picks_the_six_r_closed_form_for_the_real_arms(name):
    """PUMA 560 and the UR arms: their tables fit a 6R closed form, read from the table."""
    solver = get_solver(load_robot(name))
    assert isinstance(solver, ClosedFormSolver), f"{name=}"
    assert solver.name == f"closed_form:{SIX_R_ARMS[name]}", f"{name=}"


@pytest.mark.parametrize("name", ["humanoid7", "panda", "xarm7"])
def test_dispatch_picks_the_numeric_solver_for_other_shipped_arms(name):
    """The seven-joint arms get the numeric solver, which starts with a free-joint closed form."""
    solver = get_solver(load_robot(name))
    assert isinstance(solver, NumericIK) and solver.name == "numeric", f"{name=}"
    assert solver.closed_form is not None, f"{name=}"


@pytest.mark.parametrize("name", ["user3r", "rprrrr"])
def test_dispatch_picks_the_numeric_solver_for_user_tables(name, user_tables):
    """A user table no closed form fits (3R, prismatic joints) gets the numeric solver."""
    solver = get_solver(load_robot(str(user_tables[name])))
    assert isinstance(solver, NumericIK), f"{name=}"


def test_scara_table_gets_the_parallel_axes_closed_form(user_tables):
    """rrpr4 (a SCARA: every axis parallel) gets the parallel-axes closed form for its poses."""
    solver = get_solver(load_robot(str(user_tables["rrpr4"])))
    assert solver.name == "closed_form:parallel_axes"


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_numeric_full_pose_round_trip_on_ur5_and_panda(name, user_tables):
    """The numeric pipeline alone (no closed form), full poses from FK of 300 random q: >= 99%
    verified within the default 50 ms budget, mostly from the seed table."""
    robot = load_robot(name)
    solver = NumericIK(robot, closed_form=False)
    path = _reference_path(name, user_tables)
    good, methods = _round_trip(path, robot, True, 300, 11, solver)
    assert good >= 0.99 * 300, f"{name=} {good=}"
    assert methods.count("seed_table") > 0.9 * good, f"{name=} {set(methods)=}"


@pytest.mark.parametrize("name", ["panda", "ur5", "user3r", "rrpr4", "rprrrr"])
def test_position_round_trip_on_any_table(name, user_tables):
    """Positions from FK of 100 random q: >= 99% verified, rotation_error None, inside limits."""
    path = _reference_path(name, user_tables)
    robot = load_robot(name if name in ("panda", "ur5") else str(path))
    good, _ = _round_trip(path, robot, False, 100, 12)
    assert good >= 99, f"{name=} {good=}"


def test_full_pose_round_trip_with_a_prismatic_joint(user_tables):
    """A six-joint arm with a prismatic joint: full poses from FK, >= 99% verified."""
    path = user_tables["rprrrr"]
    good, _ = _round_trip(path, load_robot(str(path)), True, 100, 13)
    assert good >= 99, f"{good=}"


def test_two_joint_arm_of_no_closed_form(tmp_path):
    """A non-planar 2R arm (alpha1 = 60 deg) reaches positions on its surface numerically."""
    text = USER_3R.replace("user3r", "user2r").split("[[joints]]")
    path = _write(tmp_path, "user2r", "[[joints]]".join(text[:3]))
    robot = load_robot(str(path))
    assert robot.nq == 2
    good, _ = _round_trip(path, robot, False, 50, 14)
    assert good >= 49, f"{good=}"


def test_full_pose_on_a_short_arm_is_solved_or_says_how_far(user_tables):
    """A full pose on a 3R user arm (issue #21): its own FK's pose is solved; an orientation it
    cannot take fails with the nearest pose's distances; a kind no solver takes names the kinds."""
    robot = load_robot(str(user_tables["user3r"]))
    q = np.array([0.3, -0.4, 0.5])
    pose = fk_frames(load_reference(user_tables["user3r"]), q[None])[0, -1]
    reached = solve_ik(robot, PoseTarget(pose[:3, 3], pose[:3, :3]))
    assert reached.success, reached.message
    assert reached.best.position_error < 1e-5 and reached.best.rotation_error < 1e-4
    tilted = pose[:3, :3] @ np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    missed = solve_ik(robot, PoseTarget(pose[:3, 3], tilted))
    assert not missed.success  # three joints cannot turn the tool a quarter turn in place
    assert missed.status == "not_found", missed.message  # a search: it claims no proof
    assert "the nearest pose found is" in missed.message
    assert missed.rejected and missed.rejected[0].rotation_error > 1e-4
    with pytest.raises(TargetError, match=r"takes a position, .*full pose target, not a position"):
        solve_ik(load_robot("ur5"), PitchTarget([0.3, 0.0, 0.3], 0.2))


def test_five_joint_arm_takes_all_three_kinds():
    """lab5: full pose and pitch by the closed form, a position by the numeric solver."""
    robot = load_robot("lab5")
    solver = get_solver(robot)
    assert set(solver.target_kinds) == {PoseTarget, PitchTarget, PositionTarget, AxisTarget}
    q = np.array([0.2, 0.3, -0.4, 0.2, 0.1])
    from kin import Configuration

    pose = Configuration(robot).fk(q)
    closed = solve_ik(robot, PoseTarget.from_matrix(pose))
    assert closed.success and closed.method == "closed_form", f"{closed.message=}"
    assert closed.solver == "closed_form:fivedof"
    numeric = solve_ik(robot, PositionTarget(pose.translation), timeout=NO_CAP)
    assert numeric.success and numeric.solver == "numeric", f"{numeric.message=}"
    assert numeric.method in NUMERIC_METHODS


def test_position_on_a_five_joint_arm_stays_near_the_seed():
    """lab5 position targets 1 cm apart, each seeded by the last answer: no joint jumps > 0.2 rad."""
    robot = load_robot("lab5")
    solver = get_solver(robot)
    q = np.array([0.0, 2.052, -1.9148, 1.3551, -0.1357])
    for y in np.linspace(0.0, 0.1, 11):
        result = solver.solve(PositionTarget([0.2, y, 0.2]), q, timeout=NO_CAP)
        assert result.success and result.solver == "numeric", f"{y=} {result.message=}"
        step = np.abs(result.solutions[0].q - q).max()
        assert step < 0.2, f"{y=} {step=}"
        q = result.solutions[0].q


def test_result_method_names_the_stage(user_tables):
    """humanoid7 answers from the free-joint closed form, ur5 from its own, a 6-joint arm with a
    prismatic joint from the seed table."""
    from kin import Configuration

    cases = (
        ("humanoid7", "numeric", "closed_form_free_joint"),
        ("ur5", "closed_form:ur_wrist", "closed_form"),
        (str(user_tables["rprrrr"]), "numeric", "seed_table"),
    )
    for name, solver, method in cases:
        robot = load_robot(name)
        pose = Configuration(robot).fk(np.full(robot.nq, 0.3))
        result = solve_ik(robot, PoseTarget.from_matrix(pose))
        assert result.success and result.method == method, f"{name=} {result.method=}"
        assert result.solver == solver
        assert (result.iterations == 0) == method.startswith("closed_form"), f"{name=}"


def test_unreachable_target_reports_out_of_reach_with_no_method():
    """A ur5 target 2 m away: out_of_reach, distance > 0, method empty."""
    result = solve_ik(load_robot("ur5"), PositionTarget([2.0, 0.0, 0.0]), timeout=0.05)
    assert not result.success and result.status == "out_of_reach" and result.method == ""
    assert result.distance_to_workspace > 0.5


def test_solver_protocol_timeout_keyword():
    """Every solver takes timeout= (the closed form ignores it)."""
    target = PositionTarget([0.1, 0.05, 0.0])
    for name in ("planar2", "humanoid7"):
        result = get_solver(load_robot(name)).solve(target, None, timeout=0.2)
        assert result.status in ("ok", "out_of_reach", "outside_limits", "not_found", "timeout")
    assert "solve_ik" in ik.__all__ and "NUMERIC_SOLVERS" not in ik.__all__


_CACHE_PROBE = """
import sys
from kin import load_robot
from kin.ik import NumericIK
from kin.ik.numeric import seed_cache
solver = NumericIK(load_robot(sys.argv[1]), table_size=3000)
_ = solver.table
print(seed_cache.BUILDS, len(solver.table), solver.table.q[17].tolist())
"""


def _probe(cache: Path, name: str) -> tuple[int, int, list]:
    env = dict(os.environ, XDG_CACHE_HOME=str(cache))
    env.pop("DH_KINEMATICS_NO_CACHE", None)
    out = subprocess.run(
        [sys.executable, "-c", _CACHE_PROBE, name],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    ).stdout.split(maxsplit=2)
    return int(out[0]), int(out[1]), eval(out[2])  # noqa: S307 - our own printout


def test_seed_table_cache_is_reused_and_a_corrupt_file_rebuilt(tmp_path):
    """A fresh process loads the cached table (no build); a corrupt file is rebuilt silently."""
    builds, size, sample = _probe(tmp_path, "ur5")
    assert (builds, size) == (1, 3000)
    files = list((tmp_path / "dh-kinematics").glob("seed_table_*.npz"))
    assert len(files) == 1
    builds, size, again = _probe(tmp_path, "ur5")
    assert (builds, size) == (0, 3000) and again == sample
    files[0].write_bytes(b"not a table")
    builds, size, rebuilt = _probe(tmp_path, "ur5")
    assert (builds, size) == (1, 3000) and rebuilt == sample
    assert _probe(tmp_path, "ur5")[0] == 0  # the rebuilt file is valid again
    builds, _, _ = _probe(tmp_path, "panda")  # another table: its own file
    assert builds == 1 and len(list((tmp_path / "dh-kinematics").glob("*.npz"))) == 2


def test_several_structures_per_joint_count(monkeypatch):
    """recognise asks every registered structure of the table's joint count, first fit wins."""
    from kin.ik.analytic import registry
    from kin.ik.analytic.planar.offset3r import Offset3R

    class Never:
        dof = 3

        @classmethod
        def recognise(cls, table):
            raise ik.StructureError(table.name, "never", "row 1: never fits")

    table = load_robot("pickplace3").table
    monkeypatch.setattr(registry, "CLOSED_FORMS", [Never, Offset3R])
    assert isinstance(registry.recognise(table), Offset3R)
    monkeypatch.setattr(registry, "CLOSED_FORMS", [Never, Never])
    with pytest.raises(ik.StructureError, match="row 1: never fits; row 1: never fits"):
        registry.recognise(table)


@dataclass(frozen=True)
class PlainPlanar:
    """A structure with only the required parts (as a pose-only 6R plug-in has): candidates."""

    name: ClassVar[str] = "plainplanar"
    dof: ClassVar[int] = 2
    target_kinds: ClassVar[tuple[type, ...]] = (PositionTarget,)
    branch_labels: ClassVar[tuple[str, ...]] = ("first", "second")
    inner: object

    @classmethod
    def recognise(cls, table):
        from kin.ik.analytic.planar.planar2r import Planar2R

        return cls(Planar2R.recognise(table))

    def solve(self, position, rotation):
        return self.inner.solve(position, rotation)

    def solve_batch(self, positions, rotations):
        return self.inner.solve_batch(positions, rotations)


def test_a_structure_with_only_the_required_parts_plugs_in(monkeypatch):
    """Registered first, a minimal structure answers both solvers with the same joint vectors as
    the shipped one (the solvers know no structure by name); a class missing a part is refused."""
    from kin.ik.analytic import registry
    from kin.ik.analytic.closed_form_structure import ClosedFormStructure, DetailedStructure

    robot = load_robot("planar2")
    shipped_solver, shipped_batch = ClosedFormSolver(robot), ik.BatchSolver(robot)
    monkeypatch.setattr(registry, "CLOSED_FORMS", list(registry.CLOSED_FORMS))
    monkeypatch.setattr(registry, "_entries", list(registry._entries))  # restored after
    registry.register(PlainPlanar, first=True)
    with pytest.raises(TypeError, match="not a closed-form structure"):
        registry.register(type("Half", (), {"name": "half", "dof": 2}))
    solver, batch = ClosedFormSolver(robot), ik.BatchSolver(robot)
    assert isinstance(solver.structure, ClosedFormStructure)
    assert not isinstance(solver.structure, DetailedStructure)
    assert solver.name == "closed_form:plainplanar"
    rng = np.random.default_rng(4)
    q = rng.uniform(robot.lower, robot.upper, size=(40, 2))
    poses = kin.batch_forward_kinematics(robot.table, q)
    for pose, expected in zip(poses, q):
        target = PositionTarget(pose[:3, 3])
        plain, shipped = solver.solve(target), shipped_solver.solve(target)
        assert plain.success and len(plain.solutions) == len(shipped.solutions)
        assert {s.branch for s in plain.solutions} <= {"first", "second"}
        for a, b in zip(plain.solutions, shipped.solutions):
            assert np.abs(a.q - b.q).max() < 1e-12
        assert min(np.abs(s.q - expected).max() for s in plain.solutions) < 1e-9
    plain_batch = batch.solve_positions(poses[:, :3, 3])
    shipped = shipped_batch.solve_positions(poses[:, :3, 3])
    assert plain_batch.branch_names == ("first", "second")
    np.testing.assert_array_equal(plain_batch.q, shipped.q)
    np.testing.assert_array_equal(plain_batch.valid, shipped.valid)
    assert plain_batch.valid.any(1).all()
    out = solver.solve(PositionTarget([5.0, 0.0, 0.0]))
    assert not out.success and out.status == "out_of_reach"


_LAZY_PROBE = """
import sys
import kin.ik
heavy = ("scipy", "mujoco", "mink", "qpsolvers")
print(*[m for m in heavy if m in sys.modules], "|", end=" ")
import numpy as np
from kin import Configuration, load_robot
robot = load_robot("humanoid7")
pose = Configuration(robot).fk(np.array([0.3, 0.4, -0.2, 0.8, 0.1, -0.3, 0.2]))
result = kin.ik.solve_ik(robot, kin.ik.PoseTarget.from_matrix(pose))
print(*[m for m in heavy if m in sys.modules], "|", result.method)
"""


def test_import_and_a_humanoid7_solve_load_no_heavy_module(tmp_path):
    """import kin.ik loads no SciPy, MuJoCo, mink or qpsolvers; nor does a closed-form answer."""
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path))
    out = subprocess.run(
        [sys.executable, "-c", _LAZY_PROBE],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    ).stdout.split()
    assert out == ["|", "|", "closed_form_free_joint"], f"{out=}"


@pytest.mark.parametrize("name", ["puma560", "ur10"])
def test_batch_solver_of_six_r_arms_against_the_reference(name, user_tables):
    """Every branch the batch solver calls valid reaches the target in an independent DH product;
    each of 200 targets from random q inside the limits has one at least."""
    from kin.ik.analytic.batch import BatchSolver

    robot = load_robot(name)
    reference = load_reference(_reference_path(name, user_tables))
    rng = np.random.default_rng(21)
    qs = rng.uniform(reference.lower, reference.upper, size=(200, reference.dof))
    poses = fk_frames(reference, qs)[:, -1]
    result = BatchSolver(robot).solve_poses(poses)
    assert result.valid.any(axis=1).all()
    for i, j in zip(*np.nonzero(result.valid)):
        reached = fk_frames(reference, result.q[i, j])[0, -1]
        assert np.linalg.norm(reached[:3, 3] - poses[i, :3, 3]) < 1e-9, f"{i=} {j=}"
        assert rotation_angle(reached[:3, :3], poses[i, :3, :3]) < 1e-9, f"{i=} {j=}"
