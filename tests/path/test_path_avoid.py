"""Collision-free paths (kin.path.follow_path_avoiding, ``kin path --avoid``) judged apart.

Every verdict is the direct coal check built apart (tests/support/collision_reference.py: the URDF's
shapes placed by Pinocchio and asked of coal pair by pair): the scene pairs are every link with
shapes against every scene object, the self pairs those the model checks. The samples' poses are
measured by Pinocchio's forward kinematics of the same URDF (not the DH product of the code under
test). The cells put a box where the arm goes on the plain path's branch, so the plain path
surely collides (asserted by the reference too).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import assert_one_line_error, call
from support.collision_reference import CollisionReference
from support.urdf_reference import erd

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.commands import path as path_command
from kin.ik import AxisTarget, PoseTarget, PositionTarget, get_solver
from kin.path import follow_path, follow_path_avoiding, polyline

CONTACT_TOL = 1e-6
#: Reference points per segment when the motion between samples is checked densely.
DENSE = 12
#: The UR5 cells are in the maker's base frame (the tool at x < 0 is in front of the base). The
#: shelf's face is placed so that the shoulder-left, wrist-up, elbow-down branch (the plain path's)
#: is free at sample 0 and meets it from sample 1 on (link3 / shelf, about 3 mm either way with the
#: refitted forearm); test_a_branch_that_runs_into_the_shelf_fails_where_it_would_jump places its
#: own shelf from the reference's distances, so that a refit of the housings does not move it.
SHELF_TEXT = "[[box]]\nname = 'shelf'\nsize = [0.1, 1.0, 0.4]\nxyz = [{x!r}, 0.0, 0.55]\n"
SHELF = SHELF_TEXT.format(x=0.183)
ROOF = "[[box]]\nname = 'roof'\nsize = [0.3, 1.0, 0.1]\nxyz = [0.1, 0.0, 0.79]\n"
#: The cells: name -> (box TOML, start point, end point [m], tool rpy [rad] or None: the tool
#: pointing down (z axis to -z, roll free) on "-axis" cells, a position path on "-position").
CELLS = {
    # a shelf behind the base, where the UR5's upper arm goes on the shoulder-left branch
    "ur5": (
        SHELF,
        (-0.4, -0.1, 0.3),
        (-0.4, 0.3, 0.3),
        (3.14159, 0.0, 3.14159),
    ),
    # a roof over the Panda's elbow: the elbow must swing aside (the free joint); checked with the
    # maker's self pairs (_panda_srdf)
    "panda": (
        ROOF,
        (0.5, 0.2, 0.3),
        (0.5, -0.2, 0.3),
        (3.14159, 0.0, 0.0),
    ),
    # a partial pose: the closed form's roll sweep (kin.ik.partial_pose)
    "ur5-axis": (SHELF, (-0.4, -0.1, 0.3), (-0.4, 0.3, 0.3), None),
    # positions on a 7R arm: the numeric solver (its other starts, the distance bound)
    "panda-position": (ROOF, (0.5, 0.2, 0.3), (0.5, -0.2, 0.3), None),
}
STEPS = 20


def _panda_srdf(folder: Path) -> Path:
    """The maker's Panda SRDF (example-robot-data) on the DH table's links, written in ``folder``.

    Each ``panda_link{k}`` is carried by DH frame ``frame{k}`` (``panda_link0``'s housing by
    ``frame1``, about joint 1's axis). Without it the DH Panda's housings overlap in nearly every
    configuration (frame3 / frame5, frame5 / frame7: docs/tables.md, coarse self-collisions) and
    no answer of the cells is free.
    """
    text = erd("panda_description/srdf/panda.srdf").read_text(encoding="utf-8")
    carrier = {f"panda_link{k}": f"frame{max(k, 1)}" for k in range(8)}
    pairs = {
        tuple(sorted((carrier[a], carrier[b])))
        for a, b in re.findall(r'<disable_collisions link1="(\w+)" link2="(\w+)"', text)
        if a in carrier and b in carrier and carrier[a] != carrier[b]
    }
    assert ("frame3", "frame5") in pairs and ("frame5", "frame7") in pairs
    rows = "".join(f'  <disable_collisions link1="{a}" link2="{b}"/>\n' for a, b in sorted(pairs))
    file = folder / "panda_dh.srdf"
    file.write_text(f"<robot name='panda'>\n{rows}</robot>\n", encoding="utf-8")
    return file


def _cell(tmp_path: Path, name: str, scene: str | None = None):
    """(robot, path, checker, reference, pairs, scene file) of a cell."""
    text, start, end, rpy = CELLS[name]
    file = tmp_path / f"{name}.toml"
    file.write_text(text if scene is None else scene, encoding="utf-8")
    robot = load_robot(name.split("-")[0])
    if name.endswith("-axis"):
        ends = [AxisTarget(np.array(p), np.array([0.0, 0.0, -1.0])) for p in (start, end)]
    elif name.endswith("-position"):
        ends = [PositionTarget(np.array(p)) for p in (start, end)]
    else:
        ends = [PoseTarget(np.array(p), pin.rpy.rpyToMatrix(*rpy)) for p in (start, end)]
    path = polyline(ends, STEPS)
    srdf = _panda_srdf(tmp_path) if robot.name == "panda" else None
    model = load_collision_model(robot, scene=file, srdf=srdf)
    reference = CollisionReference(robot.urdf, None, robot.joint_names, None, file)
    pairs = [(link, obj) for link in reference.links for obj in reference.scene_names]
    pairs += [p for p in model.pairs if p[1] not in reference.scene_names]
    return robot, path, CollisionChecker(model), reference, pairs, file


def _deepest(reference: CollisionReference, pairs, q) -> float:
    """The reference's smallest signed distance over ``pairs`` at ``q`` [m]."""
    return min(d for d, _ in reference.signed_distances(np.asarray(q, float), pairs).values())


def _tool_poses(robot, q: np.ndarray) -> list[pin.SE3]:
    """Pinocchio FK of the robot's URDF: the tool frame at each joint vector."""
    model = pin.buildModelFromXML(robot.urdf)
    data = model.createData()
    frame = model.getFrameId(robot.tool_frame)
    poses = []
    for row in q:
        pin.framesForwardKinematics(model, data, row)
        poses.append(data.oMf[frame].copy())
    return poses


@pytest.mark.parametrize("name", sorted(CELLS))
def test_avoid_gives_a_free_path_on_target_where_the_plain_one_collides(tmp_path, name):
    """Plain path collides (reference); --avoid's samples and motions are free, poses on target."""
    robot, path, checker, reference, pairs, _ = _cell(tmp_path, name)
    plain = follow_path(robot, path)
    assert min(_deepest(reference, pairs, q) for q in plain.q) < -CONTACT_TOL, f"{name=}"
    avoided = follow_path_avoiding(robot, path, checker)
    assert avoided.success and avoided.searched and avoided.plain is not None, f"{name=}"
    q = avoided.result.q
    assert q.shape == (STEPS + 1, robot.nq)
    # every sample free, and the motion between samples (densely) free
    fractions = np.linspace(0.0, 1.0, DENSE + 1)[:-1]
    for i in range(len(q) - 1):
        for t in fractions:
            distance = _deepest(reference, pairs, q[i] + t * (q[i + 1] - q[i]))
            assert distance > -CONTACT_TOL, f"{name=} segment {i} t={t}: {distance}"
    assert _deepest(reference, pairs, q[-1]) > -CONTACT_TOL
    # on target, by Pinocchio's FK of the URDF
    for i, pose in enumerate(_tool_poses(robot, q)):
        assert np.linalg.norm(pose.translation - path.positions[i]) < 1e-6, f"{name=} {i=}"
        if path.rotations is not None:
            turn = pin.log3(pose.rotation.T @ path.rotations[i])
            assert np.linalg.norm(turn) < 1e-5, f"{name=} {i=}"
        if path.axes is not None:
            assert np.linalg.norm(pose.rotation[:, 2] - path.axes[i]) < 1e-5, f"{name=} {i=}"
    # continuous: no joint moves more than the step bound between samples
    assert np.abs(np.diff(q, axis=0)).max() <= 0.35 + 1e-12, f"{name=}"
    assert avoided.result.max_deviation < 0.01


def test_a_free_plain_path_is_kept(tmp_path):
    """A cell the plain path misses: the answer is the plain path, no search."""
    far = "[[sphere]]\nname = 'far'\nradius = 0.05\nxyz = [-1.0, -1.0, 1.0]\n"
    robot, path, checker, *_ = _cell(tmp_path, "ur5", far)
    avoided = follow_path_avoiding(robot, path, checker)
    assert avoided.success and not avoided.searched and avoided.plain is None
    np.testing.assert_array_equal(avoided.result.q, follow_path(robot, path).q)


def test_no_free_answer_fails_at_the_first_blocked_sample(tmp_path):
    """A ball on the tool's line: the failure names the first sample every answer of which collides."""
    ball = "[[sphere]]\nname = 'ball'\nradius = 0.03\nxyz = [-0.4, 0.105, 0.3]\n"
    robot, path, checker, reference, pairs, _ = _cell(tmp_path, "ur5", ball)
    avoided = follow_path_avoiding(robot, path, checker)
    assert not avoided.success and avoided.result is None
    failure = avoided.failure
    solver = get_solver(robot)

    def every_answer_collides(index: int) -> bool:
        answers = solver.solve(path.target(index)).solutions
        assert answers, f"{index=}"
        return all(_deepest(reference, pairs, s.q) < -CONTACT_TOL for s in answers)

    blocked = [i for i in range(len(path)) if every_answer_collides(i)]
    assert blocked and failure.sample == blocked[0], f"{blocked=} {failure=}"
    arc = float(np.linalg.norm(path.positions[failure.sample] - path.positions[0]))
    assert failure.arc_length == pytest.approx(arc, abs=1e-12)
    line = failure.describe()
    assert f"sample {failure.sample} " in line and "arc length" in line and "xyz = (-0.4" in line
    assert "collide" in failure.reason and "\n" not in line


def test_a_step_bound_too_small_names_the_jump(tmp_path):
    """Free answers exist but none within the step bound: the failure says how far, which joint."""
    robot, path, checker, *_ = _cell(tmp_path, "ur5")
    avoided = follow_path_avoiding(robot, path, checker, max_joint_step=1e-3)
    assert not avoided.success
    assert avoided.failure.sample == 1
    assert "would jump" in avoided.failure.reason and "from sample 0's" in avoided.failure.reason


def _line(name: str) -> list[str]:
    _, start, end, rpy = CELLS[name]
    point = [str(v) for v in rpy]
    return ["--robot", name, "--steps", str(STEPS), "--quiet", "--from", *map(str, start),
            "--rpy", *point, "--to", *map(str, end), "--rpy", *point]  # fmt: skip


def test_kin_path_avoid_json(tmp_path, capsys):
    """Exit 0; the JSON says free, names the plain path's collision, and the path is the library's."""
    robot, path, checker, _, _, scene = _cell(tmp_path, "ur5")
    code = call(path_command.main, _line("ur5") + ["--scene", str(scene), "--avoid", "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    record = json.loads(out)
    assert record["collisions"]["free"] is True and record["success"] is True
    assert (
        record["avoid"]["searched"] is True and "shelf" in record["avoid"]["plain_path_collision"]
    )
    expected = follow_path_avoiding(robot, path, checker).result.q
    np.testing.assert_allclose(record["q"], expected, atol=1e-9)


def test_kin_path_avoid_failure_is_one_line_and_writes_nothing(tmp_path, capsys):
    """No free answer: exit 1, one stderr line naming the sample, no stdout, no CSV."""
    ball = tmp_path / "ball.toml"
    ball.write_text("[[sphere]]\nradius = 0.03\nxyz = [-0.4, 0.105, 0.3]\n", encoding="utf-8")
    csv = tmp_path / "out.csv"
    argv = _line("ur5") + ["--scene", str(ball), "--avoid", "--csv", str(csv)]
    code = call(path_command.main, argv)
    out, err = capsys.readouterr()
    assert code == 1 and out == "" and not csv.exists()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "no collision-free path at sample" in lines[0], err


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--avoid"], "--avoid needs --scene or --srdf"),
        (["--avoid", "--scene", "/nonexistent/cell.toml"], "cell.toml"),
    ],
)
def test_bad_avoid_input_exits_2(capsys, extra, needle):
    """--avoid without a cell, or with a missing one: one line, exit 2."""
    code = call(path_command.main, _line("ur5") + extra)
    assert_one_line_error(code, capsys.readouterr().err, needle)


def _shelf_between(tmp_path: Path, q0: np.ndarray, q1: np.ndarray) -> str:
    """The shelf moved along x so the reference finds ``q0`` as far from it as ``q1`` is inside.

    The arm comes toward the shelf's face from ``q0`` to ``q1``: the face is put halfway between
    (the distances measured by the reference, a few corrections of the first guess), so a few mm
    of change in the housings keep ``q0`` free and ``q1`` on the shelf.
    """
    x = 0.183
    for _ in range(4):
        *_, reference, pairs, _ = _cell(tmp_path, "ur5", SHELF_TEXT.format(x=x))
        shelf = [p for p in pairs if "shelf" in p]
        d0, d1 = (_deepest(reference, shelf, q) for q in (q0, q1))
        assert d0 - d1 > 0.004, f"{d0=} {d1=}"  # the branch moves toward the shelf
        if abs(d0 + d1) < 1e-4:
            break
        x -= (d0 + d1) / 2.0  # the face at x - 0.05 faces the arm: nearer by what x loses
    return SHELF_TEXT.format(x=x)


def test_a_branch_that_runs_into_the_shelf_fails_where_it_would_jump(tmp_path):
    """The first sample forced onto the shelf's branch: the next sample's free answers all jump."""
    robot, path, *_ = _cell(tmp_path, "ur5")
    branch = "shoulder left, wrist up, elbow down"
    plain = follow_path(robot, path, branch=branch)
    shelf = _shelf_between(tmp_path, plain.q[0], plain.q[1])
    robot, path, checker, reference, pairs, _ = _cell(tmp_path, "ur5", shelf)
    assert _deepest(reference, pairs, plain.q[0]) > 0.002  # the branch is free at sample 0
    assert _deepest(reference, pairs, plain.q[1]) < -0.002  # and meets the shelf at sample 1
    avoided = follow_path_avoiding(robot, path, checker, branch=branch)
    assert not avoided.success and avoided.failure.sample == 1
    reason = avoided.failure.reason
    assert "would jump" in reason and "from sample 0's" in reason, reason


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_the_step_bound_of_revolute_arms_is_the_chain_walk(tmp_path, name):
    """The matrix form of the motion bound (all-revolute arms) equals the joint-by-joint walk."""
    from kin.path.collision_check import _Distances

    _, _, checker, *_ = _cell(tmp_path, name)
    helper = _Distances(checker)
    arms, rng = helper.arms, np.random.default_rng(5)
    assert arms is not None and arms.shape[1] == checker.model.robot.nq
    for q0, q1 in rng.uniform(-3.0, 3.0, (20, 2, checker.model.robot.nq)):
        matrix = helper.motion(q0, q1)
        helper.arms = None
        walk = helper.motion(q0, q1)
        helper.arms = arms
        assert walk.max() > 0.0
        np.testing.assert_allclose(matrix, walk, rtol=1e-12, atol=1e-12, err_msg=f"{name=}")


def test_a_plate_between_samples_fails_on_the_way_there(tmp_path):
    """A thin plate across the line between samples 1 and 2: the samples are free, the motion not."""
    plate = "[[box]]\nname = 'plate'\nsize = [0.02, 0.004, 0.02]\nxyz = [-0.4, 0.05, 0.3]\n"
    robot, _, checker, reference, pairs, _ = _cell(tmp_path, "ur5", plate)
    down = pin.rpy.rpyToMatrix(3.14159, 0.0, 3.14159)
    path = polyline(
        [PoseTarget(np.array(p), down) for p in ((-0.4, -0.1, 0.3), (-0.4, 0.3, 0.3))], 4
    )
    solver = get_solver(robot)
    for index in range(3):  # each sample up to the plate has a free answer (reference)
        answers = solver.solve(path.target(index)).solutions
        assert max(_deepest(reference, pairs, s.q) for s in answers) > CONTACT_TOL, f"{index=}"
    plain = follow_path(robot, path).q
    between = [_deepest(reference, pairs, plain[1] + t * (plain[2] - plain[1])) for t in (0.3, 0.4)]
    assert min(between) < -CONTACT_TOL  # the plain motion goes through the plate
    avoided = follow_path_avoiding(robot, path, checker)
    assert not avoided.success and avoided.failure.sample == 2
    assert "collides on the way there (link6 / plate, scene)" in avoided.failure.reason


def test_the_failure_names_the_first_sample_no_checked_chain_reaches():
    """A later sample cut off first by a colliding motion: the earlier one cut off too is named.

    Two answers per sample on a 2-joint stand-in, joined one to one within the step bound 0.35:
    chain A (cheapest) reaches samples 1-3, chain B only samples 1-2, and every motion out of
    sample 0 collides. Checking A's first motion cuts off sample 3 (B cannot reach it); B's own
    first motion, not yet checked then, cuts off sample 1, the sample to name.
    """
    from kin.path.avoid import _Layer, _Search
    from kin.path.collision_check import PathCollision

    origin = np.zeros(2)

    class Motion:
        def distances(self, q):
            return np.zeros(1)

        def between(self, q0, q1, d0, d1):
            if np.array_equal(q0, origin):
                return PathCollision(0, 0.5, (q0 + q1) / 2, "link", "wall", "scene", False, True)
            return None

    search = object.__new__(_Search)
    search.bound, search.motion = 0.35, Motion()
    search.free, search.colliding, search.blocked = set(), set(), {}
    answers = [[[0.0, 0.0]], [[0.1, 0.0], [0.0, 0.3]], [[0.4, 0.0], [0.0, 0.6]], [[0.7, 0.0]]]
    layers = []
    for index, q in enumerate(answers):
        q = np.array(q)
        layer = _Layer(q, [""] * len(q), np.zeros(len(q)), np.full(len(q), -1), [None] * len(q))
        if layers:
            search._relax(layers[-1], layer, index)
        layers.append(layer)
    assert np.isfinite(layers[3].cost).all() and layers[3].previous[0] == 0  # through A
    assert search._verify(layers) == 1
    assert search.colliding == {(1, 0, 0), (1, 0, 1)} and search.blocked[1].b == "wall"
