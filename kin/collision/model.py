"""A robot's collision model: the robot's shapes on the kin model's joints, a scene, allowed pairs.

Shapes (:mod:`.arm_shapes`): a robot loaded from a URDF keeps the ``<collision>`` elements of
every link of its URDF, the chain's and those attached to it off the chain (fingers, flange,
camera), the joints off the chain held at stated values (:mod:`.held_joints`); each shape rides
on the kin model's joint that carries its link. A DH table robot has the link cylinders the URDF
writer emits (per-row ``radius``). Scene objects hang on the world. Pairs checked: every two
links, and every link with every scene object, but the allowed ones
(:attr:`CollisionModel.disabled`): adjacent links (joined by a joint, links without shapes
skipped, as MoveIt's setup assistant counts them), links carried by the same joint, an SRDF's
pairs, a PlanningScene's allowed collision matrix (:mod:`.planning_scene`), and on a DH table
robot the pairs its rows allow (``[[joints.allow_contact]]``, :mod:`dh2urdf.link_volumes`) and the
link pairs in contact at every sampled configuration without padding
(:mod:`.always_pairs`): a pair in contact only through the padding stays checked.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import pinocchio as pin

from ..exceptions import CollisionModelError
from ..robot_model import RobotModel
from .arm_shapes import ArmShape, arm_body
from .attached import AttachedObject, check_names
from .bounds import MAX_COORDINATE
from .held_joints import HeldJoints
from .requests import CONTACT_TOLERANCE
from .urdf_shapes import Shape

__all__ = ["CollisionModel", "load_collision_model"]


@dataclass(frozen=True, eq=False)
class CollisionModel:
    """The shapes of an arm and its scene and the pairs of them that are checked.

    Attributes:
        robot: The robot (its ``model`` drives the shapes).
        geometry_model: Pinocchio's geometry model, one object per shape, its collision pairs
            those of :attr:`pairs`.
        links: Names of the arm's links that have shapes, base to tip.
        scene_objects: Names of the scene objects.
        pairs: The ``(a, b)`` checked: two links (base side first), or a link and an object.
        disabled: The pairs not checked, ``(a, b) -> reason`` (``"adjacent"``, ``"rigid"``,
            ``"srdf: <reason>"``, ``"table: <reason>"``, ``"acm"``, ``"always"``; an attached object's ``"touch"``).
        owners: Per geometry object, the link, scene object or attached object it belongs to.
        pair_owners: Per collision pair of :attr:`geometry_model`, its ``(a, b)``.
        padding: Distance added around every shape [m]: a pair is in collision closer than it
            plus :data:`~kin.collision.requests.CONTACT_TOLERANCE`.
        shape_note: One line: which geometry the queries use and how far it is from the meshes.
        held: The joints off the chain and the values they are held at; ``held.note`` says them
            in one line ("" when there is none).
        attached: The objects attached to links (a pair ``(link, object)``, ``(object,
            scene object)`` or two objects); :meth:`attach` and :meth:`detach` give new models.
        inputs: The files and holds it was loaded from (for :meth:`attach`, :meth:`detach`).
    """

    robot: RobotModel
    geometry_model: pin.GeometryModel
    links: tuple[str, ...]
    scene_objects: tuple[str, ...]
    pairs: tuple[tuple[str, str], ...]
    disabled: dict[tuple[str, str], str]
    owners: tuple[str, ...]
    pair_owners: tuple[tuple[str, str], ...]
    padding: float
    shape_note: str
    held: HeldJoints = HeldJoints()
    attached: tuple[AttachedObject, ...] = ()
    inputs: _Inputs | None = None

    def attach(self, thing: AttachedObject) -> CollisionModel:
        """A new model with ``thing`` attached too (:func:`kin.collision.attached_object`).

        Raises:
            CollisionModelError: Its name is taken, or its link or a touch link is not the robot's.
        """
        return self._with((*self.attached, thing))

    def detach(self, name: str) -> CollisionModel:
        """A new model without the attached object ``name``.

        Raises:
            CollisionModelError: No object of that name is attached.
        """
        kept = tuple(thing for thing in self.attached if thing.name != name)
        if len(kept) == len(self.attached):
            shown = ", ".join(thing.name for thing in self.attached) or "none"
            raise CollisionModelError("", f"detach: no attached object {name!r}; attached: {shown}")
        return self._with(kept)

    def _with(self, attached: tuple[AttachedObject, ...]) -> CollisionModel:
        inputs = self.inputs or _Inputs(None, None, {})
        return load_collision_model(
            self.robot,
            srdf=inputs.srdf,
            scene=inputs.scene,
            padding=self.padding,
            hold=inputs.hold,
            attached=attached,
        )


@dataclass(frozen=True)
class _Inputs:
    """What a model was loaded from, to load it again with other attached objects."""

    srdf: str | Path | None
    scene: str | Path | None
    hold: Mapping[str, float]


def load_collision_model(
    robot: RobotModel,
    *,
    srdf: str | Path | None = None,
    scene: str | Path | None = None,
    padding: float = 0.0,
    hold: Mapping[str, float] | None = None,
    attached: Iterable[AttachedObject] | None = None,
) -> CollisionModel:
    """The collision model of ``robot`` (see the module docstring for what it holds).

    Args:
        robot: A robot from :func:`kin.load_robot`.
        srdf: A MoveIt SRDF whose ``disable_collisions`` pairs are not checked.
        scene: A scene TOML, a MoveIt PlanningScene (JSON, YAML) or a URDF of the cell
            (:mod:`kin.collision.scene`).
        padding: Margin around every shape [m], 0 to :data:`~kin.collision.bounds.MAX_COORDINATE`.
        hold: A URDF joint off the chain (a finger's) -> its value [rad, or m when prismatic];
            the joints not named are held at the SRDF's group state or 0
            (:mod:`kin.collision.held_joints`; :attr:`CollisionModel.held` says which).
        attached: Objects attached to links (:mod:`kin.collision.attached`); None: the scene
            file's ``[[attached]]`` entries (none without a scene).

    Raises:
        CollisionModelError: A bad scene, SRDF, padding or hold (the message names the file or
            the argument and the field).
        kin.ModelLoadError: The robot's URDF can no longer be read.
    """
    if not 0.0 <= padding <= MAX_COORDINATE:  # NaN fails too
        raise CollisionModelError(
            "", f"padding: {padding!r} m must be a number from 0 to {MAX_COORDINATE:g} m"
        )
    body = arm_body(robot, hold, srdf)
    arm, links, all_links = body.shapes, body.links, body.all_links
    objects: tuple[Shape, ...] = ()
    cell = None
    if scene is not None:
        from .scene import load_scene

        cell = load_scene(scene)
        objects = cell.objects
        clash = sorted({s.owner for s in objects} & set(all_links))
        if clash:
            raise CollisionModelError(str(scene), f"name {clash[0]!r} is a link of the robot")
    names = tuple(dict.fromkeys(s.owner for s in objects))
    carried = tuple(cell.attached if cell is not None and attached is None else attached or ())
    check_names(carried, all_links, names, "" if scene is None else str(scene))
    held_shapes = tuple(_on_link(body.mounts[thing.link], thing) for thing in carried)
    things = tuple(thing.name for thing in carried)
    carrier = {s.owner: s.parent for s in arm}
    disabled: dict[tuple[str, str], str] = dict.fromkeys(body.adjacent, "adjacent")
    for i, a in enumerate(links):
        for b in links[i + 1 :]:
            if (a, b) not in disabled and carrier[a] == carrier[b]:
                disabled[(a, b)] = "rigid"
    disabled.update(_attached_disabled(carried, links, carrier, body.mounts))
    granted = []  # an SRDF's pairs, then a PlanningScene's allowed collision matrix ("acm")
    if srdf is not None:
        from .srdf import read_srdf

        granted.append(read_srdf(srdf, body.robot_name, {*all_links, *names}, {*links, *names}))
    if cell is not None:
        granted.append(cell.for_robot(body.base, {*all_links, *names}, links))
    if robot.urdf_source is None and robot.table is not None:
        granted.append(_table_allowed(robot, links, carrier))
    for source in granted:
        for (a, b), reason in source.items():
            if (a, b) not in disabled and (b, a) not in disabled:
                disabled[_ordered(a, b, links)] = reason
    candidates = [(a, b) for i, a in enumerate(links) for b in links[i + 1 :]]
    candidates += [(link, name) for name in names for link in links]
    candidates += [(link, thing) for thing in things for link in links]
    candidates += [(a, b) for i, a in enumerate(things) for b in things[i + 1 :]]
    candidates += [(thing, name) for name in names for thing in things]
    pairs = tuple(p for p in candidates if p not in disabled and p[::-1] not in disabled)
    moving = (*arm, *(shape for shapes in held_shapes for shape in shapes))
    geometry_model, owners, pair_owners = _geometry_model(robot, moving, objects, pairs)
    always: list[tuple[str, str]] = []
    if robot.urdf_source is None:  # a DH drawing: its links may touch at a joint (always_pairs)
        from .always_pairs import always_in_contact

        # decided without the padding: a pair that touches only through it stays checked
        link_pairs = {p for p in pairs if p[1] in carrier}
        always = sorted(always_in_contact(robot.model, geometry_model, pair_owners, link_pairs))
    if always:
        disabled.update(dict.fromkeys(always, "always"))
        pairs = tuple(p for p in pairs if p not in always)
        geometry_model, owners, pair_owners = _geometry_model(robot, moving, objects, pairs)
    return CollisionModel(
        robot=robot,
        geometry_model=geometry_model,
        links=links,
        scene_objects=names,
        pairs=pairs,
        disabled=disabled,
        owners=owners,
        pair_owners=pair_owners,
        padding=float(padding),
        shape_note=_note(moving, objects, padding, always),
        held=body.held,
        attached=carried,
        inputs=_Inputs(srdf, scene, dict(hold or {})),
    )


def _on_link(mount: tuple[int, pin.SE3], thing: AttachedObject) -> tuple[ArmShape, ...]:
    """The shapes of ``thing`` on the kin model's joint that carries its link."""
    joint, T_joint_link = mount
    return tuple(
        ArmShape(s.owner, s.name, s.geometry, T_joint_link * s.placement, s.kind, joint)
        for s in thing.shapes
    )


def _attached_disabled(
    carried: tuple[AttachedObject, ...],
    links: tuple[str, ...],
    carrier: dict[str, int],
    mounts: Mapping[str, tuple[int, pin.SE3]],
) -> dict[tuple[str, str], str]:
    """Pairs of attached objects not checked: their link and touch links, what rides with them."""
    disabled = {}
    for i, thing in enumerate(carried):
        joint = mounts[thing.link][0]
        for link in links:
            if link == thing.link or link in thing.touch_links:
                disabled[(link, thing.name)] = "touch"
            elif carrier[link] == joint:
                disabled[(link, thing.name)] = "rigid"
        for other in carried[i + 1 :]:
            if mounts[other.link][0] == joint:
                disabled[(thing.name, other.name)] = "rigid"
    return disabled


def _table_allowed(
    robot: RobotModel, links: tuple[str, ...], carrier: Mapping[str, int]
) -> dict[tuple[str, str], str]:
    """The link pairs a DH table's rows allow (``[[joints.allow_contact]]``).

    Every link carried by the row's joint with every link carried by the earlier row's joint
    (row 1's: and the base's).
    """
    table = robot.table
    assert table is not None
    joint = [robot.model.getJointId(row.name) for row in table.rows]
    allowed = {}
    for row in table.rows:
        for contact in row.allowed_contacts:
            earlier = {joint[contact.row - 1], *((0,) if contact.row == 1 else ())}
            for b in links:
                if carrier[b] != joint[row.index - 1]:
                    continue
                for a in links:
                    if carrier[a] in earlier:
                        allowed[(a, b)] = f"table: {contact.reason}"
    return allowed


def _ordered(a: str, b: str, links: tuple[str, ...]) -> tuple[str, str]:
    if a in links and b in links:
        return (a, b) if links.index(a) < links.index(b) else (b, a)
    return (a, b) if a in links else (b, a)


def _geometry_model(
    robot: RobotModel,
    arm: tuple[ArmShape, ...],
    objects: tuple[Shape, ...],
    pairs: tuple[tuple[str, str], ...],
) -> tuple[pin.GeometryModel, tuple[str, ...], tuple[tuple[str, str], ...]]:
    model = robot.model
    geometry_model = pin.GeometryModel()
    owners = []
    for shape in arm:
        frame = (
            model.getFrameId(model.names[shape.parent], pin.FrameType.JOINT) if shape.parent else 0
        )
        geometry_model.addGeometryObject(
            pin.GeometryObject(shape.name, shape.parent, frame, shape.placement, shape.geometry)
        )
        owners.append(shape.owner)
    for thing in objects:
        geometry_model.addGeometryObject(
            pin.GeometryObject(f"scene/{thing.name}", 0, 0, thing.placement, thing.geometry)
        )
        owners.append(thing.owner)
    by_owner: dict[str, list[int]] = {}
    for index, owner in enumerate(owners):
        by_owner.setdefault(owner, []).append(index)
    pair_owners = []
    for a, b in pairs:
        for i in by_owner[a]:
            for j in by_owner[b]:
                geometry_model.addCollisionPair(pin.CollisionPair(i, j))
                pair_owners.append((a, b))
    return geometry_model, tuple(owners), tuple(pair_owners)


def _note(
    arm: tuple[ArmShape, ...],
    objects: tuple[Shape, ...],
    padding: float,
    always: list[tuple[str, str]],
) -> str:
    kinds = sorted({s.kind for s in (*arm, *objects)})
    meshes = "mesh" in kinds
    primitives = [k for k in kinds if k != "mesh"]
    parts = []
    if primitives:
        parts.append(f"{', '.join(primitives)} as given (exact)")
    if meshes:
        parts.append("meshes as their convex hulls (they enclose the mesh: never closer)")
    note = (
        f"every query uses {'; '.join(parts) or 'no shapes'}; "
        f"padding {padding:g} m around every shape; a pair closer than the padding "
        f"+ {CONTACT_TOLERANCE:g} m collides (coal's accuracy)"
    )
    if always:
        from .always_pairs import SAMPLES, SEED

        note += (
            f"; not checked, in contact without padding at all {SAMPLES} sampled configurations "
            f"(default_rng({SEED})), links meeting at a joint of the DH drawing: "
            + ", ".join(f"{a}/{b}" for a, b in always)
        )
    return note
