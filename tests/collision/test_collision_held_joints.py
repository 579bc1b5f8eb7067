"""The whole robot in its collision model: links off the chain, their joints held (issue 43, item 2).

The reference is built apart from :mod:`kin.collision`: Pinocchio's model and collision model of
the FULL maker URDF of Panda (``pin.buildModelsFromUrdf``, every joint, fingers included), its
meshes taken as coal's convex hulls, every pair asked of ``coal.distance`` one by one: the scene
pairs and the self pairs the maker's SRDF does not disable.
"""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from support.cli_helper import call
from support.held_panda import HAND_DOWN, PANDA, PANDA_SRDF, FullPanda
from support.urdf_reference import erd

import kin
from kin.collision import CollisionChecker, CollisionModelError, load_collision_model
from kin.collision.requests import CONTACT_TOLERANCE
from kin.commands import check

CELL = Path(__file__).parents[1] / "data" / "collision" / "cell.toml"
FINGERS = ("panda_leftfinger", "panda_rightfinger")
#: Closer to contact than this [m], either verdict is right.
NEAR = 1e-6


@cache
def panda_hand() -> kin.RobotModel:
    return kin.load_robot(str(erd(PANDA)), tip="panda_hand")


def _fingertips_lowest(finger: float) -> float:
    """The lowest corner of the fingers' boxes at HAND_DOWN [m] (Pinocchio on the full URDF)."""
    reference = FullPanda(finger, None)
    full = np.concatenate([HAND_DOWN, [finger, finger]])
    pin.forwardKinematics(reference.model, reference.data, full)
    pin.updateGeometryPlacements(
        reference.model, reference.data, reference.collision, reference.geometry_data
    )
    lowest = math.inf
    for g, m in zip(reference.collision.geometryObjects, reference.geometry_data.oMg, strict=True):
        if "finger" in g.name:
            half = np.asarray(g.geometry.halfSide)
            for corner in np.array(np.meshgrid(*[[-1, 1]] * 3)).T.reshape(-1, 3):
                lowest = min(lowest, float(m.act(corner * half)[2]))
    return lowest


def test_issue_hand_down_fingertips_3_cm_into_the_table(tmp_path, capsys):
    """The issue's reproducer: fingertips 3 cm into a table is IN COLLISION, naming a finger."""
    top = _fingertips_lowest(0.0) + 0.03
    scene = tmp_path / "table.toml"
    scene.write_text(
        f'[[box]]\nname = "table"\nsize = [0.4, 0.4, 0.1]\nxyz = [0.5545, 0.0, {top - 0.05!r}]\n'
    )
    argv = ["--robot", str(erd(PANDA)), "--tip", "panda_hand", "--scene", str(scene)]
    assert call(check.main, [*argv, "--q", *map(str, HAND_DOWN)]) == 1
    out = capsys.readouterr().out
    assert "IN COLLISION" in out
    contacts = [line for line in out.splitlines() if line.startswith("contact")]
    assert contacts and all(any(f in line for f in FINGERS) for line in contacts), out
    assert "depth 0.0300 m" in out
    assert "panda_finger_joint1 = 0 m (zero)" in out
    # the hand alone stays clear of the table: the fingers decide
    checker = CollisionChecker(load_collision_model(panda_hand(), scene=scene))
    assert {c.a for c in checker.collisions(np.array(HAND_DOWN))} <= set(FINGERS)


@pytest.mark.parametrize("finger", [None, 0.04])
def test_verdicts_equal_the_full_urdf_check(finger):
    """300 random configurations: verdicts equal coal on the full URDF; fingers decide some."""
    robot = panda_hand()
    hold = None if finger is None else {"panda_finger_joint1": finger}
    model = load_collision_model(robot, srdf=erd(PANDA_SRDF), scene=CELL, hold=hold)
    held = model.held.values["panda_finger_joint1"]
    assert held == (0.001 if finger is None else finger)  # the SRDF's group state 'default'
    checker = CollisionChecker(model)
    reference = FullPanda(held, CELL)
    rng = np.random.default_rng(43)
    decided_by_fingers = compared = 0
    for q in rng.uniform(robot.lower, robot.upper, (300, robot.nq)):
        distances = reference.distances(q)
        if any(-NEAR <= d <= CONTACT_TOLERANCE + NEAR for d in distances.values()):
            continue
        colliding = min(distances.values()) < 0
        assert checker.in_collision(q) == colliding, f"q={q.tolist()} {finger=}"
        compared += 1
        others = [d for (a, b), d in distances.items() if a not in FINGERS and b not in FINGERS]
        decided_by_fingers += colliding and min(others) > 0
    assert compared >= 290
    assert decided_by_fingers > 0, f"{finger=}: no configuration where only a finger collides"


def test_hold_errors_one_line():
    """A bad hold names the joint and the choices, or the limits, or the leader."""
    robot = panda_hand()
    for hold, words in [
        ({"finger_joint1": 0.04}, "choose: panda_finger_joint1"),
        ({"panda_finger_joint2": 0.01}, "hold panda_finger_joint1"),
        ({"panda_joint1": 0.0}, "a joint of the chain"),
        ({"panda_finger_joint1": 0.05}, "outside the joint's limits [0, 0.04] m"),
        ({"panda_finger_joint1": math.nan}, "outside the joint's limits"),
        ({"panda_finger_joint1": "0.01"}, "is not a number"),
    ]:
        with pytest.raises(CollisionModelError, match=None) as error:
            load_collision_model(robot, hold=hold)
        assert words in str(error.value) and "\n" not in str(error.value), (hold, error.value)


def test_srdf_state_ready_first_else_the_files_first(tmp_path):
    """A group state named 'ready' is taken first; else the file's first that sets the joint."""
    states = (
        '<group_state name="open" group="hand"><joint name="panda_finger_joint1" value="0.035"/>'
        "</group_state>"
        '<group_state name="ready" group="hand"><joint name="panda_finger_joint1" value="0.02"/>'
        "</group_state>"
    )
    srdf = tmp_path / "panda.srdf"
    srdf.write_text(f'<robot name="panda">{states}</robot>')
    held = load_collision_model(panda_hand(), srdf=srdf).held
    assert held.values == {"panda_finger_joint1": 0.02, "panda_finger_joint2": 0.02}
    assert "SRDF group_state 'ready'" in held.note and "mimics panda_finger_joint1" in held.note
    srdf.write_text(f'<robot name="panda">{states.replace("ready", "closed")}</robot>')
    assert (
        "= 0.035 m (SRDF group_state 'open')"
        in load_collision_model(panda_hand(), srdf=srdf).held.note
    )


def test_cli_hold(capsys):
    """--hold sets the fingers, said in one line (and in --json); a bad one exits 2, one line."""
    argv = ["--robot", str(erd(PANDA)), "--tip", "panda_hand", "--q", *map(str, HAND_DOWN)]
    assert call(check.main, [*argv, "--hold", "panda_finger_joint1=0.04"]) == 0
    out = capsys.readouterr().out
    assert "joints off the chain held at: panda_finger_joint1 = 0.04 m (hold), " in out
    assert call(check.main, [*argv, "--hold", "panda_finger_joint1=0.04", "--json"]) == 0
    assert '"held_joints": {"panda_finger_joint1": 0.04, "panda_finger_joint2": 0.04}' in (
        capsys.readouterr().out
    )
    for bad in ("panda_finger_joint1", "panda_finger_joint1=x", "panda_finger_joint1=0.5"):
        assert call(check.main, [*argv, "--hold", bad]) == 2
        captured = capsys.readouterr()
        assert captured.out == "" and len(captured.err.strip().splitlines()) == 1, bad


def test_ur5_ee_link_beyond_tool0():
    """example-robot-data's UR5 to tool0: ee_link (off the chain) is in the model, on wrist 3."""
    robot = kin.load_robot(str(erd("ur_description/urdf/ur5_robot.urdf")), tip="tool0")
    model = load_collision_model(robot)
    assert "ee_link" in model.links
    assert model.disabled[("wrist_3_link", "ee_link")] == "adjacent"
    assert model.held.note == ""  # no joint off the chain
