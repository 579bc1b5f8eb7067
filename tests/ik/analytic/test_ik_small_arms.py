"""The small arms in closed form: SCARA positions, yaw_planar 4R arms, Kinova's 4-DOF arms.

Targets are the FK of random joint vectors inside the limits (reachable). Every returned branch
is measured by an independent FK: the plain NumPy DH product of the table file
(:mod:`dh_reference`) or Pinocchio on the maker's URDF (:mod:`urdf_reference`). Branch counts
are compared with a brute-force count: least squares from many random starts.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import least_squares
from support.dh_reference import fk_frames, load_reference, rotation_angle
from support.urdf_reference import UrdfReference

from dh2urdf import load_table
from kin import load_robot
from kin.ik import PoseTarget, PositionTarget, get_solver
from kin.ik.analytic.planar.free_angle import inside_limits, row_inside
from kin.ik.analytic.planar.yaw_planar import YawPlanar

DATA = Path(__file__).parents[2] / "data"
TABLES = {name: DATA / "toolbox" / f"{name}.toml" for name in ("cobra600", "al5d", "orion5")}
KINOVA = {
    "mico4": (DATA / "kinova4" / "m1n4s200_standalone.urdf", "root", "m1n4s200_end_effector"),
    "jaco4": (DATA / "kinova4" / "j2n4s300_standalone.urdf", "root", "j2n4s300_end_effector"),
}
STRUCTURE = {
    "cobra600": "closed_form:parallel_axes",
    "al5d": "closed_form:yaw_planar",
    "orion5": "closed_form:yaw_planar",
    "mico4": "closed_form:yaw_planar_roll",
    "jaco4": "closed_form:yaw_planar_roll",
}
TARGETS = 200


def _arm(name: str):
    """The robot and an independent FK ``q (dof,) -> T_world_tool (4, 4)`` of its source."""
    if name in TABLES:
        reference = load_reference(TABLES[name])
        return load_robot(TABLES[name]), lambda q: fk_frames(reference, q)[0, -1]
    path, base, tip = KINOVA[name]
    robot = load_robot(path, base, tip)
    urdf = UrdfReference(path, base, tip, robot.joint_names)
    return robot, urdf.pose


def _inside(robot, q) -> bool:
    return bool(np.all(q >= robot.lower - 1e-9) and np.all(q <= robot.upper + 1e-9))


@pytest.mark.parametrize("kind", ["position", "pose"])
@pytest.mark.parametrize("arm", list(STRUCTURE))
def test_every_reachable_target_is_solved_in_closed_form(arm, kind):
    """100 % of FK targets solved by the closed form; every branch reaches it (independent FK)."""
    robot, fk = _arm(arm)
    solver = get_solver(robot)
    assert solver.name == STRUCTURE[arm], f"{arm=}"
    rng = np.random.default_rng(3)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    seed = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
    solved = branches = 0
    for q in rng.uniform(lower, upper, size=(TARGETS, robot.nq)):
        T = fk(q)
        target = PositionTarget(T[:3, 3]) if kind == "position" else PoseTarget(T[:3, 3], T[:3, :3])
        result = solver.solve(target, seed)
        solved += result.success
        assert result.method == "closed_form", f"{arm=} {kind=} {result.method=} {result.message}"
        for solution in result.solutions:
            reached = fk(solution.q)
            assert np.linalg.norm(reached[:3, 3] - T[:3, 3]) < 1e-7, f"{arm=} {solution=}"
            if kind == "pose":
                assert rotation_angle(reached[:3, :3], T[:3, :3]) < 1e-7, f"{arm=} {solution=}"
            assert _inside(robot, solution.q), f"{arm=} {solution=}"
            branches += 1
    assert solved == TARGETS, f"{arm=} {kind=} {solved=}"
    assert branches >= TARGETS, f"{arm=} {kind=} {branches=}"


def _brute_force(fk, robot, T, fixed: dict[int, float], rotation: bool, starts: int = 300):
    """Distinct joint vectors inside the limits reaching ``T`` (least squares from random starts).

    ``fixed``: joints held at a value (the free joint a position leaves). Angles compared
    modulo a turn; solutions closer than 1e-4 rad are one.
    """
    rng = np.random.default_rng(5)
    free = [i for i in range(robot.nq) if i not in fixed]
    lower, upper = robot.lower, robot.upper

    def full(x):
        q = np.empty(robot.nq)
        q[free] = x
        for i, value in fixed.items():
            q[i] = value
        return q

    def residual(x):
        reached = fk(full(x))
        r = reached[:3, 3] - T[:3, 3]
        if rotation:
            r = np.concatenate([r, 0.3 * pin.log3(T[:3, :3].T @ reached[:3, :3])])
        return r

    found: list[np.ndarray] = []
    for _ in range(starts):
        x0 = rng.uniform(lower[free], upper[free])
        fit = least_squares(residual, x0, xtol=1e-14, ftol=1e-14, gtol=1e-14)
        if np.linalg.norm(residual(fit.x)) > 1e-9:
            continue
        q = full(fit.x)
        wrapped = robot.lower + np.remainder(q - robot.lower, 2 * np.pi)
        if not _inside(robot, wrapped):
            continue
        if not any(
            np.abs(np.remainder(wrapped - f + np.pi, 2 * np.pi) - np.pi).max() < 1e-4 for f in found
        ):
            found.append(wrapped)
    return found


@pytest.mark.slow
@pytest.mark.parametrize(
    ("arm", "kind"),
    [("mico4", "pose"), ("mico4", "position"), ("cobra600", "position"), ("al5d", "pose")],
)
def test_branch_count_equals_a_brute_force_count(arm, kind):
    """As many branches as least squares from 300 starts finds (the free joint at the seed's)."""
    robot, fk = _arm(arm)
    solver = get_solver(robot)
    rng = np.random.default_rng(8)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    for q in rng.uniform(lower, upper, size=(3, robot.nq)):
        seed = np.clip(rng.uniform(lower, upper), robot.lower, robot.upper)
        T = fk(q)
        if kind == "pose":
            result = solver.solve(PoseTarget(T[:3, 3], T[:3, :3]), seed)
            fixed = {}
        else:
            result = solver.solve(PositionTarget(T[:3, 3]), seed)
            last = robot.nq - 1
            fixed = {last: float(seed[last])}  # the free joint: the seed's value
        expected = _brute_force(fk, robot, T, fixed, kind == "pose")
        assert result.success, f"{arm=} {result.message}"
        assert len(result.solutions) == len(expected), f"{arm=} {kind=} {q=} {result.solutions=}"


def test_free_joint_of_a_scara_position_is_the_seeds():
    """A SCARA position keeps joint 4 at the seed's value, both elbow branches, labels say so."""
    robot, fk = _arm("cobra600")
    q = np.array([0.3, -0.8, 0.1, 0.7])
    seed = np.array([0.0, 0.5, 0.05, -1.2])
    result = get_solver(robot).solve(PositionTarget(fk(q)[:3, 3]), seed)
    assert len(result.solutions) == 2
    assert all(s.q[3] == pytest.approx(-1.2) for s in result.solutions)
    assert all("joint 4 free: the seed's value" in s.branch for s in result.solutions)
    assert any(np.allclose(s.q, [0.3, -0.8, 0.1, -1.2]) for s in result.solutions)


def test_yaw_planar_position_states_the_pitch_it_used():
    """A yaw_planar position at the seed's pitch: seeded with q, q itself is among the branches."""
    robot, fk = _arm("al5d")
    q = np.array([0.4, 0.3, -0.5, 0.6])
    result = get_solver(robot).solve(PositionTarget(fk(q)[:3, 3]), q)
    assert all("pitch free: the seed's" in s.branch for s in result.solutions)
    assert np.allclose(result.solutions[0].q, q, atol=1e-9), result.solutions
    # seeded far (q = 0: pitch 0 leaves every branch outside the limits here), a swept pitch
    far = get_solver(robot).solve(PositionTarget(fk(q)[:3, 3]), np.zeros(4))
    assert far.success and far.method == "closed_form", far.message
    assert all("pitch free" in s.branch for s in far.solutions)


@pytest.mark.parametrize("arm", ["al5d", "orion5"])
def test_single_pitch_path_equals_the_vectorized_one(arm):
    """The plain-float path of one pitch gives the NumPy path's branches and limits verdicts.

    200 targets: half FK points at random pitches, half random points of the arm's reach box
    (some out of reach: the NaN rows must match too).
    """
    robot, fk = _arm(arm)
    structure = YawPlanar(load_table(TABLES[arm]))
    rng = np.random.default_rng(11)
    lower, upper = np.maximum(robot.lower, -np.pi), np.minimum(robot.upper, np.pi)
    reach = np.array([fk(q)[:3, 3] for q in rng.uniform(lower, upper, size=(100, 4))])
    box = rng.uniform(reach.min(axis=0) * 1.3, reach.max(axis=0) * 1.3, size=(100, 3))
    limits = (structure.lower, structure.upper, np.ones(4, dtype=bool))
    bounds = tuple(tuple(v.tolist()) for v in limits)
    found = inside_count = 0
    for position in np.concatenate([reach, box]):
        pitch = float(rng.uniform(-np.pi, np.pi))
        vectorized = structure.candidates(position, None, np.array([pitch]))[0]
        scalar = np.array(structure.candidates_at(tuple(position), pitch))
        assert np.array_equal(np.isnan(scalar), np.isnan(vectorized)), f"{position=} {pitch=}"
        assert np.allclose(scalar, vectorized, atol=1e-12, equal_nan=True), f"{position=}"
        inside = inside_limits(vectorized, *limits)
        assert [row_inside(tuple(row), bounds) for row in scalar] == inside.tolist()
        inside_count += int(inside.sum())
        found += int((~np.isnan(scalar).any(axis=1)).sum())
    assert found > 100 and inside_count > 10, f"{found=} {inside_count=}"  # not NaN rows only
