"""Objects attached to a link (issue 43, item 3): checked in kin check, IK, paths and reach maps.

The reference is built apart from :mod:`kin.collision`: Pinocchio's FK of the full maker URDF
(or of the DH robot's URDF text) gives the link's placement, composed with the attach pose; coal
measures the object against the scene box and the links with their own shapes, as written in
the URDF.
"""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path

import coal
import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import call
from support.held_panda import HAND_DOWN, FullPanda, _distance
from support.urdf_reference import erd

import kin
from kin.collision import (
    CollisionChecker,
    CollisionModelError,
    attached_object,
    load_collision_model,
)
from kin.collision.requests import CONTACT_TOLERANCE
from kin.commands import check

PANDA = "panda_description/urdf/panda.urdf"
#: The part in the hand: a rod along the hand's z axis, tilted 20 deg about x [m, deg].
PART = """
angle_unit = "deg"

[[box]]
name = "table"
size = [0.8, 0.8, 0.1]
xyz = [0.5, 0.0, 0.25]

[[attached]]
name = "part"
shape = "cylinder"
radius = 0.02
length = 0.3
link = "panda_hand"
xyz = [0.0, 0.03, 0.2]
rpy = [20.0, 0.0, 0.0]
touch_links = ["panda_leftfinger", "panda_rightfinger"]
"""
#: Links that ride with panda_hand when the fingers are held (never checked against the part).
WITH_THE_HAND = {"panda_link7", "panda_hand", "panda_leftfinger", "panda_rightfinger"}
NEAR = 1e-6


@cache
def panda_hand() -> kin.RobotModel:
    return kin.load_robot(str(erd(PANDA)), tip="panda_hand")


def _scene(folder: Path, text: str = PART) -> Path:
    folder.mkdir(exist_ok=True)
    path = folder / "cell.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _part_reference(reference: FullPanda, q: np.ndarray) -> dict[str, float]:
    """The part's signed distance to the table and to each checked link [m] at ``q``."""
    full = np.concatenate([q, [0.0, 0.0]])
    pin.framesForwardKinematics(reference.model, reference.data, full)
    pin.updateGeometryPlacements(
        reference.model, reference.data, reference.collision, reference.geometry_data
    )
    hand = reference.data.oMf[reference.model.getFrameId("panda_hand")]
    pose = pin.SE3(pin.rpy.rpyToMatrix(math.radians(20.0), 0.0, 0.0), np.array([0.0, 0.03, 0.2]))
    part = [(coal.Cylinder(0.02, 0.3), hand * pose)]
    shapes: dict[str, list] = {}
    for g, m in zip(reference.collision.geometryObjects, reference.geometry_data.oMg, strict=True):
        owner = reference.model.frames[g.parentFrame].name
        if owner not in WITH_THE_HAND:
            shapes.setdefault(owner, []).append((g.geometry, m))
    table = [(coal.Box(0.8, 0.8, 0.1), pin.SE3(np.eye(3), np.array([0.5, 0.0, 0.25])))]
    out = {name: _distance(part, placed) for name, placed in shapes.items()}
    out["table"] = _distance(part, table)
    return out


def test_kin_check_attached_against_the_full_urdf(tmp_path, capsys):
    """300 random configurations: the part's verdicts equal coal on Pinocchio's link placement."""
    scene = _scene(tmp_path)
    model = load_collision_model(panda_hand(), scene=scene)
    assert [t.name for t in model.attached] == ["part"]
    assert model.disabled[("panda_hand", "part")] == "touch"
    assert model.disabled[("panda_leftfinger", "part")] == "touch"
    assert model.disabled[("panda_link7", "part")] == "rigid"
    checker = CollisionChecker(model)
    reference = FullPanda(0.0, None)
    rng = np.random.default_rng(3)
    hits = {"table": 0, "link": 0}
    robot = panda_hand()
    for q in rng.uniform(robot.lower, robot.upper, (300, robot.nq)):
        expected = _part_reference(reference, q)
        if any(-NEAR <= d <= CONTACT_TOLERANCE + NEAR for d in expected.values()):
            continue
        found = {
            c.b if c.a == "part" else c.a for c in checker.collisions(q) if "part" in (c.a, c.b)
        }
        assert found == {name for name, d in expected.items() if d < 0}, f"q={q.tolist()}"
        hits["table"] += "table" in found
        hits["link"] += bool(found - {"table"})
    assert hits["table"] > 0 and hits["link"] > 0, hits
    # the command: the part 12.5 cm into the table, hand down
    argv = ["--robot", str(erd(PANDA)), "--tip", "panda_hand", "--q", *map(str, HAND_DOWN)]
    assert call(check.main, [*argv, "--scene", str(scene)]) == 1
    assert "contact (scene): part / table" in capsys.readouterr().out


def test_attach_detach_give_new_models(tmp_path):
    """The API's attach equals the scene file's [[attached]]; detach frees the hand again."""
    table_only = _scene(tmp_path, PART.split("[[attached]]")[0])
    bare = load_collision_model(panda_hand(), scene=table_only)
    part = attached_object(
        "part",
        "panda_hand",
        cylinder=(0.02, 0.3),
        xyz=(0.0, 0.03, 0.2),
        rpy=(math.radians(20.0), 0.0, 0.0),
        touch_links=["panda_leftfinger", "panda_rightfinger"],
    )
    holding = bare.attach(part)
    from_file = load_collision_model(panda_hand(), scene=_scene(tmp_path / "part", PART))
    q = np.array(HAND_DOWN)
    assert bare.attached == () and not CollisionChecker(bare).in_collision(q)
    assert CollisionChecker(holding).distance(q).distance == pytest.approx(
        CollisionChecker(from_file).distance(q).distance, abs=1e-12
    )
    assert holding.pairs == from_file.pairs
    released = holding.detach("part")
    assert released.pairs == bare.pairs and not CollisionChecker(released).in_collision(q)
    with pytest.raises(CollisionModelError, match="no attached object 'tool'; attached: part"):
        holding.detach("tool")
    with pytest.raises(CollisionModelError, match="the robot has no link 'hand'"):
        bare.attach(attached_object("x", "hand", sphere=0.1))
    with pytest.raises(CollisionModelError, match="the name is taken"):
        holding.attach(part)


@pytest.mark.parametrize(
    ("entry", "words"),
    [
        ('shape = "cone"\nlink = "panda_hand"', "attached[0].shape: 'cone'"),
        ('shape = "sphere"\nradius = 0.1', "attached[0].link: missing"),
        ('shape = "sphere"\nradius = 0.1\nlink = "panda_hand"\ncolor = 1', "attached[0].color"),
        ('shape = "sphere"\nradius = 0.1\nlink = "nowhere"', "the robot has no link 'nowhere'"),
        ('shape = "sphere"\nradius = 0.1\nlink = "panda_hand"\ntouch_links = "x"', "touch_links"),
        ('shape = "sphere"\nradius = 40\nlink = "panda_hand"', "attached[0].radius"),
    ],
)
def test_bad_attached_entries_one_line(tmp_path, entry, words):
    """A bad [[attached]] entry is one line naming the file and the field."""
    scene = _scene(tmp_path, f"[[attached]]\n{entry}\n")
    with pytest.raises(CollisionModelError) as error:
        load_collision_model(panda_hand(), scene=scene)
    message = str(error.value)
    assert str(scene) in message and words in message and "\n" not in message, message


# -- IK and reach maps: a 0.4 m rod on UR5's tool along its z axis, a table beside the base -----

ROD = """
[[box]]
name = "table"
size = [0.4, 0.4, 0.04]
xyz = [0.45, 0.2, 0.08]

[[attached]]
name = "rod"
shape = "cylinder"
radius = 0.02
length = 0.4
link = "tool"
xyz = [0.0, 0.0, 0.21]  # 1 cm beyond the flange: clear of the wrist
"""


def test_ik_rejects_answers_that_put_the_rod_in_the_table(tmp_path):
    """Tool 0.2 m above a table pointing down: the rod (0.4 m) reaches through it, no answer."""
    from kin.ik import PoseTarget, get_solver
    from kin.ik.collision.collision_aware import CollisionAwareSolver

    robot = kin.load_robot("ur5")
    target = PoseTarget([0.4, 0.2, 0.3], pin.rpy.rpyToMatrix(math.pi, 0.0, 0.0))  # z down
    results = {}
    for text in (ROD, ROD.split("[[attached]]")[0]):
        checker = CollisionChecker(load_collision_model(robot, scene=_scene(tmp_path, text)))
        solver = CollisionAwareSolver(get_solver(robot), checker)
        results[text] = solver.solve(target, np.zeros(robot.nq), timeout=2.0)
    with_rod, without = results[ROD], results[ROD.split("[[attached]]")[0]]
    assert without.success
    # the rod spans z 0.29 .. -0.11 at this pose, the table 0.06 .. 0.10: every answer collides
    assert not with_rod.success and with_rod.status == "in_collision"
    assert with_rod.rejected and all(r.reason.startswith("scene: table") for r in with_rod.rejected)


def test_path_motion_sweeps_the_rod_through_a_plate(tmp_path):
    """Two free samples; the part alone crosses a plate between them: the path collides."""
    from kin.path.collision_check import check_path_collisions

    robot = panda_hand()
    plate = '[[box]]\nname = "plate"\nsize = [0.3, 0.01, 0.1]\nxyz = [0.55, 0.0, 0.33]\n'
    part = (
        '[[attached]]\nname = "part"\nshape = "cylinder"\nradius = 0.02\nlength = 0.3\n'
        'link = "panda_hand"\nxyz = [0.0, 0.0, 0.2]\n'
    )
    ends = np.array([HAND_DOWN, HAND_DOWN])
    ends[:, 0] = (-0.5, 0.5)  # joint 1 swings the hand across the plate's plane y = 0
    first = {}
    for name, text in (("bare", plate), ("holding", plate + part)):
        checker = CollisionChecker(load_collision_model(robot, scene=_scene(tmp_path, text)))
        assert not checker.in_collision_batch(ends).any(), name
        first[name] = check_path_collisions(checker, ends).first
    assert first["bare"] is None
    assert first["holding"] is not None and "part" in first["holding"].describe()


def test_reach_map_counts_fewer_with_the_rod(tmp_path):
    """Reach counts: the rod rules out the orientations that point it into the table."""
    from kin.reach.grid import super_fibonacci_rotations
    from kin.reach.map import count_reached

    robot = kin.load_robot("ur5")
    centers = np.array([[0.4, 0.2, 0.3], [0.3, -0.3, 0.35], [-0.4, 0.1, 0.3]])
    rotations = super_fibonacci_rotations(24)
    counts = {}
    for name, text in (("rod", ROD), ("bare", ROD.split("[[attached]]")[0])):
        scene = tmp_path / f"{name}.toml"
        scene.write_text(text)
        counts[name] = count_reached(robot, centers, rotations, collisions=(scene, None, 0.0, None))
    assert (counts["rod"] <= counts["bare"]).all() and counts["rod"].sum() < counts["bare"].sum()
