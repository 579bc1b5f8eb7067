"""Headers count what they show and what they hide; identical joint vectors are one branch.

Issue 42: without ``--all`` ``kin ik`` printed "ok: 8 valid solution(s)" above one row; with
``--scene`` the README's target said "1 collision-free, 0 colliding rejected" and with ``--all``
"4 ... 4 colliding rejected" (the judging stopped at the first free answer); ``--stdin`` with
``"all": true`` and ``--scene`` returned the first free answer alone; at a wrist singularity
(q5 = 0) the two wrist branches were one joint vector counted twice. The counts are compared
across text, ``--json`` and ``--stdin``; the branches with a pairwise check written here.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from support.cli_helper import call, run

from kin import Configuration, load_robot
from kin.commands import ik as ik_command
from kin.ik import PoseTarget, solve_ik
from kin.ik.result import SAME_BRANCH, IKSolution, distinct_solutions

CELL = str(Path(__file__).parents[2] / "examples" / "cell.toml")
README_TARGET = ["--robot", "ur5", "--target", "0.4", "0.1", "0.3", "--rpy", "180", "0", "0", "--deg"]  # fmt: skip
README_LINE = '{"target": [0.4, 0.1, 0.3], "rpy": [180, 0, 0]}'
#: The README's cell answers: free and colliding of the 8 branches (UR5's housings, issue 43;
#: with the 1 cm sticks of the old table 4 and 4), as the coal reference judges them.
README_FREE, README_REJECTED = 2, 6
#: Joint vectors at a wrist singularity (the wrist's middle joint straight) [rad].
SINGULAR = {
    "ur5": [0.3, -1.2, 1.4, -0.5, 0.0, 0.2],
    "puma560": [0.3, -0.5, 0.4, 0.2, 0.0, 0.3],
}


def _apart(a: np.ndarray, b: np.ndarray) -> float:
    """Largest joint difference of ``a`` and ``b`` modulo a turn [rad] (written here)."""
    gap = np.abs(np.asarray(a) - np.asarray(b)) % (2 * math.pi)
    return float(np.minimum(gap, 2 * math.pi - gap).max())


def _pose(name: str) -> tuple[object, PoseTarget, np.ndarray]:
    robot = load_robot(name)
    q = np.array(SINGULAR[name])
    pose = Configuration(robot, q).transform_frame_to_world("tool")
    return robot, PoseTarget(pose.translation, pose.rotation), q


@pytest.mark.parametrize("name", sorted(SINGULAR))
def test_a_wrist_singularity_gives_each_joint_vector_once(name):
    """Every answer on target, pairwise apart by more than the tolerance; the count says so."""
    robot, target, _ = _pose(name)
    result = solve_ik(robot, target)
    answers = [*result.solutions, *result.rejected]
    for i, a in enumerate(answers):
        for b in answers[:i]:
            assert _apart(a.q, b.q) > SAME_BRANCH, f"{name=}: {a.branch!r} repeats {b.branch!r}"
    for s in answers:  # each on target by forward kinematics (the wrist joints' sum is free)
        pose = Configuration(robot, s.q).transform_frame_to_world("tool")
        assert np.linalg.norm(pose.translation - target.position) < 1e-9, f"{name=}"
        assert np.abs(pose.rotation - target.rotation).max() < 1e-9, f"{name=}"
    assert "repeated branch(es) merged" in result.message, f"{name=} {result.message}"
    count = int(result.message.split()[0])
    assert count == len(result.solutions), f"{name=} {result.message}"


def test_distinct_solutions_keeps_the_first_label_and_wraps_revolute_joints_only():
    """A repeat a turn away (revolute) is merged into the first; a prismatic 2 pi m is not."""

    def solution(q: list[float], branch: str) -> IKSolution:
        return IKSolution(np.array(q), branch, True, 0.0, 0.0)

    first = solution([0.1, 0.2, 0.3], "wrist up")
    other = solution([1.0, 0.2, 0.3], "elbow down")
    repeat = solution([0.1 + 2 * math.pi, 0.2 + 1e-8, 0.3], "wrist down")
    kept = distinct_solutions((first, other, repeat))
    assert [s.branch for s in kept] == ["wrist up", "elbow down"]
    assert distinct_solutions((first, other)) == (first, other)
    slide = solution([0.1, 0.2, 0.3 + 2 * math.pi], "far")
    assert len(distinct_solutions((first, slide), revolute=(True, True, False))) == 2
    assert len(distinct_solutions((first, slide))) == 1


def test_kin_ik_all_at_a_wrist_singularity_lists_each_vector_once(capsys):
    """Text rows, --json solutions and the header's count agree, and no two rows are one vector."""
    robot, target, _ = _pose("ur5")
    xyz = [f"{v:.12g}" for v in target.position]
    rotation = Configuration(robot, SINGULAR["ur5"]).transform_frame_to_world("tool").rotation
    quat = _quaternion(rotation)
    argv = ["--robot", "ur5", "--target", *xyz, "--quat", *quat, "--all"]
    assert call(ik_command.main, argv) == 0
    out = capsys.readouterr().out.splitlines()
    rows = out[3:]
    assert call(ik_command.main, [*argv, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    qs = [s["q"] for s in record["solutions"]]
    assert (
        len(rows)
        == len(qs)
        == record["counts"]["solutions"]
        == int(out[0].split(": ")[2].split()[0])
    )
    for i, a in enumerate(qs):
        assert all(_apart(a, b) > SAME_BRANCH for b in qs[:i])


def _quaternion(rotation: np.ndarray) -> list[str]:
    """(w, x, y, z) of a rotation matrix, written here (Shepperd: the largest of w, x, y, z first)."""
    r = rotation
    candidates = [np.trace(r), r[0, 0], r[1, 1], r[2, 2]]
    k = int(np.argmax(candidates))
    if k == 0:
        w = math.sqrt(1.0 + np.trace(r)) / 2.0
        q = [
            w,
            (r[2, 1] - r[1, 2]) / (4 * w),
            (r[0, 2] - r[2, 0]) / (4 * w),
            (r[1, 0] - r[0, 1]) / (4 * w),
        ]
    else:
        i, j, m = (k - 1, k % 3, (k + 1) % 3)
        v = [0.0, 0.0, 0.0]
        v[i] = math.sqrt(max(0.0, 1.0 + r[i, i] - r[j, j] - r[m, m])) / 2.0
        v[j] = (r[j, i] + r[i, j]) / (4 * v[i])
        v[m] = (r[m, i] + r[i, m]) / (4 * v[i])
        q = [(r[m, j] - r[j, m]) / (4 * v[i]), *v]
    return [f"{value:.15g}" for value in q]


def _header_counts(line: str) -> tuple[int, int]:
    """(solutions, rejected) of a text header: 'shown: a of S solution(s), b of R rejected'."""
    found = re.search(r"shown: \d+ of (\d+) solution\(s\), \d+ of (\d+) rejected", line)
    assert found is not None, line
    return int(found.group(1)), int(found.group(2))


def test_the_header_counts_what_it_hides(capsys):
    """Without --all: one row, the header says 1 of 8 shown; --json counts the same 8."""
    assert call(ik_command.main, README_TARGET) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 4, out  # header, timing, column names, one row
    assert _header_counts(out[0]) == (8, 0), out[0]
    assert "shown: 1 of 8" in out[0]
    assert call(ik_command.main, [*README_TARGET, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["counts"] == {"solutions": 8, "rejected": 0, "rejected_listed": 0}
    assert len(record["solutions"]) == 8


def test_the_readme_cell_split_is_the_reference_s():
    """Of the README target's 8 branches the coal reference finds README_FREE free in the cell."""
    from support.collision_reference import CollisionReference

    from kin.collision import load_collision_model

    robot = load_robot("ur5")
    rotation = np.diag([1.0, -1.0, -1.0])  # rpy (180, 0, 0) deg
    branches = solve_ik(robot, PoseTarget([0.4, 0.1, 0.3], rotation))  # every branch
    assert len(branches.solutions) == README_FREE + README_REJECTED
    reference = CollisionReference(robot.urdf, None, robot.joint_names, None, Path(CELL))
    pairs = [tuple(p) for p in load_collision_model(robot, scene=CELL).pairs]
    free = 0
    for s in branches.solutions:
        distances = reference.signed_distances(s.q, pairs)
        nearest = min(d for d, _ in distances.values())
        assert abs(nearest) > 1e-3, s.branch  # no verdict left to the contact tolerance
        free += nearest > 0.0
    assert free == README_FREE


def test_scene_counts_do_not_depend_on_all(capsys):
    """The README's cell: 2 free and 6 colliding, with --all or not, in text and --json."""
    scene = [*README_TARGET, "--scene", CELL]
    free, rejected = README_FREE, README_REJECTED
    words = (f"{free} collision-free solution(s)", f"{rejected} colliding rejected")
    assert call(ik_command.main, scene) == 0
    header = capsys.readouterr().out.splitlines()[0]
    assert all(w in header for w in words), header
    assert _header_counts(header) == (free, rejected)
    assert call(ik_command.main, [*scene, "--all"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert all(w in out[0] for w in words), out[0]
    assert "shown:" not in out[0] and len(out) == 3 + free + rejected
    for extra in ([], ["--all"]):
        assert call(ik_command.main, [*scene, *extra, "--json"]) == 0
        record = json.loads(capsys.readouterr().out)
        assert record["counts"]["solutions"] == len(record["solutions"]) == free, extra
        assert record["counts"]["rejected"] == len(record["rejected"]) == rejected, extra


def test_stdin_all_lists_the_free_and_the_rejected_as_all_does():
    """--stdin --scene: a plain line counts 2 and 6 (rejected not listed); "all": true lists both."""
    free, rejected = README_FREE, README_REJECTED
    lines = README_LINE + "\n" + README_LINE[:-1] + ', "all": true}\n'
    done = run(["ik", "--robot", "ur5", "--deg", "--stdin", "--scene", CELL], stdin=lines)
    assert done.returncode == 0, done.stderr
    plain, every = (json.loads(line) for line in done.stdout.splitlines())
    assert plain["counts"] == {"solutions": free, "rejected": rejected, "rejected_listed": 0}
    assert len(plain["solutions"]) == free and plain["rejected"] == []
    assert every["counts"] == {"solutions": free, "rejected": rejected, "rejected_listed": rejected}
    assert len(every["solutions"]) == free and len(every["rejected"]) == rejected
    assert all(r["reason"].startswith(("scene:", "self:")) for r in every["rejected"])


def test_the_twins_rule_of_one_branch_is_the_library_s():
    """The 6R twins' C check of repeated branches uses kin.ik.result.SAME_BRANCH."""
    from pathlib import Path

    from kin import _native

    # The wheel ships it.
    header = Path(_native.__file__).resolve().parent / "ik/analytic/six_r/_six_r_module.h"
    match = re.search(r"#define SAME_BRANCH (\S+)", header.read_text(encoding="utf-8"))
    assert match is not None and float(match[1]) == SAME_BRANCH


def test_the_general_6r_rule_of_one_branch_is_the_library_s():
    """The general 6R solve (NumPy and C) merges branches by kin.ik.result.SAME_BRANCH."""
    from pathlib import Path

    from kin import _native
    from kin.ik.analytic.six_r._general_6r_chain import SAME_TOL

    source = Path(_native.__file__).resolve().parent / "ik/analytic/six_r/_general6r.c"
    match = re.search(r"#define SAME_TOL (\S+)", source.read_text(encoding="utf-8"))
    assert match is not None and float(match[1]) == SAME_TOL == SAME_BRANCH
