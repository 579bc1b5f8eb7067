"""One verdict downstream of the checker: paths and the distance-bounded IK near contact.

Issue 42 item 4: ``in_collision``, paths and IK agree on every configuration, near contact
included. The checker counts a pair in contact below
:data:`~kin.collision.requests.CONTACT_TOLERANCE` (10 um); the path check called the motion between
two free samples free whenever the distance stayed above 0 (a pass at 5 um, which ``in_collision``
calls contact, was "free"), and the distance-bounded IK called a run clear at any positive
distance. Judged here on a planar arm whose sphere passes a scene sphere: the closest approach
is the gap placed by hand (sphere-sphere distance, exact), at ``q1 = 0``.
"""

from __future__ import annotations

import numpy as np
import pytest

from kin import load_robot
from kin.collision import CollisionChecker, load_collision_model
from kin.collision.requests import CONTACT_TOLERANCE
from kin.ik import PositionTarget
from kin.ik.collision.collision_bound import DistanceBoundedIK
from kin.ik.collision.distance_bound import DistanceBound
from kin.path import check_path_collisions

#: A two-joint arm about z: a sphere of radius 5 cm centred 0.5 m out along x on the first link,
#: the second joint at the sphere's centre, the tool 0.1 m to its side (the second link carries no
#: shape: the sphere's distance depends on q1 alone).
ARM = """<robot name="swing">
 <link name="base"/>
 <link name="arm"><collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.05"/></geometry>
 </collision></link>
 <link name="hand"/>
 <link name="tip"/>
 <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
  <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
 <joint name="j2" type="revolute"><parent link="arm"/><child link="hand"/><axis xyz="0 0 1"/>
  <origin xyz="0.5 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
 <joint name="tip_joint" type="fixed"><parent link="hand"/><child link="tip"/>
  <origin xyz="0 0.1 0"/></joint>
</robot>
"""
#: The arm's sphere centre [m]; the scene sphere's radius [m].
REACH, RADIUS = 0.5, 0.05
#: Closest approaches [m]: in contact below the tolerance (passes within (0, tol) among them).
CONTACT_GAPS = [7.5e-6, 3e-6, 1e-6, 1e-9, 0.0, -1e-6, -1e-5]
#: Free: 1.5 and 3 times the tolerance.
FREE_GAPS = [1.5 * CONTACT_TOLERANCE, 3 * CONTACT_TOLERANCE]


@pytest.fixture(scope="module")
def swing(tmp_path_factory):
    """A function of the gap: the checker of the arm with a scene sphere that far at q = 0."""
    folder = tmp_path_factory.mktemp("swing")
    (folder / "swing.urdf").write_text(ARM, encoding="utf-8")
    robot = load_robot(str(folder / "swing.urdf"), None, "tip")

    def checker(gap: float) -> CollisionChecker:
        scene = folder / f"ball{gap!r}.toml"
        x = REACH + 2 * RADIUS + gap
        scene.write_text(f'[[sphere]]\nname = "ball"\nradius = {RADIUS}\nxyz = [{x!r}, 0.0, 0.0]\n')
        return CollisionChecker(load_collision_model(robot, scene=scene))

    return robot, checker


def gap_at(gap: float, angle: float) -> float:
    """Exact distance [m] of the arm's sphere at ``angle`` [rad] from the scene sphere."""
    x = REACH + 2 * RADIUS + gap
    centre = REACH * np.array([np.cos(angle), np.sin(angle)])
    return float(np.hypot(centre[0] - x, centre[1]) - 2 * RADIUS)


@pytest.mark.parametrize("gap", CONTACT_GAPS + FREE_GAPS)
def test_a_path_passing_the_ball_is_judged_as_in_collision_judges_its_closest_point(swing, gap):
    """Two free samples either side of the ball: colliding exactly when in_collision calls the
    closest point (the gap) contact; a named contact is one in_collision calls contact."""
    _, make = swing
    checker = make(gap)
    path = np.array([[-0.2, 0.4], [0.13, -0.1]])  # no bisection point lands on q1 = 0 itself
    assert gap_at(gap, -0.2) > 1e-3 and gap_at(gap, 0.13) > 1e-3  # both samples far and free
    closest = checker.in_collision(np.zeros(2))
    assert closest is (gap < CONTACT_TOLERANCE), f"{gap=}"  # the checker's verdict of the gap
    result = check_path_collisions(checker, path)
    assert not result.sample_collisions.any(), f"{gap=}"
    assert result.free is not closest, f"{gap=}: {result.describe()}"
    if not closest:
        return
    first = result.first
    assert first is not None and not first.at_sample and first.segment == 0, f"{gap=}"
    assert (first.a, first.b, first.kind) == ("arm", "ball", "scene")
    # the place named is in contact by in_collision and by the exact distance, on the way in
    assert first.proven and checker.in_collision(first.q), f"{gap=}"
    assert first.q[0] < 0.0 and gap_at(gap, first.q[0]) < CONTACT_TOLERANCE, f"{gap=} {first.q}"


@pytest.mark.parametrize("gap", CONTACT_GAPS[:3] + FREE_GAPS)
def test_a_bounded_run_called_clear_is_free_by_in_collision(swing, gap):
    """The distance-bounded IK toward the tool position at the closest point, no extra margin:
    a run is clear (and the solve answers) exactly where in_collision calls its answer free."""
    robot, make = swing
    checker = make(gap)
    target = PositionTarget(np.array([REACH, 0.1, 0.0]))  # the tool at q = 0
    ik = DistanceBoundedIK(robot, checker, DistanceBound(margin=0.0, random_starts=0))
    outcome = ik.run(target, np.array([-0.3, 0.2]), position_tol=1e-7)
    assert outcome.converged is (gap > CONTACT_TOLERANCE), f"{gap=} {outcome}"
    if outcome.converged:
        assert not checker.in_collision(outcome.q), f"{gap=} {outcome}"
    else:  # held off the target beyond the tolerance, where in_collision says free
        assert outcome.distance > CONTACT_TOLERANCE and not checker.in_collision(outcome.q)
    assert outcome.distance == pytest.approx(gap_at(gap, outcome.q[0]), abs=1e-8)
    result = ik.solve(target, [np.array([-0.3, 0.2])], position_tol=1e-6)
    assert result.success is (gap > CONTACT_TOLERANCE), f"{gap=} {result.message}"
    for solution in result.solutions:
        assert not checker.in_collision(solution.q), f"{gap=}"
        assert gap_at(gap, solution.q[0]) > CONTACT_TOLERANCE
