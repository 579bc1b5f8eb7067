"""The maker's Panda with a box scene that blocks the plain solver's answer: the case of the
distance-bounded IK tests, checked by the direct coal reference of the maker's URDF.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from kin.collision import CollisionChecker, load_collision_model
from kin.ik import PoseTarget, get_solver
from support.collision_reference import CollisionReference
from support.urdf_reference import erd

URDF, TIP, SRDF = (
    "panda_description/urdf/panda.urdf",
    "panda_link8",
    "panda_description/srdf/panda.srdf",
)


def _blocked_case(panda, tmp_path: Path):
    """(target, free seed, plain answer, checker, reference, pairs): a box through the forearm.

    The plain solver's answer from a free seed puts panda_link5 through a 5 cm box; a free
    answer exists (the reference finds one on the all-branches grid).
    """
    robot = panda[0]
    plain = get_solver(robot)
    probe = _reference(panda, None)
    srdf = erd(SRDF)
    rng = np.random.default_rng(4)
    for k in range(60):
        seed = rng.uniform(robot.lower, robot.upper)
        q = np.clip(seed + rng.normal(0.0, 0.4, robot.nq), robot.lower, robot.upper)
        T = _tool(probe, q)
        target = PoseTarget(T.translation, T.rotation)
        result = plain.solve(target, seed)
        if not result.solutions:
            continue
        answer = result.solutions[0].q
        center = probe.placements(answer)["panda_link5"][0][1].translation
        scene = _box_scene(tmp_path / f"box{k}.toml", center, 0.05)
        model = load_collision_model(robot, srdf=srdf, scene=scene)
        reference = _reference(panda, scene)
        pairs = [tuple(p) for p in model.pairs]
        if (
            _clearance(reference, pairs, seed) <= 0.0
            or _clearance(reference, pairs, answer) > -0.005
        ):
            continue
        grid = plain.solve(target, seed, all_branches=True).solutions
        if any(_clearance(reference, pairs, s.q) > 0.0 for s in grid):
            return target, seed, answer, CollisionChecker(model), reference, pairs
    pytest.fail("no target whose plain answer the box blocks while a free one exists")


def _box_scene(path: Path, center, size: float) -> Path:
    xyz = ", ".join(repr(float(v)) for v in center)
    path.write_text(f'[[box]]\nname = "box"\nsize = [{size}, {size}, {size}]\nxyz = [{xyz}]\n')
    return path


def _reference(panda, scene: Path | None) -> CollisionReference:
    robot, text, path, base = panda
    return CollisionReference(text, path, robot.joint_names, base, scene)


def _clearance(reference: CollisionReference, pairs, q) -> float:
    """The smallest signed distance of the checked pairs at ``q`` by the reference [m]."""
    distances = reference.signed_distances(np.asarray(q, dtype=float), pairs)
    return min(d for d, _ in distances.values())


def _tool(reference: CollisionReference, q) -> pin.SE3:
    """``T_world_link8`` by Pinocchio's FK of the maker's URDF at ``q``."""
    reference.placements(np.asarray(q, dtype=float))  # runs the FK on reference.data
    model, data = reference.model, reference.data
    world = data.oMf[model.getFrameId(reference.base, pin.FrameType.BODY)].inverse()
    return world * data.oMf[model.getFrameId(TIP, pin.FrameType.BODY)]
