"""Compare a shipped DH table's body with the maker's collision meshes in a scene.

Per arm, over N random configurations within the joint limits: the maker's URDF
(example-robot-data, its collision meshes as convex hulls: they enclose the meshes) checked by coal
through a Pinocchio GeometryModel built here, against the shipped table's model
(``kin.collision`` on ``load_robot(name)``); only arm-scene pairs, self-collisions aside. Prints
the misses (the maker's arm collides with the scene, the table says free: must be 0) and the
false alarms (the table collides, the maker's arm is free). The maker's links are those from its
root to the table's tool (a UR's ``ee_link`` and Panda's hand are off that chain). The two models
share one world frame: the transform between their roots is measured at q = 0 from the tool
poses and checked at every configuration.

Self-collisions: over the same configurations, the maker's chain with its SRDF's pairs disabled
(example-robot-data's ``panda.srdf``; ``ur5.srdf`` for the three URs, whose link names it shares),
hulls checked by coal, against the shipped table's own model (``kin.collision``, no SRDF: its
adjacent, always-in-contact and ``[[joints.allow_contact]]`` pairs aside). Prints both rates,
the misses (the maker's arm collides with itself, the table says free) and the false alarms.

``--fit`` prints, per row, the ``[[joints.housing]]`` cylinders that enclose the maker's hulls
(per maker link up to three, each around a slab of its hull along an axis of DH frame i, the split
of least volume; a link fixed to the base gets one cylinder about joint 1's axis, on row 1), and
the ``[[joints.allow_contact]]`` of the row pairs whose links the maker's SRDF all disables and
whose volumes touch in some of the configurations (rows not joined by a joint: an arm folded at
its joint collides, though the SRDF disables adjacent links).
"""

from __future__ import annotations

import argparse
import importlib.metadata
import math
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pinocchio as pin

#: arm -> (URDF inside example-robot-data's robots folder, the maker's frame of our tool).
MAKER_URDFS = {
    "panda": ("panda_description/urdf/panda.urdf", "panda_link8"),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "tool0"),
    "ur3": ("ur_description/urdf/ur3_robot.urdf", "tool0"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0"),
}
#: arm -> the maker's SRDF inside example-robot-data's robots folder.
MAKER_SRDFS = {
    "panda": "panda_description/srdf/panda.srdf",
    "ur10": "ur_description/srdf/ur5.srdf",
    "ur3": "ur_description/srdf/ur5.srdf",
    "ur5": "ur_description/srdf/ur5.srdf",
}
#: The cell of the README's examples.
DEFAULT_SCENE = Path(__file__).resolve().parent.parent / "examples" / "cell.toml"
#: Largest tool-pose difference between the two models once in one world frame [m].
FRAME_TOL = 1e-6
#: Margin added to a fitted housing's radius and length [m], before rounding up to 1 mm.
FIT_MARGIN = 0.001


def erd_urdf(relative: str) -> Path:
    """Absolute path of an example-robot-data URDF (``robots/<relative>``)."""
    suffix = f"example-robot-data/robots/{relative}"
    for file in importlib.metadata.files("example-robot-data") or ():
        if str(file).endswith(suffix):
            return Path(str(file.locate()))
    raise FileNotFoundError(f"{suffix}: pip install example-robot-data")


@dataclass(frozen=True)
class Counts:
    """Scene verdicts of one arm over ``samples`` configurations."""

    robot: str
    samples: int
    maker_hits: int
    table_hits: int
    misses: int
    false_alarms: int


class MakerArm:
    """The maker's URDF with its chain's collision hulls, placed in the table's world frame."""

    def __init__(self, name: str):
        from kin import load_robot

        relative, tip = MAKER_URDFS[name]
        path = erd_urdf(relative)
        self.table = load_robot(name)
        self.model = pin.buildModelFromUrdf(str(path))
        share = str(path.parents[4])  # package://example-robot-data/... resolves from here
        geometry = pin.buildGeomFromUrdf(self.model, str(path), pin.COLLISION, package_dirs=[share])
        self.index = [
            self.model.idx_qs[self.model.getJointId(joint)] for joint in self.table.joint_names
        ]
        chain = set()
        frame = self.model.getFrameId(tip)
        while frame > 0:
            chain.add(self.model.frames[frame].name)
            frame = self.model.frames[frame].parentFrame
        chain.add(self.model.frames[0].name)
        self.geometry = pin.GeometryModel()
        for item in geometry.geometryObjects:
            if self.model.frames[item.parentFrame].name not in chain:
                continue
            if hasattr(item.geometry, "buildConvexHull"):  # a mesh: its hull
                item.geometry.buildConvexHull(True, "Qt")
                item.geometry = item.geometry.convex
            self.geometry.addGeometryObject(item)
        self.data = self.model.createData()
        self.tip = self.model.getFrameId(tip)
        self.T_maker_table = self._root_transform()

    def q(self, q_table: np.ndarray) -> np.ndarray:
        """The maker's joint vector of the table's ``q`` [rad] (other joints at 0)."""
        q = pin.neutral(self.model)
        q[self.index] = q_table
        return q

    def tool(self, q_table: np.ndarray) -> pin.SE3:
        """The maker's tool frame in the maker's root frame."""
        pin.framesForwardKinematics(self.model, self.data, self.q(q_table))
        return self.data.oMf[self.tip].copy()

    def _root_transform(self) -> pin.SE3:
        from kin import Configuration

        zero = np.zeros(self.table.nq)
        ours = Configuration(self.table, zero).transform_frame_to_world(self.table.tool_frame)
        return self.tool(zero) * ours.inverse()

    def check_frames(self, qs: np.ndarray) -> float:
        """Largest tool position difference [m] between the models in one world frame."""
        from kin import Configuration

        worst = 0.0
        for q in qs[:: max(1, len(qs) // 200)]:
            ours = Configuration(self.table, q).transform_frame_to_world(self.table.tool_frame)
            moved = self.T_maker_table * ours
            worst = max(worst, float(np.linalg.norm(moved.translation - self.tool(q).translation)))
        return worst


def _maker_verdicts(arm: MakerArm, scene_objects, qs: np.ndarray) -> np.ndarray:
    """Whether the maker's chain touches a scene object, per configuration."""
    geometry = arm.geometry.clone()
    links = len(geometry.geometryObjects)
    for thing in scene_objects:
        placement = arm.T_maker_table * thing.placement
        geometry.addGeometryObject(
            pin.GeometryObject(f"scene/{thing.name}", 0, 0, placement, thing.geometry)
        )
    for i in range(links):
        for j in range(links, len(geometry.geometryObjects)):
            geometry.addCollisionPair(pin.CollisionPair(i, j))
    data = geometry.createData()
    return np.array(
        [pin.computeCollisions(arm.model, arm.data, geometry, data, arm.q(q), True) for q in qs]
    )


def _table_verdicts(robot, scene: Path, qs: np.ndarray) -> np.ndarray:
    """Whether the table's body touches a scene object (kin.collision), per configuration."""
    from kin.collision import CollisionChecker, load_collision_model

    full = load_collision_model(robot, scene=scene)
    keep = [k for k, (_, b) in enumerate(full.pair_owners) if b in full.scene_objects]
    geometry = pin.GeometryModel()
    for item in full.geometry_model.geometryObjects:
        geometry.addGeometryObject(item)
    for k in keep:
        geometry.addCollisionPair(full.geometry_model.collisionPairs[k])
    pairs = tuple(p for p in full.pairs if p[1] in full.scene_objects)
    owners = tuple(full.pair_owners[k] for k in keep)
    model = replace(full, geometry_model=geometry, pairs=pairs, pair_owners=owners)
    return CollisionChecker(model).in_collision_batch(qs, threads=1)


def compare(name: str, samples: int, scene: Path = DEFAULT_SCENE, seed: int = 0) -> Counts:
    """The maker's and the table's scene verdicts at ``samples`` random configurations."""
    from kin.collision.scene import load_scene

    arm = MakerArm(name)
    robot = arm.table
    rng = np.random.default_rng(seed)
    qs = rng.uniform(robot.lower, robot.upper, size=(samples, robot.nq))
    offset = arm.check_frames(qs)
    if offset > FRAME_TOL:
        raise RuntimeError(f"{name}: the two models' tools differ by {offset:.3g} m")
    maker = _maker_verdicts(arm, load_scene(scene).objects, qs)
    table = _table_verdicts(robot, scene, qs)
    return Counts(
        name,
        samples,
        int(maker.sum()),
        int(table.sum()),
        int((maker & ~table).sum()),
        int((table & ~maker).sum()),
    )


def _maker_self(arm: MakerArm, name: str) -> tuple[pin.GeometryModel, set[tuple[str, str]]]:
    """The maker's chain with every link pair its SRDF leaves checked, and those pairs."""
    geometry = arm.geometry.clone()
    geometry.addAllCollisionPairs()
    pin.removeCollisionPairs(arm.model, geometry, str(erd_urdf(MAKER_SRDFS[name])))
    links = [arm.model.frames[item.parentFrame].name for item in geometry.geometryObjects]
    checked = {(links[p.first], links[p.second]) for p in geometry.collisionPairs}
    return geometry, checked


def _maker_rows(arm: MakerArm) -> dict[str, int]:
    """Maker link -> the table row whose housings enclose it (row 1 for links fixed to the base)."""
    rows = {}
    for item in arm.geometry.geometryObjects:
        joint = arm.model.names[item.parentJoint] if item.parentJoint else None
        names = arm.table.joint_names
        rows[arm.model.frames[item.parentFrame].name] = (
            names.index(joint) + 1 if joint in names else 1
        )
    return rows


def self_compare(name: str, samples: int, seed: int = 0) -> Counts:
    """The maker's (with its SRDF) and the table's self-collision verdicts, random q."""
    from kin.collision import CollisionChecker, load_collision_model

    arm = MakerArm(name)
    robot = arm.table
    qs = np.random.default_rng(seed).uniform(robot.lower, robot.upper, size=(samples, robot.nq))
    geometry, _ = _maker_self(arm, name)
    data = geometry.createData()
    maker = np.array(
        [pin.computeCollisions(arm.model, arm.data, geometry, data, arm.q(q), True) for q in qs]
    )
    table = CollisionChecker(load_collision_model(robot)).in_collision_batch(qs, threads=1)
    return Counts(
        name,
        samples,
        int(maker.sum()),
        int(table.sum()),
        int((maker & ~table).sum()),
        int((table & ~maker).sum()),
    )


def allowed_rows(name: str, samples: int = 1000, seed: int = 0) -> list[tuple[int, int, str]]:
    """Row pairs ``(earlier, later, reason)`` to allow in the table.

    Those whose maker links the SRDF all disables and whose table volumes touch in some of
    ``samples`` random configurations, rows joined by a joint aside.
    """
    from kin.collision import load_collision_model
    from kin.collision.pair_contacts import PairContacts
    from kin.collision.srdf import srdf_root

    arm = MakerArm(name)
    robot = arm.table
    _, checked = _maker_self(arm, name)
    rows = _maker_rows(arm)
    reasons = {}
    for item in srdf_root(str(erd_urdf(MAKER_SRDFS[name]))).iter("disable_collisions"):
        first, second = item.get("link1"), item.get("link2")
        reasons[(first, second)] = reasons[(second, first)] = item.get("reason") or ""
    model = load_collision_model(robot)
    joint_row = {robot.model.getJointId(n): k + 1 for k, n in enumerate(robot.joint_names)}
    carrier = {o.name: max(o.parentJoint, 1) for o in model.geometry_model.geometryObjects}
    owner_row = {
        owner: joint_row[carrier[o.name]]
        for owner, o in zip(model.owners, model.geometry_model.geometryObjects, strict=True)
    }
    contacts = PairContacts(robot.model, model.geometry_model, model.pair_owners)
    qs = np.random.default_rng(seed).uniform(robot.lower, robot.upper, size=(samples, robot.nq))
    touching = set()
    for q in qs:
        touching |= {(owner_row[a], owner_row[b]) for a, b in contacts.at(q, set(model.pairs))}
    out = []
    for low, high in sorted(touching):
        pairs = [(a, b) for a in rows if rows[a] == low for b in rows if rows[b] == high]
        # rows joined by a joint stay checked: the SRDF disables such links as adjacent, but an
        # arm folded at the joint does collide (UR5's forearm on its upper arm)
        if high - low < 2 or any(p in checked or p[::-1] in checked for p in pairs):
            continue
        why = ", ".join(sorted({reasons.get(p, "") for p in pairs} - {""}))
        links = ", ".join(f"{a}/{b}" for a, b in pairs)
        out.append((low, high, f"the maker's SRDF disables {links}" + (f" ({why})" if why else "")))
    return out


def _hull_points(arm: MakerArm, item: pin.GeometryObject) -> np.ndarray:
    """The vertices of a maker link's hull, in the maker's root frame at q = 0 [m] (N, 3)."""
    geometry = item.geometry
    points = np.array(
        [geometry.points(i) for i in range(geometry.num_points)]
        if hasattr(geometry, "num_points")
        else _primitive_points(geometry)
    )
    pin.framesForwardKinematics(arm.model, arm.data, arm.q(np.zeros(arm.table.nq)))
    placement = arm.data.oMf[item.parentFrame] * item.placement
    return points @ placement.rotation.T + placement.translation


def _primitive_points(geometry) -> np.ndarray:
    """Corners of a box (or of the box around a sphere or cylinder) in its own frame [m]."""
    if hasattr(geometry, "halfSide"):
        half = np.asarray(geometry.halfSide)
    elif hasattr(geometry, "halfLength"):
        half = np.array([geometry.radius, geometry.radius, geometry.halfLength])
    else:
        half = np.full(3, geometry.radius)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    return corners * half


def _enclosing_circle(points: np.ndarray) -> tuple[np.ndarray, float]:
    """A small circle around 2-D points: centre and radius (a few refinement steps)."""
    centre = (points.min(axis=0) + points.max(axis=0)) / 2.0
    for step in np.geomspace(0.02, 1e-5, 60):
        radius = np.linalg.norm(points - centre, axis=1)
        far = points[int(np.argmax(radius))]
        centre = centre + step * (far - centre) / max(float(radius.max()), 1e-12)
    return centre, float(np.linalg.norm(points - centre, axis=1).max())


def _cylinder(points: np.ndarray, axis: int, centre: np.ndarray | None = None):
    """The cylinder along ``axis`` around ``points`` (frame coordinates): ends, radius, volume."""
    plane = [k for k in range(3) if k != axis]
    if centre is None:
        centre, radius = _enclosing_circle(points[:, plane])
    else:
        radius = float(np.linalg.norm(points[:, plane] - centre, axis=1).max())
    radius = math.ceil((radius + FIT_MARGIN) * 1000.0) / 1000.0
    low = math.floor((points[:, axis].min() - FIT_MARGIN) * 1000.0) / 1000.0
    high = math.ceil((points[:, axis].max() + FIT_MARGIN) * 1000.0) / 1000.0
    ends = np.zeros((2, 3))
    ends[:, plane] = np.round(centre, 4)
    ends[:, axis] = (low, high)
    return ends, radius, math.pi * radius**2 * (high - low)


#: Most cylinders one maker link is split into by ``--fit``.
MAX_PIECES = 3
#: A split is kept only when it saves more than this fraction of one cylinder's volume per
#: extra cylinder (fewer shapes to check when the saving is small).
SPLIT_GAIN = 0.1


def _hull_edges(points: np.ndarray) -> np.ndarray:
    """The edges of the convex hull of ``points`` (pairs of points, (E, 2, 3))."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(points)
    edges = {
        tuple(sorted((int(a), int(b))))
        for tri in hull.simplices
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0]))
    }
    return points[np.array(sorted(edges))]


def _slab_points(points: np.ndarray, edges: np.ndarray, axis: int, low: float, high: float):
    """The corners of the hull cut to ``low <= x[axis] <= high``.

    Its points inside and where its edges cross the two planes (the slab of a convex hull is the
    hull of these).
    """
    inside = points[(points[:, axis] >= low) & (points[:, axis] <= high)]
    crossings = [inside]
    a, b = edges[:, 0], edges[:, 1]
    for plane in (low, high):
        da, db = a[:, axis] - plane, b[:, axis] - plane
        cross = da * db < 0.0
        t = (da[cross] / (da[cross] - db[cross]))[:, None]
        crossings.append(a[cross] + t * (b[cross] - a[cross]))
    return np.concatenate(crossings)


def _pieces(points: np.ndarray):
    """Up to :data:`MAX_PIECES` cylinders whose union encloses the hull of ``points``.

    The hull is cut into slabs along one axis of the frame (cuts on a 5 % grid of its extent);
    each slab gets the smallest of its three axis-aligned cylinders. The split with the least
    total volume wins when it saves :data:`SPLIT_GAIN` per extra cylinder.
    """
    edges = _hull_edges(points)
    one = min((_cylinder(points, k) for k in range(3)), key=lambda c: c[2])
    best, best_score = [one], one[2]
    grid = np.linspace(0.05, 0.95, 19)
    for split in range(3):
        low, high = points[:, split].min(), points[:, split].max()
        cuts_list = [(f,) for f in grid]
        if MAX_PIECES >= 3:
            cuts_list += [(f, g) for f in grid for g in grid if g > f + 0.04]
        for cuts in cuts_list:
            bounds = [low, *(low + f * (high - low) for f in cuts), high]
            pieces = []
            for lo, hi in zip(bounds[:-1], bounds[1:]):
                piece = _slab_points(points, edges, split, lo, hi)
                pieces.append(min((_cylinder(piece, k) for k in range(3)), key=lambda c: c[2]))
            volume = sum(c[2] for c in pieces)
            score = volume + SPLIT_GAIN * one[2] * (len(pieces) - 1)
            if score < best_score:
                best, best_score = pieces, score
    return best


def fit_housings(name: str) -> dict[int, list[tuple[np.ndarray, np.ndarray, float, str]]]:
    """Per row, the housings (from, to in DH frame i [m], radius [m], maker link) to add."""
    from kin import Configuration

    arm = MakerArm(name)
    robot = arm.table
    world = Configuration(robot, np.zeros(robot.nq))
    to_table = arm.T_maker_table.inverse()
    fits: dict[int, list] = {}
    for item in arm.geometry.geometryObjects:
        points = _hull_points(arm, item) @ to_table.rotation.T + to_table.translation
        joint = arm.model.names[item.parentJoint] if item.parentJoint else None
        row = robot.joint_names.index(joint) + 1 if joint in robot.joint_names else 1
        frame = world.transform_frame_to_world(f"frame{row}").inverse()
        local = points @ frame.rotation.T + frame.translation
        link = arm.model.frames[item.parentFrame].name
        if joint is None:  # fixed to the base: a cylinder about joint 1's axis
            axis_pose = frame * world.transform_frame_to_world(f"frame{row - 1}")
            # joint 1 turns about z of frame 0 (standard) or of frame 1 (modified)
            if robot.table is not None and robot.table.convention == "modified":
                axis_pose = pin.SE3.Identity()
            around = (local - axis_pose.translation) @ axis_pose.rotation
            ends, radius, _ = _cylinder(around, 2, np.zeros(2))
            ends = ends @ axis_pose.rotation.T + axis_pose.translation
            fits.setdefault(row, []).append((ends[0], ends[1], radius, link))
            continue
        for ends, radius, _ in _pieces(local):
            fits.setdefault(row, []).append((ends[0], ends[1], radius, link))
    return fits


def get_argument_parser() -> argparse.ArgumentParser:
    """Command-line arguments."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("robots", nargs="*", default=sorted(MAKER_URDFS), help="shipped arms")
    parser.add_argument("--n", type=int, default=10_000, help="configurations per arm")
    parser.add_argument("--scene", type=Path, default=DEFAULT_SCENE, help="the cell")
    parser.add_argument("--seed", type=int, default=0, help="random seed")
    parser.add_argument("--fit", action="store_true", help="print enclosing housings instead")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Print the counts per arm; exit 1 when an arm has a miss."""
    args = get_argument_parser().parse_args(argv)
    unknown = sorted(set(args.robots) - set(MAKER_URDFS))
    if unknown or args.n < 1:
        print(f"choose robots from {', '.join(sorted(MAKER_URDFS))} and --n >= 1", file=sys.stderr)
        return 2
    if args.fit:
        for robot in args.robots:
            for row, housings in sorted(fit_housings(robot).items()):
                for start, end, radius, link in housings:
                    print(f"# {robot} row {row}: encloses {link}")
                    print(f"from = {np.round(start, 4).tolist()}\nto = {np.round(end, 4).tolist()}")
                    print(f"radius = {radius}")
            for low, high, reason in allowed_rows(robot):
                print(f"# {robot} row {high}: [[joints.allow_contact]]")
                print(f"row = {low}\nreason = {reason!r}")
        return 0
    worst = 0
    print(f"scene {args.scene}, {args.n} configurations per arm (seed {args.seed})")
    print("robot  maker-hits  table-hits  misses  false-alarms")
    for robot in args.robots:
        c = compare(robot, args.n, args.scene, args.seed)
        alarms = f"{c.false_alarms} ({100.0 * c.false_alarms / c.samples:.1f} %)"
        print(f"{robot:6s} {c.maker_hits:10d} {c.table_hits:11d} {c.misses:7d}  {alarms}")
        worst = max(worst, c.misses)
    print("self-collisions: the maker's arm with its SRDF, the table's own model (no SRDF)")
    print("robot  maker-hits  table-hits  misses  false-alarms")
    for robot in args.robots:
        c = self_compare(robot, args.n, args.seed)
        alarms = f"{c.false_alarms} ({100.0 * c.false_alarms / c.samples:.1f} %)"
        print(f"{robot:6s} {c.maker_hits:10d} {c.table_hits:11d} {c.misses:7d}  {alarms}")
        worst = max(worst, c.misses)
    return 1 if worst else 0


if __name__ == "__main__":
    raise SystemExit(main())
