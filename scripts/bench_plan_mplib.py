"""mplib's planner as a worker of scripts/bench_plan.py: one JSON line in, one JSON line out.

Runs in its own virtual environment (mplib pins numpy < 2; bench_plan.py makes it under
``.bench/mplib-venv`` on demand) and imports neither kin nor the project. Each input line is one
problem::

    {"id", "urdf", "srdf", "move_group", "joints", "held", "boxes", "start", "goal",
     "time_limit", "seed"}

(``urdf`` with absolute mesh paths; ``joints`` the names of ``start`` and ``goal`` [rad];
``held`` the other joints' values [rad or m]; ``boxes`` as in bench_plan_problems.json, in the
base frame). The answer line: ``{"id", "status", "plan_time" [s], "path"}``, ``path`` the joint
vectors of mplib's RRTConnect after its simplification, before its time parametrization (the
geometric path its edges were checked on), or ``{"id", "error"}``. mplib's own defaults:
RRT range 0.1, meshes as convex hulls (``use_convex``, the shapes kin's checker and the
reference judge).
"""

from __future__ import annotations

import json
import math
import os
import signal
import sys
import time

import numpy as np


def _objects(boxes: list[dict]) -> list:
    from mplib import Pose
    from mplib.collision_detection import fcl

    objects = []
    for box in boxes:
        yaw = box["rpy"][2]
        quat = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]  # w, x, y, z
        shape = fcl.CollisionObject(fcl.Box(np.array(box["size"], dtype=float)), Pose())
        pose = Pose(np.array(box["xyz"], dtype=float), np.array(quat))
        objects.append(fcl.FCLObject(box["name"], pose, [shape], [Pose()]))
    return objects


def solve(problem: dict) -> dict:
    """One problem: mplib's RRTConnect from start to goal, timed around the search alone."""
    import mplib

    planner = mplib.Planner(
        problem["urdf"],
        problem["move_group"],
        srdf=problem["srdf"],
        use_convex=True,
        objects=_objects(problem["boxes"]),
    )
    names = list(planner.user_joint_names)
    full = np.zeros(len(names))
    for name, value in problem["held"].items():
        if name in names:
            full[names.index(name)] = value
    index = [names.index(n) for n in problem["joints"]]
    start, goal = full.copy(), full.copy()
    start[index] = problem["start"]
    goal[index] = problem["goal"]
    moving = planner.move_group_joint_indices
    if sorted(moving) != sorted(index):
        return {"id": problem["id"], "error": f"move group joints {moving} are not {index}"}
    mplib.set_global_seed(int(problem["seed"]))
    planner.robot.set_qpos(start, True)
    began = time.perf_counter()
    status, path = planner.planner.plan(
        start[moving],
        [goal[moving]],
        time=float(problem["time_limit"]),
        range=0.1,
        simplify=True,
    )
    elapsed = time.perf_counter() - began
    ok = status == "Exact solution"
    order = [list(moving).index(i) for i in index]  # the path's columns as problem["joints"]
    rows = np.asarray(path)[:, order].tolist() if ok else []
    return {
        "id": problem["id"],
        "status": "ok" if ok else status,
        "plan_time": elapsed,
        "path": rows,
    }


def main() -> int:
    """Answer problems from stdin until it closes (Ctrl-C is the parent's to handle)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    answers = os.fdopen(os.dup(1), "w")  # mplib and OMPL print to stdout: that goes to stderr
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    for line in sys.stdin:
        problem = json.loads(line)
        try:
            answer = solve(problem)
        except Exception as err:  # noqa: BLE001 - reported to the parent, one line
            answer = {"id": problem.get("id"), "error": f"{type(err).__name__}: {err}"}
        answers.write(json.dumps(answer) + "\n")
        answers.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
