"""The compiled walk of a free angle (``kin/_native/ik/analytic/planar/_pitch_sweep.c``) gives the Python walk's answer.

A position on a ``yaw_planar`` arm leaves the pitch free, on a planar 3R the yaw: when the seed's
value has no branch inside the limits, a 10-degree then 1-degree walk finds the nearest that has
one (:func:`kin.ik.analytic.planar.free_angle.free_angle_branches`). The twin answers that walk
in C; the same structure with ``compiled = False`` walks in Python. Both must give the same
branches, the same stated angle and the same labels, on reachable points, on points off the
reach and from seeds all round the turn; and the walk must be exercised (most targets swept).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from support.dh_reference import fk_frames, load_reference

from dh2urdf import load_table
from kin.ik.analytic.planar import free_angle
from kin.ik.analytic.planar.parallel_axes import ParallelAxes3
from kin.ik.analytic.planar.yaw_planar import YawPlanar

TOOLBOX = Path(__file__).parents[1] / "data" / "toolbox"

needs_twin = pytest.mark.skipif(
    free_angle._twin() is None, reason="kin/ik/analytic/planar/_pitch_sweep not built"
)

#: A planar 3R with joint limits (the yaw's sweep of ParallelAxes3), lengths in meters.
PLANAR3R = """
name = "planar3r"
convention = "standard"
length_unit = "m"
angle_unit = "deg"
[[joints]]
name = "j1"
type = "revolute"
a = 0.4
alpha = 0.0
d = 0.0
theta = 0.0
limits = [-90.0, 90.0]
[[joints]]
name = "j2"
type = "revolute"
a = 0.3
alpha = 0.0
d = 0.0
theta = 0.0
limits = [-150.0, 10.0]
[[joints]]
name = "j3"
type = "revolute"
a = 0.1
alpha = 0.0
d = 0.0
theta = 0.0
limits = [-45.0, 45.0]
"""


def _structure(arm: str, tmp_path: Path):
    """The structure and its table file."""
    if arm == "planar3r":
        path = tmp_path / "planar3r.toml"
        path.write_text(PLANAR3R)
        return ParallelAxes3(load_table(path)), path
    path = TOOLBOX / f"{arm}.toml"
    return YawPlanar(load_table(path)), path


def _compare(structure, points: np.ndarray, seeds: np.ndarray) -> int:
    """Both walks on every point and seed; returns how many answers were swept to."""
    swept = 0
    for position, seed in zip(points, seeds):
        structure.compiled = True
        q_c, label_c = structure.free_branches(position, seed)
        structure.compiled = False
        q_p, label_p = structure.free_branches(position, seed)
        assert label_c == label_p, f"{position=} {seed=}"
        assert np.array_equal(q_c, q_p, equal_nan=True), f"{position=} {seed=}\n{q_c}\n{q_p}"
        swept += "deg" in label_c
    return swept


@needs_twin
@pytest.mark.parametrize("arm", ["al5d", "orion5", "planar3r"])
def test_compiled_walk_gives_the_python_walk(arm, tmp_path):
    """300 points (reachable, boxed, far) from random seeds: the same branches and labels."""
    structure, path = _structure(arm, tmp_path)
    reference = load_reference(path)
    rng = np.random.default_rng(7)
    lower = np.maximum(structure.lower, -math.pi)
    upper = np.minimum(structure.upper, math.pi)
    dof = len(lower)
    # reachable: the FK of random joint vectors is the point of a yaw (pitch) the sweep meets
    qs = rng.uniform(lower, upper, size=(200, dof))
    reach = np.array([fk_frames(reference, q)[0, -1][:3, 3] for q in qs])
    box = rng.uniform(reach.min(axis=0) * 1.2, reach.max(axis=0) * 1.2, size=(100, 3))
    points = np.concatenate([reach, box])
    seeds = rng.uniform(-math.pi, math.pi, size=(len(points), dof))
    swept = _compare(structure, points, seeds)
    assert swept > 50, f"{arm=}: the walk was exercised on {swept} targets only"


@needs_twin
def test_compiled_walk_refuses_a_bad_chain():
    """A chain of the wrong length is a ValueError naming the layout, not a crash."""
    module = free_angle._twin()
    with pytest.raises(ValueError, match="18 floats"):
        module.first_inside(0.0, (1.0,) * 5)
    assert math.isnan(module.first_inside(0.0, (0.0,) * 18))  # no point: no hit


@needs_twin
def test_the_solver_answers_the_same_with_and_without_the_twin():
    """Through ``get_solver``: 100 AL5D positions seeded at zero (mostly swept), same solutions."""
    from kin import load_robot
    from kin.ik import PositionTarget, get_solver

    robot = load_robot(TOOLBOX / "al5d.toml")
    solver = get_solver(robot)
    structure = solver.structure
    assert isinstance(structure, YawPlanar) and structure._walk_data is not None
    reference = load_reference(TOOLBOX / "al5d.toml")
    rng = np.random.default_rng(3)
    qs = rng.uniform(np.maximum(robot.lower, -math.pi), np.minimum(robot.upper, math.pi), (100, 4))
    swept = 0
    for q in qs:
        target = PositionTarget(fk_frames(reference, q)[0, -1][:3, 3])
        structure.compiled = True
        compiled = solver.solve(target, np.zeros(4))
        structure.compiled = False
        python = solver.solve(target, np.zeros(4))
        assert compiled.success and python.success, f"{q=}"
        assert [s.branch for s in compiled.solutions] == [s.branch for s in python.solutions]
        for a, b in zip(compiled.solutions, python.solutions):
            assert np.array_equal(a.q, b.q), f"{q=}"
        swept += "deg" in compiled.solutions[0].branch
    assert swept > 30, f"the walk was exercised on {swept} targets only"


def test_a_chain_with_a_slide_walks_in_python():
    """The twin takes three revolute joints alone: a SCARA's chain has no walk data."""
    from kin.ik.analytic.planar.parallel_axes import ParallelAxes

    structure = ParallelAxes(load_table(TOOLBOX / "cobra600.toml"))
    chain = structure.chain
    assert chain.prismatic and chain.walk_data([0.0] * 3, [1.0] * 3) is None
