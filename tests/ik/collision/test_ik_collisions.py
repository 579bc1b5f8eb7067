"""Collision-aware IK (kin/ik/collision/collision_aware.py) judged by a direct coal check built apart.

Every verdict below is the reference's (tests/support/collision_reference.py: the original URDF's
shapes placed by Pinocchio and asked of coal pair by pair), not the checker's under test: a
joint vector collides when a checked pair's signed distance is below ``-CONTACT_TOL``.
Obstacles are placed from the reference's own placement of a link's shape at the plain
solver's answer, so the answer the plain solver prefers surely collides.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.collision_reference import CollisionReference
from support.collision_setup import setup

import kin
from kin.collision import CollisionChecker, load_collision_model
from kin.ik import AxisTarget, PoseTarget, get_solver
from kin.ik.collision.collision_aware import CollisionAwareSolver

CONTACT_TOL = 1e-6
#: Random targets per robot in the property test.
PROPERTY_TARGETS = 200


def _reference(robot: kin.RobotModel, scene: Path) -> CollisionReference:
    return CollisionReference(robot.urdf, None, robot.joint_names, None, scene)


def _collides(reference: CollisionReference, pairs, q) -> list[tuple[str, str]]:
    """The checked pairs the reference finds overlapping at ``q`` by more than CONTACT_TOL."""
    distances = reference.signed_distances(np.asarray(q, dtype=float), pairs)
    return [pair for pair, (d, _) in distances.items() if d < -CONTACT_TOL]


def _collides_as_named(reference: CollisionReference, pairs, q, reason: str) -> bool:
    """Whether the reference finds ``q`` colliding, asking first the pairs ``reason`` names.

    ``reason`` is the checker's (``"scene: table; self: a/b"``, deepest first): the pairs of its
    first part are measured first, the rest only when none of them overlaps.
    """
    first = reason.split("; ")[0]
    kind, _, names = first.partition(": ")
    named = set(names.split("/"))
    if kind == "scene":
        chosen = [p for p in pairs if named & set(p)]
    else:
        chosen = [p for p in pairs if set(p) == named]
    if chosen and _collides(reference, chosen, q):
        return True
    return bool(_collides(reference, pairs, q))


def _ball_scene(tmp_path: Path, center, radius: float, name: str = "post") -> Path:
    path = tmp_path / f"{name}.toml"
    xyz = ", ".join(f"{v:.17g}" for v in center)
    path.write_text(f'[[sphere]]\nname = "{name}"\nradius = {radius}\nxyz = [{xyz}]\n')
    return path


def _shape_center(reference: CollisionReference, q, link: str) -> np.ndarray:
    return np.array(reference.placements(np.asarray(q, dtype=float))[link][0][1].translation)


def _pose(robot: kin.RobotModel, q) -> PoseTarget:
    T = kin.Configuration(robot).fk(np.asarray(q, dtype=float))
    return PoseTarget(T.translation, T.rotation)


def _aware(robot, scene):
    model = load_collision_model(robot, scene=scene)
    checker = CollisionChecker(model)
    return get_solver(robot, collisions=checker), checker, model


def _blocked_nearest(
    tmp_path, robot, plain, link, targets, radius=0.04, others=None, all_blocked=False
):
    """(target, seed, plain result, scene, reference): the plain answer's ``link`` in a ball.

    Another answer (of the plain result, or of ``others(target, seed)``) is free by the
    reference, over every checked pair (the arm's volumes are fat enough to meet the ball, or
    each other, elsewhere than at ``link``). ``all_blocked``: every answer of the plain result
    collides, so only ``others`` hold a free one.
    """
    rng = np.random.default_rng(3)
    probe = _reference(robot, _ball_scene(tmp_path, (9.0, 9.0, 9.0), 0.01))
    for _ in range(200):
        q = rng.uniform(robot.lower, robot.upper)
        target = targets(q)
        seed = q + rng.normal(0.0, 0.05, robot.nq)
        result = plain.solve(target, seed)
        if not result.solutions:
            continue
        scene = _ball_scene(tmp_path, _shape_center(probe, result.solutions[0].q, link), radius)
        reference = _reference(robot, scene)
        pairs = [tuple(p) for p in load_collision_model(robot, scene=scene).pairs]
        if all_blocked and not all(_collides(reference, pairs, s.q) for s in result.solutions):
            continue
        more = result.solutions[1:] if others is None else others(target, seed)
        if any(not _collides(reference, pairs, s.q) for s in more):
            return target, seed, result, scene, reference
    pytest.fail("no target whose nearest answer could be blocked alone")


def _assert_free(reference, model, solutions):
    pairs = [tuple(p) for p in model.pairs]
    for s in solutions:
        assert not _collides(reference, pairs, s.q), f"q={s.q.tolist()} collides"


def test_ur5_nearest_branch_blocked_gets_the_other_branch(tmp_path):
    """UR5: a ball through the nearest branch's forearm; the answer is the nearest free branch."""
    robot = kin.load_robot("ur5")
    plain = get_solver(robot)
    target, seed, result, scene, reference = _blocked_nearest(
        tmp_path, robot, plain, "link3", lambda q: _pose(robot, q)
    )
    aware, checker, model = _aware(robot, scene)
    answer = aware.solve(target, seed)
    pairs = [tuple(p) for p in model.pairs]
    expected = [s for s in result.solutions if not _collides(reference, pairs, s.q)]
    assert answer.status == "ok" and answer.success
    assert answer.solutions[0].branch == expected[0].branch
    np.testing.assert_allclose(answer.solutions[0].q, expected[0].q, atol=1e-12)
    assert len(answer.solutions) == 1  # the judging stops at the first free answer
    every = CollisionAwareSolver(plain, checker, every=True).solve(target, seed)
    assert [s.branch for s in every.solutions] == [s.branch for s in expected]
    _assert_free(reference, model, every.solutions)
    _assert_free(reference, model, answer.solutions)
    assert not any(checker.in_collision(s.q) for s in answer.solutions)
    nearest = result.solutions[0]
    blocked = [s for s in answer.rejected if s.branch == nearest.branch and s.reason]
    assert blocked and "scene: post" in blocked[0].reason
    assert _collides(reference, pairs, blocked[0].q)


def test_ur5_every_branch_colliding_says_in_collision(tmp_path):
    """A ball around the tool point: reachable, every branch collides -> in_collision."""
    robot = kin.load_robot("ur5")
    q = np.array([0.3, -1.2, 1.4, -0.5, 1.2, 0.2])
    target = _pose(robot, q)
    scene = _ball_scene(tmp_path, target.position, 0.12)
    aware, checker, model = _aware(robot, scene)
    answer = aware.solve(target, q)
    assert get_solver(robot).solve(target, q).status == "ok"
    assert answer.status == "in_collision" and not answer.success
    assert not answer.solutions
    assert "reachable" in answer.message and "collide" in answer.message
    reference = _reference(robot, scene)
    pairs = [tuple(p) for p in model.pairs]
    colliding = [s for s in answer.rejected if s.reason]
    assert colliding
    for s in colliding:
        assert _collides(reference, pairs, s.q)
        assert "scene: post" in s.reason


def test_ur5_out_of_reach_stays_out_of_reach(tmp_path):
    """A target beyond reach says out_of_reach, not in_collision."""
    robot = kin.load_robot("ur5")
    aware, _, _ = _aware(robot, _ball_scene(tmp_path, (0.0, 0.0, 3.0), 0.1))
    answer = aware.solve(PoseTarget([3.0, 0.0, 0.3], np.eye(3)))
    assert answer.status == "out_of_reach"


def test_7r_free_joint_gives_a_free_answer(tmp_path):
    """humanoid7: the usual answer's forearm blocked; the free joint gives a free answer."""
    robot = kin.load_robot("humanoid7")
    plain = get_solver(robot)
    target, seed, result, scene, reference = _blocked_nearest(
        tmp_path,
        robot,
        plain,
        "frame4",
        lambda q: _pose(robot, q),
        radius=0.03,
        others=lambda t, s: plain.solve(t, s, all_branches=True).solutions,
    )
    aware, checker, model = _aware(robot, scene)
    answer = aware.solve(target, seed)
    assert answer.status == "ok", answer.message
    pairs = [tuple(p) for p in model.pairs]
    assert _collides(reference, pairs, result.solutions[0].q)
    _assert_free(reference, model, answer.solutions)
    assert not any(checker.in_collision(s.q) for s in answer.solutions)
    config = kin.Configuration(robot)
    for s in answer.solutions:
        T = config.fk(s.q)
        assert np.linalg.norm(T.translation - target.position) < 1e-6
        assert np.abs(T.rotation - target.rotation).max() < 1e-6


def test_ur5_axis_target_gets_another_roll(tmp_path):
    """UR5 AxisTarget: the seed roll's answers blocked at the wrist; another roll is free.

    The target fixes the flange's x axis (a tool pointing sideways), so a roll about it swings
    the whole wrist. About the flange's z axis a roll is joint 6 alone: it turns only wrist_3's
    housing, round about that axis to 3 mm, so no roll could dodge a ball (the scenario once
    passed only on a forearm / wrist_3 self-contact within those 3 mm, a pair the maker's SRDF
    no longer checks). The ball sits on wrist_1 (link4) of the nearest answer; every branch at
    the seed's roll collides (the ball or the arm's own volumes), so the free answer is another
    roll's.
    """
    robot = kin.load_robot("ur5")
    plain = get_solver(robot)

    def axis(q):
        T = kin.Configuration(robot).fk(q)
        return AxisTarget(T.translation, T.rotation[:, 0], tool_axis="x")

    target, seed, result, scene, reference = _blocked_nearest(
        tmp_path,
        robot,
        plain,
        "link4",
        axis,
        radius=0.03,
        others=lambda t, s: plain.partial.solve(t, s, every_roll=True).solutions,
        all_blocked=True,
    )
    aware, checker, model = _aware(robot, scene)
    answer = aware.solve(target, seed)
    assert answer.status == "ok", answer.message
    pairs = [tuple(p) for p in model.pairs]
    assert all(_collides(reference, pairs, s.q) for s in result.solutions)
    assert ("link4", "post") in _collides(reference, pairs, result.solutions[0].q)
    _assert_free(reference, model, answer.solutions)
    config = kin.Configuration(robot)
    seed_z = config.fk(result.solutions[0].q).rotation[:, 2]
    for s in answer.solutions:
        T = config.fk(s.q)
        assert np.linalg.norm(T.translation - target.position) < 1e-6
        assert np.dot(T.rotation[:, 0], target.axis) > 1 - 1e-8
        assert np.dot(T.rotation[:, 2], seed_z) < np.cos(np.radians(1.0))  # another roll


@pytest.mark.parametrize("name", ["ur5", "humanoid7", "panda"])
def test_no_solution_collides(name):
    """200 random targets in the cell: no answer in ``solutions`` collides (by the reference)."""
    robot, model, checker, reference, _ = setup(name)
    aware = get_solver(robot, collisions=checker)
    pairs = [tuple(p) for p in model.pairs]
    config = kin.Configuration(robot)
    rng = np.random.default_rng(11)
    statuses: dict[str, int] = {}
    for _ in range(PROPERTY_TARGETS):
        q = rng.uniform(robot.lower, robot.upper)
        T = config.fk(q)
        seed = rng.uniform(robot.lower, robot.upper)
        answer = aware.solve(PoseTarget(T.translation, T.rotation), seed, timeout=5.0)
        statuses[answer.status] = statuses.get(answer.status, 0) + 1
        for s in answer.solutions:
            assert not _collides(reference, pairs, s.q), f"{name}: q={s.q.tolist()} collides"
        if answer.status == "in_collision":
            assert all(
                _collides_as_named(reference, pairs, s.q, s.reason)
                for s in answer.rejected
                if s.reason
            )
    assert statuses.get("ok", 0) > 0 and statuses.get("in_collision", 0) > 0, statuses


# -- every route gives the library's answer ------------------------------------------------------

CELL = Path(__file__).parents[2] / "data" / "collision" / "cell.toml"


def _cell_targets(robot: kin.RobotModel, count: int, seed: int = 5):
    config = kin.Configuration(robot)
    rng = np.random.default_rng(seed)
    qs = rng.uniform(robot.lower, robot.upper, (count, robot.nq))
    return [config.fk(q) for q in qs], rng.uniform(robot.lower, robot.upper, (count, robot.nq))


@pytest.mark.parametrize("name", ["ur5", "humanoid7"])
def test_kin_ik_stdin_and_solve_batch_give_the_library_answer(name, monkeypatch, capsys):
    """kin ik --json, kin ik --stdin and solve_batch(collisions=) answer as get_solver does."""
    import io
    import json

    from kin.commands import ik
    from kin.ik import solve_batch

    robot = kin.load_robot(name)
    checker = CollisionChecker(load_collision_model(robot, scene=CELL))
    poses, seeds = _cell_targets(robot, 12)
    rpys = [pin.rpy.matrixToRpy(T.rotation).tolist() for T in poses]
    command = get_solver(robot, near_seed=True, collisions=checker)
    library = get_solver(robot, collisions=checker)
    targets = [PoseTarget(T.translation, pin.rpy.rpyToMatrix(*rpy)) for T, rpy in zip(poses, rpys)]
    expected = [command.solve(t, s) for t, s in zip(targets, seeds)]
    assert {r.status for r in expected} >= {"ok", "in_collision"}, [r.status for r in expected]
    argv = ["--robot", name, "--scene", str(CELL)]
    lines = [
        json.dumps({"target": T.translation.tolist(), "rpy": rpy, "seed_q": s.tolist()})
        for T, rpy, s in zip(poses, rpys, seeds)
    ]
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(line + "\n" for line in lines)))
    ik.main([*argv, "--stdin"])
    records = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert len(records) == len(expected)
    for record, result in zip(records, expected):
        assert record["status"] == result.status
        if result.solutions:
            np.testing.assert_allclose(
                record["solutions"][0]["q"], result.solutions[0].q, atol=1e-12
            )
    for k in (0, 1, 2, 3):
        T, rpy, s = poses[k], rpys[k], seeds[k]
        code = ik.main(
            [
                *argv,
                "--json",
                "--target",
                *map(str, T.translation),
                "--rpy",
                *map(repr, rpy),
                "--seed-q",
                *map(repr, s.tolist()),
            ]
        )
        record = json.loads(capsys.readouterr().out)
        assert record["status"] == expected[k].status
        assert code == (0 if expected[k].success else 1)
        if expected[k].solutions:
            np.testing.assert_allclose(
                record["solutions"][0]["q"], expected[k].solutions[0].q, atol=1e-9
            )
    batch = solve_batch(
        robot,
        [t.position for t in targets],
        [t.rotation for t in targets],
        seeds,
        collisions=checker,
    )
    for i, t in enumerate(targets):
        result = library.solve(t, seeds[i])
        assert bool(batch.success[i]) == result.success
        if result.success:
            np.testing.assert_allclose(batch.q[i], result.solutions[0].q, atol=1e-12)
            assert not checker.in_collision(batch.q[i])


def test_kin_ik_text_names_the_colliding_branches(capsys):
    """kin ik --scene --all marks each colliding branch with its reason; --padding needs a scene."""
    from kin.commands import ik

    code = ik.main(
        [
            "--robot",
            "ur5",
            "--target",
            "0.4",
            "0.1",
            "0.3",
            "--rpy",
            "3.14",
            "0",
            "0",
            "--scene",
            str(CELL),
            "--all",
        ]
    )
    out = capsys.readouterr().out
    assert code == 0
    assert "collides: scene: wall" in out
    with pytest.raises(SystemExit) as exit_:
        ik.main(["--robot", "ur5", "--target", "0.4", "0.1", "0.3", "--padding", "0.01"])
    assert exit_.value.code == 2
    assert "--padding needs --scene or --srdf" in capsys.readouterr().err
