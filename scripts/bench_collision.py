"""Benchmark the collision checker against Pinocchio's own call and MuJoCo's; print a table.

Per robot (UR5 and Panda from example-robot-data, Panda with the maker's SRDF, humanoid7's DH
shapes), in the cell of tests/data/collision/cell.toml (a table, a wall, a ball), at random
configurations within the limits:

* ``check``: ``CollisionChecker.in_collision(q)`` (self and scene), median of single calls; it
  runs Pinocchio's computeCollisions through coal's naive broad phase (world boxes, the exact
  test only where two boxes overlap) on the models with meshes, else pair by pair on the
  checker's own pairs (the most often in contact first: kin.collision.pair_order), GJK stopped
  once a pair is proven beyond the padding (kin.collision.requests);
* ``pin``: ``pin.computeCollisions`` on the same GeometryModel (FK, placements, every active
  pair, stop at the first contact), median of single calls, alternated with ``check``: each goes
  first at every other configuration (the first call after MuJoCo's finds the shared meshes out
  of cache; always calling ``check`` first made it 1.4-1.8x ``pin`` and ``pin`` first 1.4x
  ``check``; ``check``, ``pin`` and ``bare`` now take turns going first);
* ``bare``: ``pin.computeCollisions`` called as the checker calls it (through the same naive
  broad-phase manager when ``checker.broad_phase``: the models with meshes; else on the
  checker's own pairs, the most often in contact first: kin.collision.pair_order), bare:
  ``check`` / ``bare`` is the wrapper's own cost (the input check of ``q``);
* ``batch``: ``in_collision_batch`` over ``--batch`` configurations, per configuration, against
  a Python loop of ``in_collision`` over the same ones, in seven alternating rounds of a
  seventh each, each side's median round (on a shared machine one long run of each measures the
  neighbours' load as much as the code, and a sum of rounds lets one slowed round decide);
* ``mujoco``: ``mj_kinematics`` + ``mj_collision`` on the maker's URDF (meshes: MuJoCo's convex
  hulls, the same as the checker's) with the cell's geoms added, the checker's disabled pairs
  excluded; MuJoCo finds every contact (no early stop).

* ``ik``: ``get_solver(robot, collisions=checker).solve`` against the plain ``solve`` of the
  same targets and seeds (full poses of random configurations, seeds 0.05 rad away), alternated
  medians, over the targets whose plain nearest answer is already free (the colliding ones take
  the extra search: their median is printed beside, not judged).

Goals (issue 36 item 7): check <= 1.2x pin; batch >= 1.5x faster than the loop on 2 cores;
collision-aware IK <= 2x the plain call when the nearest branch is free.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import re  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402
from bench_ik_urdf import erd  # noqa: E402

from kin import load_robot  # noqa: E402
from kin.cli import ArgumentParser, positive_int  # noqa: E402

CELL = Path(__file__).resolve().parents[1] / "tests" / "data" / "collision" / "cell.toml"
#: row -> (URDF in example-robot-data or a shipped robot's name, tip link, SRDF or None).
ROWS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "tool0", None),
    "panda": ("panda_description/urdf/panda.urdf", "panda_link8", None),
    "panda+srdf": (
        "panda_description/urdf/panda.urdf",
        "panda_link8",
        "panda_description/srdf/panda.srdf",
    ),
    "humanoid7": ("humanoid7", None, None),
}
CHECK_GOAL = 1.2
BATCH_GOAL = 1.5
IK_GOAL = 2.0
#: The IK rows: the robots of the issue's goal (UR5, Panda, humanoid7).
IK_ROWS = ("ur5", "panda", "humanoid7")


def get_argument_parser() -> ArgumentParser:
    """Command-line arguments."""
    parser = ArgumentParser(prog="bench_collision.py", description=__doc__)
    parser.add_argument(
        "--configurations",
        type=positive_int,
        default=2000,
        help="single-call timings per figure, each at its own configuration (default 2000)",
    )
    parser.add_argument(
        "--batch",
        type=positive_int,
        default=20_000,
        help="configurations per batch (default 20000)",
    )
    parser.add_argument(
        "--ik-targets",
        type=positive_int,
        default=300,
        help="IK targets per robot for the collision-aware IK rows (default 300)",
    )
    return parser


def _alternate(
    functions: list[Callable[[np.ndarray], object]], qs: np.ndarray, rotated: int = 3
) -> list[float]:
    """Median single-call time [us] of each function over ``qs``, alternating per configuration.

    The first ``rotated`` functions take turns going first (configuration i starts with function
    i mod ``rotated``); the others come after them.
    """
    times: list[list[float]] = [[] for _ in functions]
    clock = time.perf_counter
    for q in qs[:5]:
        for function in functions:
            function(q)
    timed = list(zip(functions, times, strict=True))
    turns, rest = timed[:rotated], timed[rotated:]
    for i, q in enumerate(qs):
        k = i % len(turns)
        for function, bucket in turns[k:] + turns[:k] + rest:
            start = clock()
            function(q)
            bucket.append(clock() - start)
    return [statistics.median(bucket) * 1e6 for bucket in times]


def _loop_and_batch(checker, qs: np.ndarray, rounds: int = 7) -> tuple[float, float, bool]:
    """Time [us/configuration] of a loop of ``in_collision`` and of ``in_collision_batch``.

    Alternating rounds over sevenths of ``qs``, each side's median round (as the other figures,
    a median: one round slowed by other work does not decide); the third value: the verdicts
    agree.
    """
    clock = time.perf_counter
    loops, batches = [], []
    agree = True
    for chunk in np.array_split(qs, rounds):
        start = clock()
        looped = [checker.in_collision(q) for q in chunk]
        loops.append((clock() - start) / len(chunk))
        start = clock()
        batched = checker.in_collision_batch(chunk)
        batches.append((clock() - start) / len(chunk))
        agree &= list(map(bool, batched)) == list(map(bool, looped))
    return statistics.median(loops) * 1e6, statistics.median(batches) * 1e6, agree


def _mujoco_collide(robot, model) -> Callable[[np.ndarray], object] | None:
    """``q -> ncon`` of MuJoCo on the same links and cell, or None when MuJoCo cannot load it."""
    import mujoco

    from kin.collision.scene import read_scene

    if robot.urdf_source is not None:
        path = Path(robot.urdf_source[0])
        text = path.read_text(encoding="utf-8")
        text = re.sub(
            r'filename="package://([^"]+)"',
            lambda m: f'filename="{_package_file(m.group(1), path)}"',
            text,
        )
    else:
        text = robot.urdf
    text = re.sub(r"<mujoco>.*?</mujoco>", "", text, flags=re.S)
    start = text.find(">", text.find("<robot")) + 1
    compiler = '<mujoco><compiler fusestatic="false" discardvisual="true" angle="radian"/></mujoco>'
    spec = mujoco.MjSpec.from_string(text[:start] + compiler + text[start:])
    for shape in read_scene(CELL):
        _add_geom(mujoco, spec, shape)
    for a, b in model.disabled:
        try:
            spec.add_exclude(bodyname1=a, bodyname2=b)
        except Exception:  # noqa: BLE001 - a link without a body in MuJoCo
            pass
    try:
        mj_model = spec.compile()
    except ValueError as err:
        print(f"  (MuJoCo cannot load {robot.name}: {err})")
        return None
    data = mujoco.MjData(mj_model)
    addresses = [mj_model.jnt_qposadr[mj_model.joint(n).id] for n in robot.joint_names]

    def collide(q: np.ndarray) -> int:
        data.qpos[addresses] = q
        mujoco.mj_kinematics(mj_model, data)
        mujoco.mj_collision(mj_model, data)
        return int(data.ncon)

    return collide


def _package_file(rest: str, urdf: Path) -> Path:
    package, _, inside = rest.partition("/")
    for folder in urdf.resolve().parents:
        if folder.name == package:
            return folder / inside
    return urdf.parent / inside


def _add_geom(mujoco, spec, shape) -> None:
    """Add a scene shape (kin.collision.urdf_shapes.Shape, world frame) to MuJoCo's worldbody."""
    geometry = shape.geometry
    kind = shape.kind
    if kind == "box":
        size, type_ = list(geometry.halfSide), mujoco.mjtGeom.mjGEOM_BOX
    elif kind == "sphere":
        size, type_ = [geometry.radius, 0, 0], mujoco.mjtGeom.mjGEOM_SPHERE
    elif kind == "cylinder":
        size, type_ = [geometry.radius, geometry.halfLength, 0], mujoco.mjtGeom.mjGEOM_CYLINDER
    else:
        return
    quat = pin.Quaternion(shape.placement.rotation)
    spec.worldbody.add_geom(
        name=shape.name,
        type=type_,
        size=size,
        pos=shape.placement.translation,
        quat=[quat.w, quat.x, quat.y, quat.z],
    )


def bench_row(name: str, configurations: int, batch: int) -> tuple[float, float]:
    """Print one robot's row; return (check / pin, loop / batch)."""
    from kin.collision import CollisionChecker, load_collision_model

    source, tip, srdf = ROWS[name]
    robot = load_robot(source if tip is None else erd(source), None, tip)
    model = load_collision_model(robot, srdf=erd(srdf) if srdf else None, scene=CELL)
    checker = CollisionChecker(model)
    geometry_model = model.geometry_model
    pin_model = robot.model
    pin_data, geometry_data = pin_model.createData(), pin.GeometryData(geometry_model)

    def pinocchio(q: np.ndarray) -> bool:
        return pin.computeCollisions(pin_model, pin_data, geometry_model, geometry_data, q, True)

    verdict_model = checker._verdict_geometry  # the pairs (and their order) the checker tests
    bare_data = pin.GeometryData(verdict_model)
    checker._prepare(bare_data, contact=False)
    bare_pin_data = pin_model.createData()
    manager = pin.BroadPhaseManager_NaiveCollisionManager(pin_model, geometry_model, bare_data)

    def bare(q: np.ndarray) -> bool:
        if checker.broad_phase:
            return pin.computeCollisions(pin_model, bare_pin_data, manager, q, True)
        return pin.computeCollisions(pin_model, bare_pin_data, verdict_model, bare_data, q, True)

    rng = np.random.default_rng(0)
    qs = rng.uniform(robot.lower, robot.upper, (max(configurations, batch), robot.nq))
    single = qs[:configurations]
    agree = sum(bool(pinocchio(q)) == bool(checker.in_collision(q)) for q in single[:200])
    functions: list[Callable[[np.ndarray], object]] = [
        checker.in_collision,
        pinocchio,
        bare,
    ]
    collide = _mujoco_collide(robot, model)
    if collide is not None:
        functions.append(collide)
    timings = _alternate(functions, single)
    t_check, t_pin, t_bare = timings[0], timings[1], timings[2]
    t_mujoco = timings[3] if collide is not None else float("nan")
    t_loop, t_batch, same = _loop_and_batch(checker, qs[:batch])
    assert same, name
    colliding = float(np.mean(checker.in_collision_batch(qs[:batch])))
    print(
        f"{name:<11} {len(model.pairs):>5} {colliding:>9.0%} {t_check:>10.1f} {t_pin:>9.1f} "
        f"{t_check / t_pin:>6.2f} {t_bare:>7.1f} {t_check / t_bare:>6.2f} {t_loop:>9.1f} "
        f"{t_batch:>10.1f} {t_loop / t_batch:>6.2f} {t_mujoco:>11.1f}   ({agree}/200 verdicts as pin)",
        flush=True,
    )
    return t_check / t_pin, t_loop / t_batch


def ik_row(name: str, count: int) -> float:
    """Print one robot's collision-aware IK row; return aware / plain on free nearest answers."""
    from kin import Configuration
    from kin.collision import CollisionChecker, load_collision_model
    from kin.ik import PoseTarget, get_solver

    source, tip, srdf = ROWS[name]
    robot = load_robot(source if tip is None else erd(source), None, tip)
    checker = CollisionChecker(load_collision_model(robot, scene=CELL))
    plain, aware = get_solver(robot), get_solver(robot, collisions=checker)
    config = Configuration(robot)
    rng = np.random.default_rng(1)
    free_cases, blocked_cases = [], []
    for q in rng.uniform(robot.lower, robot.upper, (count, robot.nq)):
        pose = config.fk(q)
        target = PoseTarget(pose.translation, pose.rotation)
        seed = np.clip(q + rng.normal(0.0, 0.05, robot.nq), robot.lower, robot.upper)
        first = plain.solve(target, seed)
        if first.solutions:
            blocked = checker.in_collision(first.solutions[0].q)
            (blocked_cases if blocked else free_cases).append((target, seed))
    clock = time.perf_counter

    def medians(cases: list) -> tuple[float, float]:
        t_plain: list[float] = []
        t_aware: list[float] = []
        for target, seed in cases[:5]:
            plain.solve(target, seed), aware.solve(target, seed)
        for target, seed in cases:
            for solver, bucket in ((plain, t_plain), (aware, t_aware)):
                start = clock()
                solver.solve(target, seed)
                bucket.append(clock() - start)
        if not cases:
            return float("nan"), float("nan")
        return statistics.median(t_plain) * 1e6, statistics.median(t_aware) * 1e6

    p_free, a_free = medians(free_cases)
    p_blocked, a_blocked = medians(blocked_cases)
    print(
        f"{name:<11} {len(free_cases):>5} {p_free:>10.1f} {a_free:>10.1f} {a_free / p_free:>6.2f}"
        f"   {len(blocked_cases):>5} {p_blocked:>10.1f} {a_blocked:>10.1f}",
        flush=True,
    )
    return a_free / p_free


def main(argv: list[str] | None = None) -> int:
    """Print the benchmark table; exit 0."""
    args = get_argument_parser().parse_args(argv)
    print(f"cell: {CELL}; {os.cpu_count()} cores; medians of single calls [us/configuration]")
    print(
        f"{'robot':<11} {'pairs':>5} {'colliding':>9} {'check':>10} {'pin':>9} {'ratio':>6} "
        f"{'bare':>7} {'ratio':>6} {'loop':>9} {'batch':>10} {'speed':>6} {'mujoco':>11}"
    )
    worst_check, worst_batch = 0.0, float("inf")
    for name in ROWS:
        ratio, speedup = bench_row(name, args.configurations, args.batch)
        worst_check, worst_batch = max(worst_check, ratio), min(worst_batch, speedup)
    print(
        f"worst check/pin {worst_check:.2f} (goal <= {CHECK_GOAL}); "
        f"worst batch speed-up {worst_batch:.2f}x (goal >= {BATCH_GOAL}x)"
    )
    print(
        "collision-aware IK vs the plain call, medians [us/solve]; free: the plain nearest answer "
        "is collision-free (judged); blocked: it collides (extra search, not judged)"
    )
    print(
        f"{'robot':<11} {'free':>5} {'plain':>10} {'aware':>10} {'ratio':>6}   "
        f"{'blkd':>5} {'plain':>10} {'aware':>10}"
    )
    worst_ik = max(ik_row(name, args.ik_targets) for name in IK_ROWS)
    print(f"worst collision-aware IK / plain {worst_ik:.2f}x (goal <= {IK_GOAL}x)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
