"""Redundancy exposed: every branch of a 7R arm over a stated grid of its free joint (issue 32.6).

Checked against code that is not the solver's: a plain NumPy DH product of the table file
(``dh_reference``), ssik's own forward kinematics for the arms it ships (their chains read back
as URDFs), and ssik's answers counted at the same free-joint values.
"""

from __future__ import annotations

import importlib
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference, rotation_angle
from support.scripts_helper import load_script

import dh2urdf
from kin import load_robot
from kin.commands import ik
from kin.ik import PoseTarget, PositionTarget, get_solver
from kin.ik.analytic.seven_r.branches7 import distinct, free_grid, windings
from kin.ik.numeric.all_branches import solve_all_branches

TABLES = Path(dh2urdf.__file__).resolve().parent / "tables"  # the installed package's
#: Pose agreement of every branch with the target [m] / [rad].
TOL = 1e-9
#: Random targets per arm.
TARGETS = 6
SHIPPED_7R = ("panda", "xarm7", "humanoid7")


def _targets(robot, count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Joint vectors inside the limits (count, 7) and their tool poses by the NumPy DH product."""
    reference = load_reference(TABLES / f"{robot.name}.toml")
    q = np.random.default_rng(seed).uniform(robot.lower, robot.upper, (count, robot.nq))
    return q, fk_frames(reference, q)[:, -1]


def _assert_branches(name: str, result, pose: np.ndarray, fk, lower, upper) -> np.ndarray:
    """Every solution on ``pose`` by ``fk`` (independent), inside the limits, no two equal."""
    assert result.success, f"{name=} {result.message}"
    rows = np.array([s.q for s in result.solutions])
    reached = fk(rows)
    position = np.linalg.norm(reached[:, :3, 3] - pose[:3, 3], axis=1)
    rotation = rotation_angle(
        reached[:, :3, :3], np.broadcast_to(pose[:3, :3], reached[:, :3, :3].shape)
    )
    assert position.max() < TOL and rotation.max() < TOL, (
        f"{name=} {position.max()=} {rotation.max()=}"
    )
    assert (rows >= lower).all() and (rows <= upper).all(), f"{name=}"
    # Two rows more than 1e-6 rad apart in a joint differ there once rounded to 1e-6 rad.
    assert np.unique(np.round(rows / 1e-6), axis=0).shape[0] == len(rows), f"{name=} equal branches"
    return rows


@pytest.mark.parametrize("name", SHIPPED_7R)
def test_every_branch_reaches_the_pose_and_the_seed_is_among_them(name):
    """FK(seed) as target: each branch on it (NumPy DH), inside, distinct, the seed among them."""
    robot = load_robot(name)
    solver = get_solver(robot)
    reference = load_reference(TABLES / f"{name}.toml")
    q_all, poses = _targets(robot, TARGETS, seed=32)
    for q, pose in zip(q_all, poses):
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        result = solver.solve(target, q, all_branches=True)
        rows = _assert_branches(
            name, result, pose, lambda r: fk_frames(reference, r)[:, -1], robot.lower, robot.upper
        )
        gap = np.abs(rows - q).max(axis=1)
        assert gap.min() < 1e-8, f"{name=} the seed is not among the {len(rows)} branches"
        assert gap.argmin() == 0, f"{name=} the seed's own branch is not first"
        distance = ((rows - q) ** 2).sum(axis=1)
        assert (np.diff(distance) >= 0).all(), f"{name=} not nearest the seed first"


@pytest.mark.parametrize("name", SHIPPED_7R)
def test_without_all_branches_the_answer_is_unchanged_and_among_its_value_s_branches(name):
    """The default call gives one answer, the same as all_branches=False; at its free value, a branch.

    The branches at the seed's free value are all there (every one the form gives at that value,
    judged by the NumPy DH product), nearest the seed first.
    """
    robot = load_robot(name)
    solver = get_solver(robot)
    free = solver.closed_form.free
    reference = load_reference(TABLES / f"{robot.name}.toml")
    q_all, poses = _targets(robot, 3, seed=7)
    seed = np.clip(np.zeros(7), robot.lower, robot.upper)
    for pose in poses:
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        usual = solver.solve(target, seed)
        assert len(usual.solutions) == 1
        again = solver.solve(target, seed, all_branches=False)
        np.testing.assert_array_equal(usual.solutions[0].q, again.solutions[0].q)
        at_its_value = solve_all_branches(
            solver, target, seed, free_values=[usual.solutions[0].q[free]]
        )
        rows = np.array([s.q for s in at_its_value.solutions])
        assert np.abs(rows - usual.solutions[0].q).max(axis=1).min() < 1e-5, f"{name=}"
        every = solver.solve(target, seed, all_branches=True)
        rows = np.array([s.q for s in every.solutions])
        distance = np.linalg.norm(rows - seed, axis=1)
        assert (np.diff(distance) >= 0).all(), f"{name=}: not nearest the seed first"
        at_seed = solve_all_branches(solver, target, seed, free_values=[seed[free]])
        for branch in at_seed.solutions:
            if branch.q[free] != seed[free]:
                continue  # none at the seed's value: the usual answer instead
            assert np.abs(rows - branch.q).max(axis=1).min() < 1e-12, f"{name=}: lost at the seed"
            reached = fk_frames(reference, branch.q[None])[0, -1]
            assert np.abs(reached - pose).max() < 1e-9


def test_a_position_target_gets_the_usual_answer():
    """A position leaves four joints free: no grid of one joint, the usual single answer."""
    solver = get_solver(load_robot("panda"))
    target = PositionTarget([0.4, 0.1, 0.5])
    every = solver.solve(target, None, all_branches=True)
    usual = solver.solve(target, None)
    assert len(every.solutions) == 1
    np.testing.assert_array_equal(every.solutions[0].q, usual.solutions[0].q)


def test_free_grid_is_the_midpoints_over_one_turn_at_most():
    """Panda's joint 7 (about 5.8 rad): midpoints of 4 cells; xArm7's 4 pi range: one turn."""
    np.testing.assert_allclose(free_grid(-2.0, 2.0, 4), [-1.5, -0.5, 0.5, 1.5])
    grid = free_grid(-2 * math.pi, 2 * math.pi, 8)
    np.testing.assert_allclose(grid, -2 * math.pi + (np.arange(8) + 0.5) * math.pi / 4)


def test_windings_give_every_copy_inside_the_limits():
    """Limits +-2 pi and +-1: 1.0 has two copies, 3.0 none (its row goes), 7.0 two."""
    lower, upper = np.array([-2 * math.pi, -1.0]), np.array([2 * math.pi, 1.0])
    rows = np.array([[1.0, 0.5], [0.5, 3.0], [7.0, -0.5]])
    copies, source = windings(rows, lower, upper)
    expected = [
        [1.0 - 2 * math.pi, 0.5],
        [1.0, 0.5],
        [7.0 - 4 * math.pi, -0.5],
        [7.0 - 2 * math.pi, -0.5],
    ]
    np.testing.assert_allclose(copies, expected, atol=1e-15)
    assert source.tolist() == [0, 0, 2, 2]


def test_distinct_drops_rows_equal_modulo_a_turn_and_keeps_the_first():
    """Equal within 1e-6 rad joint by joint, modulo 2 pi (across the +-pi seam too)."""
    rows = np.array(
        [
            [math.pi - 1e-9, 0.0],
            [0.3, 0.2],
            [-math.pi + 1e-9, 2 * math.pi],
            [0.3 + 1e-7, 0.2],
            [0.3, 0.3],
        ]
    )
    np.testing.assert_array_equal(distinct(rows), rows[[0, 1, 4]])


def _stdin(monkeypatch, capsys, argv: list[str], lines: list[str], code: int = 0) -> list[dict]:
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(line + "\n" for line in lines)))
    assert ik.main([*argv, "--stdin"]) == code
    captured = capsys.readouterr()
    assert captured.err == ""
    return [json.loads(line) for line in captured.out.splitlines()]


def test_the_same_branches_by_every_route(monkeypatch, capsys):
    """Library, `kin ik --all --json`, a stdin line's "all": true and `--stdin --all` agree."""
    robot = load_robot("panda")
    q_all, poses = _targets(robot, 1, seed=3)
    pose = poses[0]
    rpy = _rpy(pose[:3, :3])
    seed = [float(v) for v in q_all[0]]
    library = get_solver(robot, near_seed=True).solve(
        PoseTarget(pose[:3, 3], pose[:3, :3]), np.array(seed), all_branches=True
    )
    expected = np.array([s.q for s in library.solutions])
    assert len(expected) > 1
    argv = ["--robot", "panda", "--seed-q", *map(repr, seed)]
    target = ["--target", *map(repr, pose[:3, 3].tolist()), "--rpy", *map(repr, rpy)]
    assert ik.main([*argv, *target, "--all", "--json"]) == 0
    single = json.loads(capsys.readouterr().out)
    line = {"target": pose[:3, 3].tolist(), "rpy": rpy}
    routes = {
        "--all --json": single,
        '"all": true': _stdin(monkeypatch, capsys, argv, [json.dumps({**line, "all": True})])[0],
        "--stdin --all": _stdin(monkeypatch, capsys, [*argv, "--all"], [json.dumps(line)])[0],
    }
    for route, answer in routes.items():
        got = np.array([s["q"] for s in answer["solutions"]])
        assert got.shape == expected.shape, f"{route=}"
        np.testing.assert_allclose(got, expected, atol=1e-12, err_msg=route)
    plain = _stdin(monkeypatch, capsys, argv, [json.dumps(line)])[0]
    assert len(plain["solutions"]) == 1  # without "all": the usual answer


def test_a_non_boolean_all_is_an_error_line(monkeypatch, capsys):
    """A line with "all": 1 is refused on its line, naming the field."""
    line = json.dumps({"target": [0.4, 0, 0.5], "all": 1})
    answers = _stdin(monkeypatch, capsys, ["--robot", "panda"], [line], code=1)
    assert '"all" must be true or false' in answers[0]["error"]


def _rpy(rotation: np.ndarray) -> list[float]:
    """URDF roll-pitch-yaw [rad] of a rotation (Pinocchio's)."""
    import pinocchio as pin

    return pin.rpy.matrixToRpy(rotation).tolist()


# --- ssik's arms: counts at ssik's free-joint values -------------------------------------------

#: Our arm (a shipped name, or None: ssik's chain written as a URDF) -> ssik's prebuilt module.
PEERS = {
    **load_script("bench_ik_7r_branches").ARMS,
    "xarm7-chain": (None, "ufactory.xarm7_ik"),  # rounded: an idealised closed form, polished
}


@pytest.mark.peer
@pytest.mark.parametrize("arm", sorted(PEERS))
def test_at_least_ssik_branches_at_its_free_joint_values(arm, tmp_path):
    """At the free-joint values of ssik's answers we verify at least as many branches as it returns."""
    pytest.importorskip("ssik")
    shipped, module_name = PEERS[arm]
    module = importlib.import_module(f"ssik.prebuilt.{module_name}")
    if shipped is None:  # its chain as ssik has it: ssik's FK is the model's
        path = tmp_path / f"{arm}.urdf"
        path.write_text(
            load_script("bench_ik_7r_branches").ssik_urdf(module, arm), encoding="utf-8"
        )
        robot = load_robot(path)
        fk = lambda rows: np.array([module.fk(r) for r in rows])  # noqa: E731
    else:  # ours (within 1e-5 of ssik's chain): the NumPy DH product of its table
        robot = load_robot(shipped)
        reference = load_reference(TABLES / f"{shipped}.toml")
        fk = lambda rows: fk_frames(reference, rows)[:, -1]  # noqa: E731
    solver = get_solver(robot)
    free = solver.closed_form.free
    rng = np.random.default_rng(62)
    counted = 0
    for q in rng.uniform(robot.lower, robot.upper, (TARGETS, 7)):
        pose = fk(q[None])[0]  # ssik's base and tool frames are ours
        theirs = module.solve(pose)
        values = [s.q[free] for s in theirs]
        if not values:
            continue
        target = PoseTarget(pose[:3, 3], pose[:3, :3])
        ours = solve_all_branches(solver, target, q, free_values=values)
        _assert_branches(arm, ours, pose, fk, robot.lower, robot.upper)
        assert len(ours.solutions) >= len(theirs), f"{arm=} {len(ours.solutions)=} {len(theirs)=}"
        counted += 1
    assert counted >= TARGETS // 2, f"{arm=}: ssik answered {counted} of {TARGETS}"


def test_bench_refuses_bad_arguments_with_one_line(capsys):
    """--targets 0 and an arm it does not know: exit 2, one line naming the option."""
    from support.scripts_helper import exit_code

    bench = load_script("bench_ik_7r_branches")
    for argv, needle in ((["--targets", "0"], "--targets"), (["--arms", "ur5"], "--arms")):
        assert exit_code(bench.main, argv) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and needle in err, err


@pytest.mark.peer
def test_bench_prints_one_row_per_arm(capsys):
    """Two Panda targets: the header and one row whose counts and ratio are numbers."""
    pytest.importorskip("ssik")
    assert load_script("bench_ik_7r_branches").main(["--arms", "panda", "--targets", "2"]) == 0
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| panda")]
    assert len(rows) == 1
    cells = [cell.strip() for cell in rows[0].strip("|").split("|")]
    assert cells[1] == "2" and float(cells[4]) > 0 and cells[7] == "2/2", rows[0]
