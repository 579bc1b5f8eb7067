"""The planners scripts/bench_plan.py runs beside kin.plan.plan (issue 44, item 4).

* :func:`plain_ompl`: what a user writes with the ``ompl`` wheel and a Pinocchio + coal check:
  ``SimpleSetup`` on a ``RealVectorStateSpace`` of the joint limits, RRTConnect, a validity
  callback (:meth:`plan_reference.Reference.in_collision`, its own instance), OMPL's discrete
  motion validator at its default resolution (1 % of the space's extent) or at a given joint
  step [rad], then ``simplifySolution``.
* :class:`MplibWorker`: mplib (pip ``mplib``, which pins numpy < 2) in a virtual environment of
  its own, made on demand under ``.bench/mplib-venv``, run as a subprocess
  (scripts/bench_plan_mplib.py) that reads problems as JSON lines and returns paths. Its URDF
  copies name their meshes relative to ``.bench/mplib-meshes``, where each collision mesh's
  convex hull (scipy's qhull) is written beside it as ``NAME.convex.stl``, so that mplib's
  ``use_convex`` checks the same shapes as kin and the reference.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from bench_ik_urdf import erd

ROOT = Path(__file__).resolve().parents[1]
#: Where the mplib venv and mesh copies live (git-ignored).
BENCH = ROOT / ".bench"


def plain_ompl(reference, lower, upper, start, goal, time_limit: float, step: float | None, seed):
    """RRTConnect with a plain validity callback; (status, plan time [s], path or None).

    ``step``: the motion validator's joint-space step [rad] (None: OMPL's default resolution).
    """
    from ompl import base as ob
    from ompl import geometric as og
    from ompl import util as ou

    ou.setLogLevel(ou.LogLevel.LOG_NONE)
    n = len(start)
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for i in range(n):
        bounds.setLow(i, float(lower[i]))
        bounds.setHigh(i, float(upper[i]))
    space.setBounds(bounds)
    si = ob.SpaceInformation(space)
    si.setStateValidityChecker(
        lambda s: not reference.in_collision(np.array([s[i] for i in range(n)]))
    )
    if step is not None:
        si.setStateValidityCheckingResolution(step / space.getMaximumExtent())
    si.setup()
    ou.RNG.setSeed(seed + 1)
    setup = og.SimpleSetup(si)
    states = []
    for q in (start, goal):
        state = space.allocState()
        for i, value in enumerate(q):
            state[i] = float(value)
        states.append(state)
    setup.setStartAndGoalStates(states[0], states[1])
    setup.setPlanner(og.RRTConnect(si))
    began = time.perf_counter()
    setup.solve(time_limit)
    if not setup.haveExactSolutionPath():
        return "not_found", time.perf_counter() - began, None
    setup.simplifySolution()
    elapsed = time.perf_counter() - began
    found = setup.getSolutionPath()
    path = np.array(
        [[found.getState(k)[i] for i in range(n)] for k in range(found.getStateCount())]
    )
    return "ok", elapsed, path


def _hull_stl(mesh: Path, out: Path) -> None:
    """Write the convex hull of ``mesh`` (coal's loader, scipy's qhull) as an ASCII STL."""
    import coal
    from scipy.spatial import ConvexHull

    model = coal.MeshLoader().load(str(mesh), np.ones(3))
    points = np.array([model.vertices(i) for i in range(model.num_vertices)])
    hull = ConvexHull(points)
    centre = points[hull.vertices].mean(axis=0)
    lines = ["solid hull"]
    for tri in hull.simplices:
        a, b, c = points[tri]
        normal = np.cross(b - a, c - a)
        if normal @ (a - centre) < 0.0:  # outward
            b, c, normal = c, b, -normal
        normal /= max(float(np.linalg.norm(normal)), 1e-12)
        lines.append(f"facet normal {normal[0]:.9g} {normal[1]:.9g} {normal[2]:.9g}\nouter loop")
        lines += [f"vertex {p[0]:.9g} {p[1]:.9g} {p[2]:.9g}" for p in (a, b, c)]
        lines.append("endloop\nendfacet")
    lines.append("endsolid hull\n")
    out.write_text("\n".join(lines), encoding="ascii")


def mplib_urdf(urdf: Path, name: str) -> Path:
    """A copy of ``urdf`` for mplib: collision meshes copied with their hulls, paths relative."""
    folder = BENCH / "mplib-meshes" / name
    folder.mkdir(parents=True, exist_ok=True)
    text = urdf.read_text(encoding="utf-8")

    def local(match: re.Match) -> str:
        package, _, rest = match.group(1).partition("/")
        source = next(
            (f / rest for f in urdf.resolve().parents if f.name == package), urdf.parent / rest
        )
        copy = folder / rest.replace("/", "_")
        if not copy.exists():
            shutil.copyfile(source, copy)
            _hull_stl(source, copy.with_name(copy.name + ".convex.stl"))
        return f'filename="{copy.name}"'

    target = folder / urdf.name
    target.write_text(re.sub(r'filename="package://([^"]+)"', local, text), encoding="utf-8")
    return target


def mplib_srdf(urdf: Path, srdf: Path, model, name: str) -> Path:
    """A copy of ``srdf`` that also allows every link pair kin's ``model`` does not check.

    So that mplib checks the same self pairs as kin and the reference (e.g. UR5's ``wrist_3_link``
    and ``ee_link``, one body on a fixed joint, which the maker's SRDF leaves checked: mplib then
    calls every UR5 state in collision).
    """
    import xml.etree.ElementTree as ET

    links = sorted(
        {link.get("name", "") for link in ET.parse(urdf).iter("link") if link.find("collision")}
    )
    checked = {frozenset(p) for p in model.pairs}
    extra = [
        f'  <disable_collisions link1="{a}" link2="{b}" reason="kin"/>'
        for i, a in enumerate(links)
        for b in links[i + 1 :]
        if frozenset((a, b)) not in checked
    ]
    text = srdf.read_text(encoding="utf-8")
    end = text.rindex("</robot>")
    target = BENCH / "mplib-meshes" / name / srdf.name
    target.write_text(text[:end] + "\n".join(extra) + "\n" + text[end:], encoding="utf-8")
    return target


class MplibWorker:
    """mplib in its own venv and process; :meth:`solve` sends one problem and waits for its path.

    ``available`` is False (``reason`` says why) when the venv cannot be made or mplib not
    installed.
    """

    def __init__(self):
        self.venv = BENCH / "mplib-venv"
        self.process: subprocess.Popen | None = None
        self.reason = ""
        python = self.venv / "bin" / "python"
        if not python.exists() or self._missing(python):
            print("bench_plan: making .bench/mplib-venv (pip install mplib)", file=sys.stderr)
            made = subprocess.run(
                f"{sys.executable} -m venv {self.venv} && {python} -m pip install -q mplib",
                shell=True,
                capture_output=True,
                text=True,
            )
            if made.returncode != 0 or self._missing(python):
                self.reason = (made.stderr.strip().splitlines() or ["pip failed"])[-1][:100]
        self.available = not self.reason
        if self.available:
            self.process = subprocess.Popen(
                [str(python), str(Path(__file__).with_name("bench_plan_mplib.py"))],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=(BENCH / "mplib-worker.log").open("w"),
                text=True,
                env={**os.environ, "OPENBLAS_NUM_THREADS": "1"},
            )

    @staticmethod
    def _missing(python: Path) -> bool:
        return (
            subprocess.run([str(python), "-c", "import mplib"], capture_output=True).returncode != 0
        )

    def solve(self, arm, robot, model, problem, time_limit: float, seed: int) -> dict:
        """The mplib answer: ``status``, ``plan_time`` [s], ``path`` (or ``error``)."""
        assert self.process is not None and self.process.stdin and self.process.stdout
        request = {
            "id": problem.id,
            "urdf": str(mplib_urdf(erd(arm.robot), arm.name)),
            "srdf": str(mplib_srdf(erd(arm.robot), erd(arm.srdf), model, arm.name)),
            "move_group": arm.tip,
            "joints": list(robot.joint_names),
            "held": {h.name: h.value for h in model.held.joints},
            "boxes": [b.as_json() for b in problem.boxes],
            "start": problem.start.tolist(),
            "goal": problem.goal.tolist(),
            "time_limit": time_limit,
            "seed": seed,
        }
        self.process.stdin.write(json.dumps(request) + "\n")
        self.process.stdin.flush()
        line = self.process.stdout.readline()
        if not line:
            return {"error": f"the mplib worker ended (exit {self.process.wait()})"}
        return json.loads(line)

    def close(self) -> None:
        """End the worker this object started."""
        if self.process is not None:
            self.process.stdin.close()  # type: ignore[union-attr]
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
            self.process = None
