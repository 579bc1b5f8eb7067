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

import math
import time
from collections.abc import Callable, Generator, Mapping
from contextlib import closing
from pathlib import Path
from typing import Any

import numpy as np

from ..exceptions import KinError
from ..robot_model import RobotModel
from .cluster import reach_client
from .grid import (
    MAX_ORIENTATIONS,
    MAX_VOXELS_PER_SIDE,
    ReachMap,
    smallest_voxel,
    super_fibonacci_rotations,
)
from .grid import voxel_grid as _grid
from .map_file import load_reach_map, save_reach_map
from .plot import PLOT_SLICES, plot_reach_map

# The map's grid, file and picture live in grid, map_file and plot (this folder); their
# names stay importable from here.
__all__ = [
    "MAX_ORIENTATIONS",
    "MAX_VOXELS_PER_SIDE",
    "PLOT_SLICES",
    "ReachMap",
    "count_reached",
    "load_reach_map",
    "plot_reach_map",
    "reachability_map",
    "save_reach_map",
    "smallest_voxel",
    "super_fibonacci_rotations",
]

#: Poses per chunk by default (a tenth of a second to a second of closed-form batch IK: the
#: progress bar moves at least that often).
DEFAULT_CHUNK_POSES = 10_000


def count_reached(
    robot: RobotModel,
    centers: np.ndarray,
    rotations: np.ndarray,
    timeout: float | None = None,
    collisions: Any = None,
) -> np.ndarray:
    """Orientations reached at each centre (one chunk): int (N,) for centres (N, 3) [m].

    With ``collisions`` (a :class:`kin.collision.CollisionChecker`, or a ``(scene, srdf,
    padding, hold)`` it is built from) an orientation counts only with a collision-free answer, judged
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
    from ..ik.batch_solve import free_joint_answers, solve_batch
    from ..ik.dispatch import get_solver

    n, k = len(centers), len(rotations)
    positions = np.repeat(centers, k, axis=0)
    frames = np.broadcast_to(rotations, (n, k, 3, 3)).reshape(n * k, 3, 3)
    seeds = np.zeros((n * k, robot.nq))
    solver = get_solver(robot)
    checker = _checker(robot, collisions)
    if solver.closed_form_kinds:  # a closed form: the vectorized batch
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
    """A checker: None, a checker as given, or built from ``(scene, srdf, padding, hold)``."""
    if collisions is None or not isinstance(collisions, tuple):
        return collisions
    from ..collision import CollisionChecker, load_collision_model

    scene, srdf, padding, hold = collisions
    model = load_collision_model(robot, scene=scene, srdf=srdf, padding=padding, hold=hold)
    return CollisionChecker(model)


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
    from ..ik.numeric.solver import STAGES
    from ..ik.targets.target import PoseTarget

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
    from ..ik.targets.target import PoseTarget

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

    from dh2urdf.stop_signals import raise_lost_stop

    from ..workspace.run import dask_faults

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
            raise_lost_stop()  # a SIGTERM whose raise a GC callback swallowed
            yield future.result()


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
    hold: Mapping[str, float] | None = None,
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
        hold: Joints off the chain -> held values [rad or m] (with ``scene`` or ``srdf``;
            :func:`kin.collision.load_collision_model`).

    Raises:
        KinError: An arm of fewer than 6 joints, a voxel that is not a positive finite length
            or needs more than :data:`MAX_VOXELS_PER_SIDE` per side, orientations not in 1 ..
            :data:`MAX_ORIENTATIONS`, a bad ``chunk_poses``, or Dask missing or unreachable.
        RunFaultError: The Dask scheduler was lost during the run (or a chunk killed every
            worker it ran on).
    """
    from ..ik.reach import arm_reach

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
        from ..collision import CollisionChecker, load_collision_model

        model = load_collision_model(robot, scene=scene, srdf=srdf, padding=padding, hold=hold)
        collisions = (scene, srdf, padding, hold)  # rebuilt by each Dask worker from the files
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
    with reach_client(scheduler) as client:
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
    held = f"; joints off the chain held at: {model.held.note}" if model.held.note else ""
    return (
        f"collision-free answers only ({', '.join(against)}; {len(model.pairs)} pairs, "
        f"padding {model.padding:g} m{held})"
    )
