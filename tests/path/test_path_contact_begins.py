"""A colliding path says so on stdout, with the first colliding sample and where contact begins.

Issue 42: ``kin path --scene`` without ``--avoid`` printed "21 samples, followed" for a colliding
path (only stderr and the exit code said otherwise) and named the first colliding sample's end,
not where contact begins. The README's cell (examples/cell.toml): the UR5's tool pointing down in
front of its base (x = -0.4 m in the maker's base frame), lowered from 0.3 m to -0.15 m, meets the
table (top at z = -0.02 m) between samples 14 and 15.
The place named is compared with a dense scan of the segment by the checker's own verdict.
"""

from __future__ import annotations

import json
import re
from functools import cache
from pathlib import Path

import numpy as np
from support.cli_helper import call

from kin import load_robot
from kin.commands import path as path_command
from kin.path import check_path_collisions

CELL = Path(__file__).parents[2] / "examples" / "cell.toml"
DOWN = ["--rpy", "180", "0", "180"]
LOWERED = ["--robot", "ur5", "--deg", "--steps", "20", "--quiet", "--scene", str(CELL), "--from", "-0.4", "-0.1", "0.3", *DOWN, "--to", "-0.4", "-0.1", "-0.15", *DOWN]  # fmt: skip
#: Points of the dense scan of a segment.
DENSE = 4001


@cache
def lowered_path() -> tuple[object, np.ndarray]:
    """(checker, joint path) of the lowered tool (:data:`LOWERED`), 21 samples."""
    from kin.collision import CollisionChecker, load_collision_model
    from kin.ik import PoseTarget
    from kin.ik.angles import rpy_matrix
    from kin.path import follow_path, polyline

    robot = load_robot("ur5")
    checker = CollisionChecker(load_collision_model(robot, scene=CELL))
    down = np.array(rpy_matrix(np.pi, 0.0, np.pi))
    path = polyline(
        [PoseTarget([-0.4, -0.1, 0.3], down), PoseTarget([-0.4, -0.1, -0.15], down)], 20
    )
    result = follow_path(robot, path)
    assert result.success and len(result.q) == 21
    return checker, result.q


def test_contact_begins_where_a_dense_scan_first_sees_it():
    """The fraction named is in contact, and a dense scan of the segment is free before it."""
    checker, q = lowered_path()
    check = check_path_collisions(checker, q)
    first = check.first
    assert first is not None and first.proven and not first.at_sample
    assert check.first_sample == 15 and first.segment == 14 and first.b == "table"
    assert 0.0 < first.fraction < 1.0
    q0, q1 = q[14], q[15]
    assert checker.in_collision(q0 + first.fraction * (q1 - q0))
    t = np.linspace(0.0, 1.0, DENSE)
    hits = [s for s in t if checker.in_collision(q0 + s * (q1 - q0))]
    assert hits, "the dense scan must see the contact"
    step = 1.0 / (DENSE - 1)
    assert hits[0] - step <= first.fraction <= hits[0] + 1e-12, (first.fraction, hits[0])
    # every sample before the segment's end is free: the first colliding sample is its end
    assert not check.sample_collisions[:15].any() and check.sample_collisions[15]


def test_kin_path_says_it_collides_on_stdout_and_in_json(capsys):
    """Text: the summary and the collisions line; --json: the same sample and fraction."""
    code = call(path_command.main, LOWERED)
    out, err = capsys.readouterr()
    assert code == 1
    head = out.splitlines()[0]
    assert "21 samples" in head and "IN COLLISION" in head, head
    line = next(row for row in out.splitlines() if row.startswith("collisions:"))
    assert "first colliding sample 15" in line, line
    found = re.search(r"contact begins between samples 14 and 15 at t = ([0-9.]+)", line)
    assert found is not None, line
    assert "first colliding sample 15" in err and len(err.strip().splitlines()) == 1
    code = call(path_command.main, [*LOWERED, "--json"])
    record = json.loads(capsys.readouterr().out)["collisions"]
    assert code == 1
    assert record["free"] is False and record["first_colliding_sample"] == 15
    assert record["first"]["segment"] == 14 and record["first"]["at_sample"] is False
    assert abs(record["first"]["fraction"] - float(found.group(1))) < 1e-6
    assert record["resolution_m"] == 1e-6


def test_a_free_path_says_free(capsys, tmp_path):
    """A path above the table: no IN COLLISION in the summary, 'collisions: free', exit 0."""
    argv = [*LOWERED[: LOWERED.index("--to")], "--to", "-0.4", "-0.1", "0.2", *DOWN]
    code = call(path_command.main, argv)
    out = capsys.readouterr().out
    assert code == 0
    assert "IN COLLISION" not in out and "collisions: free" in out
