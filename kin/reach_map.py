"""Reachability (capability) maps: per voxel, the fraction of tool orientations the arm reaches.

The capability map of Zacharias et al. (2007), Reuleaux's reachability map in ROS: the box
around the base origin that holds the arm's reach is cut into cubic voxels; at each voxel's
centre the tool is asked to take each of K orientations spread evenly over SO(3), and the
voxel's *index* is the fraction of them with a verified IK answer inside the joint limits
(:func:`kin.ik.solve_batch`: every success is on target and within the limits). Users read it
to place an arm's base: high indices mark where the tool can work from many directions.

- **Orientations**: a super-Fibonacci spiral of K unit quaternions (Alexa, "Super-Fibonacci
  Spirals: Fast, Low-Discrepancy Sampling of SO(3)", CVPR 2022): deterministic, so the set
  depends on K only (no seed to pass; the same K gives the same rotations on every machine), and
  evenly spread over SO(3) for every K, with no pole or seam.
- **Grid**: voxel centres at ``origin + voxel * (i - k, j - k, l - k)`` for i, j, l in
  ``0 .. 2k``, where ``origin`` is the base origin (of ``T_world_base``, world frame) and k the
  smallest integer with ``(k + 1/2) voxel >= maximum reach``: the cube of centres holds the sphere
  of :attr:`kin.ik.reach.Reach.maximum` (:func:`kin.ik.reach.arm_reach`), the bounding box of
  every tool point. Voxels whose centre lies beyond that distance get index 0 without solving.
- **Chunks**: the voxels within reach are solved in chunks of about ``chunk_poses`` poses; a
  chunk's counts do not depend on where it runs, so the map is the same in this process and on
  a Dask cluster (``scheduler``: an address, ``"local-cluster:N"`` or a ``distributed.Client``;
  Dask is imported only then). Closed-form arms (a 6R arm's, a 7R arm's free-joint scan) are
  exact (1e-9 m and rad); an arm without one is solved pose by pose by its numeric solver,
  bounded by a number of starts (the time budget ``timeout`` is only a cap), so a loaded
  machine gives the same map.

Lengths in meters, the world frame throughout.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable, Generator, Iterator
from contextlib import closing, contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .exceptions import KinError
from .robot_model import RobotModel

__all__ = [
    "ReachMap",
    "count_reached",
    "load_reach_map",
    "plot_reach_map",
    "reachability_map",
    "save_reach_map",
    "super_fibonacci_rotations",
]

#: Poses per chunk by default (a tenth of a second to a second of closed-form batch IK: the
#: progress bar moves at least that often).
DEFAULT_CHUNK_POSES = 10_000
#: Most voxels along a side of the grid.
MAX_VOXELS_PER_SIDE = 256
#: Most orientations per voxel.
MAX_ORIENTATIONS = 100_000
#: Horizontal slices drawn by :func:`plot_reach_map`.
PLOT_SLICES = 4

# Alexa's constants: sqrt(2) and the real root of psi^4 = psi + 4.
_PHI = math.sqrt(2.0)
_PSI = 1.533751168755204288118041


@dataclass(frozen=True, eq=False)
class ReachMap:
    """The reachability map of a robot (world frame, SI units).

    Attributes:
        robot: Robot name.
        voxel_m: Voxel edge [m].
        centers_m: Voxel centres (n, n, n, 3) [m], indexed (x, y, z): ``centers_m[i, j, l]`` is
            the centre of the voxel i-th along x, j-th along y, l-th along z.
        index: Fraction of the orientations reached at each centre (n, n, n), in [0, 1].
        orientations: K, the tool orientations tried per voxel.
        rotations: Those orientations ``R_world_tool`` (K, 3, 3).
        max_reach_m: The arm's maximum reach from the base origin [m] (voxels whose centre is
            farther have index 0, unsolved).
        time_s: Wall time of the computation [s].
        collisions: ``""`` (poses and limits only), or what the answers were checked against:
            ``"collision-free answers only (scene cell.toml; 42 pairs, padding 0 m)"``.
    """

    robot: str
    voxel_m: float
    centers_m: np.ndarray
    index: np.ndarray
    orientations: int
    rotations: np.ndarray
    max_reach_m: float
    time_s: float
    collisions: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The map as a JSON-ready dict (SI units).

        Keys ``voxel_m``, ``centers_m``, ``index``, ``orientations`` (K), ``time_s``, and
        ``robot``, ``max_reach_m``.
        """
        return {
            "robot": self.robot,
            "voxel_m": self.voxel_m,
            "centers_m": self.centers_m.tolist(),
            "index": self.index.tolist(),
            "orientations": self.orientations,
            "max_reach_m": self.max_reach_m,
            "time_s": self.time_s,
            "collisions": self.collisions,
        }


def super_fibonacci_rotations(count: int) -> np.ndarray:
    """``count`` rotation matrices (count, 3, 3) spread evenly over SO(3) (super-Fibonacci).

    Raises:
        KinError: ``count`` is not a positive integer.
    """
    if not isinstance(count, int | np.integer) or count < 1:
        raise KinError(f"orientations must be a positive integer, got {count!r}")
    s = np.arange(count) + 0.5
    r = np.sqrt(s / count)
    big_r = np.sqrt(1.0 - s / count)
    alpha = 2.0 * math.pi * s / _PHI
    beta = 2.0 * math.pi * s / _PSI
    # Unit quaternions (w, x, y, z).
    w, x = r * np.sin(alpha), r * np.cos(alpha)
    y, z = big_r * np.sin(beta), big_r * np.cos(beta)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def smallest_voxel(reach: float) -> float:
    """The smallest voxel edge [m] whose grid holds ``reach`` [m] in :data:`MAX_VOXELS_PER_SIDE`."""
    return 2.0 * reach / (MAX_VOXELS_PER_SIDE - 1)


def _grid(origin: np.ndarray, voxel: float, reach: float) -> np.ndarray:
    """Voxel centres (n, n, n, 3) [m] of the cube around ``origin`` that holds ``reach``."""
    half = max(0, math.ceil(reach / voxel - 0.5))
    side = 2 * half + 1
    if side > MAX_VOXELS_PER_SIDE:
        raise KinError(
            f"voxel {voxel:g} m needs {side} voxels per side for a reach of {reach:.4g} m; at "
            f"most {MAX_VOXELS_PER_SIDE}: give a voxel of at least {smallest_voxel(reach):.3g} m"
        )
    steps = (np.arange(side) - half) * voxel
    axes = np.meshgrid(steps, steps, steps, indexing="ij")
    return np.stack(axes, axis=-1) + origin


def count_reached(
    robot: RobotModel,
    centers: np.ndarray,
    rotations: np.ndarray,
    timeout: float | None = None,
    collisions: Any = None,
) -> np.ndarray:
    """Orientations reached at each centre (one chunk): int (N,) for centres (N, 3) [m].

    With ``collisions`` (a :class:`kin.collision.CollisionChecker`, or a ``(scene, srdf,
    padding)`` it is built from) an orientation counts only with a collision-free answer, judged
    by ``in_collision_batch``: every valid branch of a vectorized closed form, else the one
    answer each pose's solve gives (a colliding one is not searched further).

    Every pose of the chunk is solved from q = 0 by the arm's closed form when it has one: a
    vectorized one (:func:`kin.ik.solve_batch`), or the free-joint form of a 7R arm, as the
    first stage of its numeric solver takes it: the free joint scanned from the seed for every
    pose at once (:func:`kin.ik.batch_solve.free_joint_answers`, compiled, in threads), then for
    the poses left the free joints of the nearest seed-table samples (:func:`_sample_scans`).
    The later numeric stages, which run until a deadline, are not tried: they found none of 400
    poses the first stage left on a Panda map, at 50 ms each. An arm with neither is solved pose
    by pose by its numeric solver, bounded by :data:`NUMERIC_ATTEMPTS` starts per pose
    (``timeout`` [s] only a cap, :data:`NUMERIC_CAP` by default). Either way a busy machine
    gives the same count.
    """
    from .ik.batch_solve import free_joint_answers, solve_batch
    from .ik.dispatch import get_solver
    from .ik.numeric.solver import NumericIK

    n, k = len(centers), len(rotations)
    positions = np.repeat(centers, k, axis=0)
    frames = np.broadcast_to(rotations, (n, k, 3, 3)).reshape(n * k, 3, 3)
    seeds = np.zeros((n * k, robot.nq))
    solver = get_solver(robot)
    checker = _checker(robot, collisions)
    if not isinstance(solver, NumericIK):
        result = solve_batch(robot, positions, frames, seeds, all_branches=checker is not None)
        success, q = result.success, result.q
        if checker is not None and result.branches is not None:  # any free branch counts
            valid = result.branches.valid
            free = valid.copy()
            free[valid] = ~checker.in_collision_batch(result.branches.q[valid])
            return free.any(axis=1).reshape(n, k).sum(axis=1)
    elif (answers := free_joint_answers(solver, robot, positions, frames, seeds)) is not None:
        q = answers[0]
        success = ~np.isnan(q).any(axis=1)
        missed = np.flatnonzero(~success)
        success[missed], q[missed] = _sample_scans(solver, positions[missed], frames[missed])
    else:
        success, q = _numeric_success(solver, positions, frames, seeds, timeout)
    if checker is not None and success.any():
        success[success] = ~checker.in_collision_batch(q[success])
    return success.reshape(n, k).sum(axis=1)


def _checker(robot: RobotModel, collisions: Any) -> Any:
    """A collision checker: None, a checker as given, or built from ``(scene, srdf, padding)``."""
    if collisions is None or not isinstance(collisions, tuple):
        return collisions
    from .collision import CollisionChecker, load_collision_model

    scene, srdf, padding = collisions
    return CollisionChecker(load_collision_model(robot, scene=scene, srdf=srdf, padding=padding))


def _answers(results: list[Any], nq: int) -> tuple[np.ndarray, np.ndarray]:
    """(success (N,), q (N, nq) with NaN rows) of IK results: their first solution."""
    q = np.full((len(results), nq), np.nan)
    for i, result in enumerate(results):
        if result.success:
            q[i] = result.solutions[0].q
    return np.array([r.success for r in results], dtype=bool).reshape(-1), q


#: Starts (seed-table, random, QP) of the numeric solver per pose of an arm without a closed form.
NUMERIC_ATTEMPTS = 16
#: Wall-clock cap of one such numeric solve [s] (the work bound is :data:`NUMERIC_ATTEMPTS`).
NUMERIC_CAP = 2.0


def _sample_scans(
    solver: Any, positions: np.ndarray, frames: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per pose (N,), whether the free-joint closed form answers it from seed-table samples.

    The first stage of the numeric pipeline alone (:func:`kin.ik.numeric.free_joint.
    solve_free_joint`, without a seed: the seed's scan is done), work-bounded: the nearest
    sample's free joints scanned, then those of the next few samples. ``solver`` is the arm's
    numeric solver; its later stages are dropped here.
    """
    from .ik.numeric.solver import STAGES
    from .ik.target import PoseTarget

    solver.stages = STAGES[:1]
    results = [
        solver.solve(PoseTarget(p, r), None, timeout=NUMERIC_CAP) for p, r in zip(positions, frames)
    ]
    return _answers(results, solver.robot.nq)


def _numeric_success(
    solver: Any,
    positions: np.ndarray,
    frames: np.ndarray,
    seeds: np.ndarray,
    timeout: float | None,
) -> tuple[np.ndarray, np.ndarray]:
    """Per pose (N,), whether the numeric solver answers it within its work bound, and q."""
    from .ik.target import PoseTarget

    cap = NUMERIC_CAP if timeout is None else timeout
    results = [
        solver.solve(PoseTarget(p, r), q, timeout=cap, max_attempts=NUMERIC_ATTEMPTS)
        for p, r, q in zip(positions, frames, seeds)
    ]
    return _answers(results, seeds.shape[1])


def _in_process(
    robot: RobotModel,
    chunks: list[np.ndarray],
    rotations: np.ndarray,
    timeout: float | None,
    collisions: Any = None,
) -> Generator[tuple[int, np.ndarray], None, None]:
    checker = _checker(robot, collisions)  # once: the shapes are loaded a single time
    for i, chunk in enumerate(chunks):
        yield i, count_reached(robot, chunk, rotations, timeout, checker)


def _numbered(i: int, *args: Any) -> tuple[int, np.ndarray]:
    return i, count_reached(*args)


def _on_dask(
    client: Any,
    robot: RobotModel,
    chunks: list[np.ndarray],
    rotations: np.ndarray,
    timeout: float | None,
    collisions: Any = None,
) -> Generator[tuple[int, np.ndarray], None, None]:
    from distributed import as_completed

    from .workspace_run import dask_faults

    futures: list[Any] = []
    with dask_faults(client, futures):  # a lost scheduler: RunFaultError, not a traceback
        # A key of its own (not the data's hash): two maps of one robot on one scheduler (two
        # clients) must not share it, or the first one's release loses the second one's copy.
        [shared] = client.scatter([robot], broadcast=True, hash=False)
        futures.extend(
            client.submit(_numbered, i, shared, chunk, rotations, timeout, collisions, pure=False)
            for i, chunk in enumerate(chunks)
        )
        for future in as_completed(futures):
            yield future.result()


@contextmanager
def _client(scheduler: Any) -> Iterator[Any]:
    """The Dask client ``scheduler`` names (None for this process), closed on exit if opened."""
    if scheduler is None or scheduler == "local":
        yield None
        return
    if not isinstance(scheduler, str):
        yield scheduler  # a distributed.Client of the caller's
        return
    from .workspace_run import DASK_HINT, _ignore_sigint, dask_client

    if not scheduler.startswith("local-cluster:"):
        with dask_client(scheduler) as client:
            yield client
        return
    workers = scheduler.removeprefix("local-cluster:")
    if not workers.isdigit() or int(workers) < 1:
        raise KinError(
            f"scheduler {scheduler!r}: give local-cluster:N with N a positive number of workers"
        )
    try:
        import dask
        from distributed import Client, LocalCluster
    except ImportError as err:
        raise KinError(f"--scheduler needs Dask: {DASK_HINT}") from err
    # Dask's nannies start workers with MALLOC_TRIM_THRESHOLD_=65536, which fixes glibc's mmap
    # threshold: every NumPy temporary of the batch IK is then mapped and faulted in afresh
    # (measured: 3x to 6x slower chunks). The workers of this cluster keep glibc's default,
    # and go without the statistical profiler (a sampling thread; no dashboard to show it).
    environ = dask.config.get("distributed.nanny.pre-spawn-environ", default={})
    kept = {k: v for k, v in environ.items() if k != "MALLOC_TRIM_THRESHOLD_"}
    settings = {
        "distributed.nanny.pre-spawn-environ": kept,
        "distributed.worker.profile.enabled": False,
    }
    with dask.config.set(settings):
        cluster = LocalCluster(
            n_workers=int(workers),
            threads_per_worker=1,
            dashboard_address=None,
            processes=True,
            silence_logs=logging.CRITICAL,  # a task's error still reaches the caller
        )
        with cluster, Client(cluster) as client:
            client.run(_ignore_sigint)  # Ctrl-C is the parent's: no traceback per worker
            yield client


def reachability_map(
    robot: RobotModel,
    voxel: float,
    orientations: int,
    *,
    scheduler: Any = None,
    progress: Callable[[int, int], None] | None = None,
    chunk_poses: int | None = None,
    timeout: float | None = None,
    scene: str | Path | None = None,
    srdf: str | Path | None = None,
    padding: float = 0.0,
) -> ReachMap:
    """The :class:`ReachMap` of ``robot``.

    Args:
        robot: The robot.
        voxel: Voxel edge [m].
        orientations: K, tool orientations per voxel (super-Fibonacci over SO(3)).
        scheduler: None or ``"local"``: this process; a Dask scheduler address
            (``"tcp://host:8786"``), ``"local-cluster:N"`` (a LocalCluster of N worker
            processes, started and closed here) or a ``distributed.Client``: the chunks run there.
        progress: Called with (poses solved, poses to solve) as chunks finish.
        chunk_poses: Poses per chunk (whole voxels, at least one per chunk; default
            :data:`DEFAULT_CHUNK_POSES`).
        timeout: Wall-clock cap of each numeric solve of an arm without a closed form [s]
            (None: :data:`NUMERIC_CAP`); its work bound is :data:`NUMERIC_ATTEMPTS` starts.
        scene: A cell (TOML or URDF, :func:`kin.collision.load_collision_model`): with it, or
            with ``srdf``, only collision-free answers count (:func:`count_reached`).
        srdf: A MoveIt SRDF whose ``disable_collisions`` pairs are allowed.
        padding: Margin around every shape [m] (with ``scene`` or ``srdf``).

    Raises:
        KinError: An arm of fewer than 6 joints, a voxel that is not a positive finite length
            or needs more than :data:`MAX_VOXELS_PER_SIDE` per side, orientations not in 1 ..
            :data:`MAX_ORIENTATIONS`, a bad ``chunk_poses``, or Dask missing or unreachable.
        RunFaultError: The Dask scheduler was lost during the run (or a chunk killed every
            worker it ran on).
    """
    from .ik.reach import arm_reach

    if not (isinstance(voxel, int | float) and math.isfinite(voxel) and voxel > 0):
        raise KinError(f"voxel must be a positive length in m, got {voxel!r}")
    if not isinstance(orientations, int | np.integer) or not 1 <= orientations <= MAX_ORIENTATIONS:
        raise KinError(
            f"orientations must be an integer from 1 to {MAX_ORIENTATIONS:,}, got {orientations!r}"
        )
    if robot.nq < 6:  # its tool poses form at most a 5-dimensional set: every index is 0
        raise KinError(
            f"'{robot.name}' has {robot.nq} joints: it reaches a full tool pose only on a set of "
            "orientations of measure zero, so every voxel's index would be 0; a reachability map "
            "needs an arm of 6 or more joints"
        )
    chunk_poses = DEFAULT_CHUNK_POSES if chunk_poses is None else chunk_poses
    if not isinstance(chunk_poses, int) or chunk_poses < 1:
        raise KinError(f"chunk_poses must be a positive integer, got {chunk_poses!r}")
    start = time.perf_counter()
    collisions: Any = None
    note = ""
    if scene is not None or srdf is not None:
        from .collision import CollisionChecker, load_collision_model

        model = load_collision_model(robot, scene=scene, srdf=srdf, padding=padding)
        collisions = (scene, srdf, padding)  # rebuilt by each Dask worker from the files
        note = _collision_note(model, scene, srdf)
    reach = arm_reach(robot)
    centers = _grid(reach.origin, float(voxel), reach.maximum)
    rotations = super_fibonacci_rotations(int(orientations))
    flat = centers.reshape(-1, 3)
    inside = np.flatnonzero(np.linalg.norm(flat - reach.origin, axis=1) <= reach.maximum)
    per_chunk = max(1, chunk_poses // int(orientations))
    slices = [inside[i : i + per_chunk] for i in range(0, len(inside), per_chunk)]
    chunks = [flat[s] for s in slices]
    counts = np.zeros(len(flat), dtype=np.int64)
    total, done = len(inside) * int(orientations), 0
    if progress is not None:
        progress(0, total)  # at once: the first chunk may take seconds
    with _client(scheduler) as client:
        results = (
            _in_process(
                robot,
                chunks,
                rotations,
                timeout,
                None if collisions is None else CollisionChecker(model),
            )
            if client is None
            else _on_dask(client, robot, chunks, rotations, timeout, collisions)
        )
        with closing(results):  # on Ctrl-C the futures are cancelled here, not when collected
            for i, reached in results:
                counts[slices[i]] = reached
                done += len(slices[i]) * int(orientations)
                if progress is not None:
                    progress(done, total)
    return ReachMap(
        robot=robot.name,
        voxel_m=float(voxel),
        centers_m=centers,
        index=(counts / int(orientations)).reshape(centers.shape[:3]),
        orientations=int(orientations),
        rotations=rotations,
        max_reach_m=float(reach.maximum),
        time_s=time.perf_counter() - start,
        collisions=note,
    )


def _collision_note(model: Any, scene: str | Path | None, srdf: str | Path | None) -> str:
    """One line: the map counts collision-free answers only, against what."""
    against = [f"scene {Path(scene).name}"] if scene is not None else []
    against += [f"srdf {Path(srdf).name}"] if srdf is not None else []
    return (
        f"collision-free answers only ({', '.join(against)}; {len(model.pairs)} pairs, "
        f"padding {model.padding:g} m)"
    )


def _write_whole(path: Path, write: Callable[[Any], object]) -> None:
    """Put what ``write`` writes on a binary handle at ``path``, whole or not at all.

    Raises:
        OutputFileError: ``path`` is not a regular file or a new path in a writable folder.
        OutputWriteError: The disk filled up part-way; the old file is unchanged.
    """
    from dh2urdf.output_file import write_atomic

    from .exceptions import OutputFileError, OutputWriteError

    write_atomic(path, write, OutputFileError, OutputWriteError)


def save_reach_map(reach_map: ReachMap, path: str | Path) -> Path:
    """Write ``reach_map`` to ``path`` as ``.npz``, never half-written (a temporary file, renamed).

    The arrays: those of :meth:`ReachMap.to_dict`, and ``rotations`` (K, 3, 3).

    Raises:
        OutputFileError: ``path`` is a device, FIFO, socket or folder, or its folder is missing.
        OutputWriteError: The disk filled up part-way; a previous file is unchanged.
    """
    path = Path(path)
    arrays: dict[str, Any] = {
        "robot": np.array(reach_map.robot),
        "voxel_m": np.array(reach_map.voxel_m),
        "centers_m": reach_map.centers_m,
        "index": reach_map.index,
        "orientations": np.array(reach_map.orientations),
        "rotations": reach_map.rotations,
        "max_reach_m": np.array(reach_map.max_reach_m),
        "time_s": np.array(reach_map.time_s),
        "collisions": np.array(reach_map.collisions),
    }
    _write_whole(path, lambda handle: np.savez_compressed(handle, **arrays))
    return path


def load_reach_map(path: str | Path) -> ReachMap:
    """The :class:`ReachMap` written by :func:`save_reach_map`.

    Raises:
        KinError: Not such a file (missing, unreadable, or arrays missing or misshapen).
    """
    file = Path(path)
    try:
        with file.open("rb") as handle:
            zipped = handle.read(4) == b"PK\x03\x04"
        if not zipped:
            raise ValueError("not a .npz file")
        with np.load(file, allow_pickle=False) as data:
            fields = {name: data[name] for name in data.files}
    except FileNotFoundError as err:
        raise KinError(f"{path}: no such file; write one with kin reach -o FILE.npz") from err
    except (OSError, ValueError) as err:
        raise KinError(f"{path}: not a reachability map written by kin reach ({err})") from err
    try:
        centers, index = fields["centers_m"], fields["index"]
        if centers.ndim != 4 or centers.shape[3] != 3 or index.shape != centers.shape[:3]:
            raise KeyError("centers_m/index shapes")
        return ReachMap(
            robot=str(fields.get("robot", "")),
            voxel_m=float(fields["voxel_m"]),
            centers_m=centers.astype(float),
            index=index.astype(float),
            orientations=int(fields["orientations"]),
            rotations=fields.get("rotations", np.zeros((0, 3, 3))),
            max_reach_m=float(fields.get("max_reach_m", math.nan)),
            time_s=float(fields.get("time_s", math.nan)),
            collisions=str(fields.get("collisions", "")),
        )
    except (KeyError, TypeError, ValueError) as err:
        raise KinError(f"{path}: not a reachability map written by kin reach ({err})") from err


def plot_reach_map(
    reach_map: ReachMap, path: str | Path, unit: str = "m", slices: int = PLOT_SLICES
) -> Path:
    """Write ``slices`` horizontal (constant z) slices of the map to a figure, atomically.

    The slices are evenly spaced over the z range of voxels with a nonzero index; each shows the
    index as colour (one colour bar, 0 to 1) over x and y in ``unit``. The format follows the
    suffix (``.png``, ``.svg``, ``.pdf``); matplotlib is imported here, drawn on its Agg canvas.

    Raises:
        KinError: matplotlib is missing.
    """
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as err:
        raise KinError("pictures need matplotlib: pip install 'matplotlib>=3.7'") from err
    from dh2urdf.command_line import length_scale

    path = Path(path)
    scale = length_scale(unit)
    centers, index = reach_map.centers_m / scale, reach_map.index
    side = index.shape[2]
    layers = np.flatnonzero(index.reshape(-1, side).max(axis=0) > 0)
    lo, hi = (int(layers[0]), int(layers[-1])) if len(layers) else (0, side - 1)
    picks = sorted(set(np.linspace(lo, hi, slices + 2)[1:-1].round().astype(int).tolist()))
    v = reach_map.voxel_m / scale
    x, y = centers[:, 0, 0, 0], centers[0, :, 0, 1]
    extent = (x[0] - v / 2, x[-1] + v / 2, y[0] - v / 2, y[-1] + v / 2)
    figure = Figure(figsize=(4.2 * len(picks) + 1.2, 4.6), dpi=100, layout="constrained")
    FigureCanvasAgg(figure)
    image = None
    axes_list = figure.subplots(1, len(picks), squeeze=False)[0]
    for axes, layer in zip(axes_list, picks, strict=True):
        image = axes.imshow(
            index[:, :, layer].T,
            origin="lower",
            extent=extent,
            vmin=0.0,
            vmax=1.0,
            cmap="viridis",
            interpolation="nearest",
        )
        axes.set_title(f"z = {centers[0, 0, layer, 2]:.3g} {unit}")
        axes.set_xlabel(f"x [{unit}]")
        axes.set_ylabel(f"y [{unit}]")
        axes.set_aspect("equal")
    assert image is not None  # at least one slice
    label = "reachability index" + (", collision-free" if reach_map.collisions else "")
    figure.colorbar(image, ax=list(axes_list), shrink=0.85, label=label)
    figure.suptitle(
        f"{reach_map.robot}: reachability index ({reach_map.orientations} orientations, "
        f"{v:.3g} {unit} voxels)" + (f"\n{reach_map.collisions}" if reach_map.collisions else "")
    )
    kind = path.suffix.lower().lstrip(".") or "png"
    _write_whole(path, lambda handle: figure.savefig(handle, format=kind))
    return path
