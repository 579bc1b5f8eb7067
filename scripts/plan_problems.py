"""Planning problems of scripts/bench_plan.py and scripts/certify_plans.py (issue 44, items 3-5).

* :data:`ARMS` (:mod:`plan_parts`, with :class:`Arm` and :class:`Box`): Panda and UR5 as their makers ship them (example-robot-data's URDF and SRDF,
  meshes as their convex hulls, as kin's collision model takes them) and UR10's DH table.
* :func:`scene_boxes`: four kinds of cell made of boxes (``table``, ``shelves``, ``box``, ``cage``)
  in front of the arm, scaled to its reach, each moved and turned a little by a seeded generator;
  the arm stands on a floor 2 cm below its base.
* :class:`Cell`: an arm in a scene, with kin's collision checker and the independent
  :class:`plan_reference.Reference` built from the same boxes; :func:`draw_problem` draws a free
  start and goal whose straight joint line is blocked.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from bench_ik_urdf import erd
from plan_parts import ARMS as ARMS  # the scripts' arms, read from here too
from plan_parts import Arm, Box
from plan_reference import Reference

#: The kinds of scene, in table order.
SCENES = ("table", "shelves", "box", "cage")


def load_arm(arm: Arm):
    """The kin robot of ``arm`` (``kin.load_robot``: the URDF's chain, or the shipped table)."""
    from kin import load_robot

    if arm.tip is None:
        return load_robot(arm.robot)
    return load_robot(erd(arm.robot), None, arm.tip)


def collision_model(arm: Arm, robot, scene: Path | None):
    """The collision model (kin) of ``arm`` in the scene TOML ``scene`` (the SRDF when it has one)."""
    from kin.collision import load_collision_model

    srdf = erd(arm.srdf) if arm.srdf else None
    return load_collision_model(robot, srdf=srdf, scene=scene)


def _layout(kind: str) -> list[tuple[str, tuple[float, float, float], tuple[float, float, float]]]:
    """(name, size, centre) of a scene kind's boxes in units of the reach, before the turn."""
    t = 0.02  # board thickness [reach]
    if kind == "table":
        return [("top", (0.5, 1.2, 0.04), (0.6, 0.0, 0.15))]
    if kind == "shelves":
        x, d, w, h = 0.62, 0.35, 0.9, 1.2
        boxes = [(f"board{i}", (d, w, t), (x, 0.0, z)) for i, z in enumerate((0.05, 0.45, 0.85))]
        boxes += [("top", (d, w, t), (x, 0.0, h)), ("back", (t, w, h), (x + d / 2, 0.0, h / 2))]
        boxes += [(f"side{i}", (d, t, h), (x, s * w / 2, h / 2)) for i, s in enumerate((-1, 1))]
        return boxes
    if kind == "box":
        x, d, w, h = 0.55, 0.4, 0.5, 0.3
        boxes = [("bottom", (d, w, t), (x, 0.0, 0.0))]
        boxes += [
            (f"wall{i}", (t, w, h), (x + s * d / 2, 0.0, h / 2)) for i, s in enumerate((-1, 1))
        ]
        boxes += [(f"end{i}", (d, t, h), (x, s * w / 2, h / 2)) for i, s in enumerate((-1, 1))]
        return boxes
    if kind == "cage":
        x, d, w, h, b = 0.55, 0.45, 0.6, 0.6, 0.04
        boxes = [("base", (d, w, t), (x, 0.0, 0.0)), ("roof", (d, w, t), (x, 0.0, h))]
        corners = [(x + sx * d / 2, sy * w / 2) for sx in (-1, 1) for sy in (-1, 1)]
        boxes += [(f"post{i}", (b, b, h), (cx, cy, h / 2)) for i, (cx, cy) in enumerate(corners)]
        boxes += [(f"bar{i}", (b, w, b), (x - d / 2, 0.0, z)) for i, z in enumerate((0.2, 0.4))]
        boxes += [(f"rail{i}", (d, b, b), (x, s * w / 2, 0.3)) for i, s in enumerate((-1, 1))]
        return boxes
    raise ValueError(f"unknown scene kind {kind!r}; choose one of: {', '.join(SCENES)}")


def scene_boxes(kind: str, reach: float, rng: np.random.Generator) -> list[Box]:
    """The boxes of a ``kind`` scene for an arm of ``reach`` [m], moved by ``rng``.

    The layout (:func:`_layout`) is scaled by the reach, turned about the base's z axis by up to
    +-0.5 rad and shifted by up to 5 % of the reach; a 4 cm floor lies 2 cm below the base.
    """
    turn = float(rng.uniform(-0.5, 0.5))
    shift = rng.uniform(-0.05, 0.05, 2) * reach
    c, s = math.cos(turn), math.sin(turn)
    floor = 2.5 * reach
    boxes = [Box("floor", (floor, floor, 0.04), (0.0, 0.0, -0.04))]
    for name, size, (x, y, z) in _layout(kind):
        x, y, z = x * reach, y * reach, z * reach
        centre = (c * x - s * y + shift[0], s * x + c * y + shift[1], z)
        boxes.append(Box(f"{kind}_{name}", tuple(v * reach for v in size), centre, turn))  # type: ignore[arg-type]
    return [Box(b.name, _round(b.size), _round(b.xyz), round(b.yaw, 6)) for b in boxes]


def _round(values) -> tuple[float, float, float]:
    return tuple(round(float(v), 6) for v in values)  # type: ignore[return-value]


def boxes_from_json(items: list[dict]) -> list[Box]:
    """The boxes of a problem file (:meth:`Box.as_json`)."""
    return [Box(i["name"], tuple(i["size"]), tuple(i["xyz"]), i["rpy"][2]) for i in items]


def scene_toml(boxes: list[Box]) -> str:
    """The boxes as a kin scene TOML (``[[box]]`` with ``size``, ``xyz`` [m], ``rpy`` [rad])."""
    rows = []
    for b in boxes:
        rows.append(
            f"[[box]]\nname = '{b.name}'\nsize = {list(b.size)}\nxyz = {list(b.xyz)}\n"
            f"rpy = [0.0, 0.0, {b.yaw}]\n"
        )
    return "\n".join(rows)


def absolute_meshes(urdf: Path) -> str:
    """The URDF's text with each ``package://`` mesh named by its absolute path."""
    text = urdf.read_text(encoding="utf-8")

    def absolute(match: re.Match) -> str:
        package, _, rest = match.group(1).partition("/")
        for folder in urdf.resolve().parents:
            if folder.name == package:
                return f'filename="{folder / rest}"'
        return match.group(0)

    return re.sub(r'filename="package://([^"]+)"', absolute, text)


@dataclass(frozen=True)
class Problem:
    """A planning problem: an arm, a scene and free start and goal joint vectors [rad]."""

    id: str
    arm: str
    scene: str
    boxes: list[Box]
    start: np.ndarray
    goal: np.ndarray

    def as_json(self) -> dict:
        """The problem as a JSON object."""
        return {
            "id": self.id,
            "arm": self.arm,
            "scene": self.scene,
            "boxes": [b.as_json() for b in self.boxes],
            "start": [round(float(v), 9) for v in self.start],
            "goal": [round(float(v), 9) for v in self.goal],
        }

    @classmethod
    def from_json(cls, item: dict) -> Problem:
        """A problem of a problem file (:meth:`as_json`)."""
        return cls(
            item["id"],
            item["arm"],
            item["scene"],
            boxes_from_json(item["boxes"]),
            np.array(item["start"], dtype=float),
            np.array(item["goal"], dtype=float),
        )


class Cell:
    """An arm in a scene: kin's checker and the reference, built from the same boxes.

    Args:
        arm: The arm.
        robot: Its kin robot (:func:`load_arm`).
        boxes: The scene.
        folder: Where the scene's TOML is written (kin reads the scene from a file).
    """

    def __init__(self, arm: Arm, robot, boxes: list[Box], folder: Path):
        from kin.collision import CollisionChecker

        scene = folder / "scene.toml"
        scene.write_text(scene_toml(boxes), encoding="utf-8")
        self.arm, self.robot, self.boxes = arm, robot, boxes
        self.model = collision_model(arm, robot, scene)
        self.checker = CollisionChecker(self.model)
        self.reference = Reference(arm, robot, self.model, boxes)

    def free(self, q: np.ndarray) -> bool:
        """Free by both kin's checker and the reference."""
        return not (self.checker.in_collision(q) or self.reference.in_collision(q))


def draw_problem(
    arm: Arm,
    robot,
    kind: str,
    rng: np.random.Generator,
    folder: Path,
    name: str,
    blocked: bool,
    cell: Cell | None = None,
) -> tuple[Problem, Cell] | None:
    """A problem in a new ``kind`` scene (or in ``cell``): start and goal drawn until both are free.

    ``blocked``: the straight joint line between them must hit the scene or the arm itself (by
    the reference at :data:`RESAMPLE`), so that a planner has work to do. None after 3,000 draws.
    """
    if cell is None:
        cell = Cell(arm, robot, scene_boxes(kind, arm.reach, rng), folder)
    lower = np.maximum(robot.lower, -arm.span)
    upper = np.minimum(robot.upper, arm.span)
    free: list[np.ndarray] = []
    for _ in range(3000):
        q = rng.uniform(lower, upper)
        if not cell.free(q):
            continue
        if free:
            start = free[-1]
            if not blocked or not cell.reference.judge(np.array([start, q]), stop=True).free:
                return Problem(name, arm.name, kind, cell.boxes, start, q), cell
        free.append(q)
    return None
