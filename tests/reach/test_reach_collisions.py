"""``kin reach --scene/--srdf``: only collision-free answers count, judged by coal called directly.

A box filling the half space x < -0.15 m beside UR5: the map counts fewer voxels than without it,
and each voxel's count is the number of orientations with at least one valid closed-form branch
that the direct coal check (tests/support/collision_reference.py) finds free. The face stays 3.8 cm clear
of the base and shoulder housings (link1, 0.112 m radius, turning with the first joint only), so
the arm can reach past it; at x < -0.05 m, beside the old 1 cm sticks, they met it in every
posture and nothing was free (issue 43).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error, call
from support.collision_reference import CollisionReference

from kin import load_robot
from kin.commands import reach as reach_command
from kin.ik import solve_batch
from kin.reach.map import load_reach_map, reachability_map

HALF = """
[[box]]
name = "half"
size = [2.0, 4.0, 4.0]
xyz = [-1.15, 0.0, 0.0]
"""
VOXEL, K = 0.2, 4


@pytest.fixture(scope="module")
def scene(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("cell") / "half.toml"
    path.write_text(HALF, encoding="utf-8")
    return path


def test_a_scene_counts_exactly_the_free_answers(scene):
    """Fewer voxels than without the box; per voxel, the orientations with a reference-free branch."""
    from kin.collision import load_collision_model

    robot = load_robot("ur5")
    plain = reachability_map(robot, VOXEL, K)
    blocked = reachability_map(robot, VOXEL, K, scene=scene)
    assert "collision-free answers only" in blocked.collisions and plain.collisions == ""
    assert (blocked.index > 0).sum() < (plain.index > 0).sum()
    assert (blocked.index <= plain.index).all()
    pairs = [tuple(p) for p in load_collision_model(robot, scene=scene).pairs]
    reference = CollisionReference(robot.urdf, None, robot.joint_names, None, scene)
    centers = plain.centers_m.reshape(-1, 3)
    reached = np.flatnonzero(plain.index.reshape(-1) > 0)
    positions = np.repeat(centers[reached], K, axis=0)
    frames = np.broadcast_to(plain.rotations, (len(reached), K, 3, 3)).reshape(-1, 3, 3)
    branches = solve_batch(robot, positions, frames, all_branches=True).branches
    assert branches is not None
    expected = np.zeros(len(positions), dtype=int)
    near = 0
    for row, column in zip(*np.nonzero(branches.valid)):
        if expected[row]:
            continue
        distances = reference.signed_distances(branches.q[row, column], pairs)
        deepest = min(d for d, _ in distances.values())
        near += abs(deepest) <= 1e-6
        expected[row] = deepest > 0
    assert near == 0  # no answer within 1e-6 m of contact: every verdict is sharp
    counts = np.rint(blocked.index.reshape(-1)[reached] * K).astype(int)
    np.testing.assert_array_equal(counts, expected.reshape(-1, K).sum(axis=1))
    assert 0 < counts.sum() < np.rint(plain.index.reshape(-1)[reached] * K).sum()


def test_the_map_file_and_json_say_collision_free(scene, tmp_path, capsys):
    """The .npz, the JSON and the summary name the check; the file round-trips it."""
    output = tmp_path / "map.npz"
    argv = ["--robot", "ur5", "--voxel", "0.4", "--orientations", "2", "-o", str(output)]
    code = call(reach_command.main, argv + ["--scene", str(scene), "--quiet", "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert json.loads(out)["collisions"].startswith("collision-free answers only (scene half.toml")
    assert load_reach_map(output).collisions.startswith("collision-free answers only")
    code = call(reach_command.main, argv + ["--scene", str(scene), "--quiet"])
    out, err = capsys.readouterr()
    assert code == 0 and "counted: collision-free answers only" in out, err


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--scene", "/nonexistent/cell.toml"], "cell.toml"),
        (["--padding", "0.01"], "--padding needs --scene or --srdf"),
    ],
)
def test_bad_collision_input_exits_2(tmp_path, capsys, extra, needle):
    """A missing scene, or --padding alone: one line, exit 2, no map written."""
    output = tmp_path / "map.npz"
    argv = ["--robot", "ur5", "--voxel", "0.4", "--orientations", "2", "-o", str(output)]
    code = call(reach_command.main, argv + extra + ["--quiet"])
    assert_one_line_error(code, capsys.readouterr().err, needle)
    assert not output.exists()
