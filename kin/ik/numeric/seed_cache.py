"""On-disk cache of seed tables, one file per table hash, in the user's cache directory.

A seed table costs a few hundred milliseconds to sample and index; a command-line solve must not
pay that on every process start. The arrays are stored with ``np.savez`` under
``$XDG_CACHE_HOME/dh-kinematics`` (else ``~/.cache/dh-kinematics``), named by a hash of
everything the table depends on: the table's SI rows (joint types, DH parameters, limits), the
base and tool transforms, the model's joint limits and tool frame, the table size, the random
seed, the grid parameters and the package version. A file is written to a temporary name and moved into place with
``os.replace`` (a reader never sees half a file); an unreadable, corrupt or mismatching file is
ignored and the table rebuilt. ``DH_KINEMATICS_NO_CACHE=1`` turns the cache off.
"""

from __future__ import annotations

import hashlib
import logging
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from kin import RobotModel

logger = logging.getLogger(__name__)

#: Bumped when the cached arrays change meaning.
FORMAT = 3

#: Number of seed tables sampled in this process (a test sees whether the cache was used).
BUILDS = 0


def cache_dir() -> Path:
    """``$XDG_CACHE_HOME/dh-kinematics``, else ``~/.cache/dh-kinematics``."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "dh-kinematics"


def table_key(
    robot: RobotModel, size: int, seed: int, rotation_weight: float, cell_size: float
) -> str:
    """Hex digest naming the cache file of a seed table."""
    from kin import __version__

    table = robot.table
    parts: list[object] = [FORMAT, __version__, table.convention, robot.tool_frame, size, seed]
    parts.append(cell_size)
    parts.append(rotation_weight)
    for row in table.rows:
        part = (row.joint_type, row.a, row.alpha, row.d, row.theta, row.lower, row.upper)
        # A reversed joint changes the samples; the keys of the other rows stay as they were.
        parts.append(part if row.direction == 1 else (*part, "direction", row.direction))
    digest = hashlib.sha256(repr(parts).encode())
    for matrix in (table.T_world_base, table.T_last_tool):
        digest.update(np.ascontiguousarray(matrix, dtype=float).tobytes())
    digest.update(np.ascontiguousarray(robot.model.lowerPositionLimit, dtype=float).tobytes())
    digest.update(np.ascontiguousarray(robot.model.upperPositionLimit, dtype=float).tobytes())
    return digest.hexdigest()[:32]


def _enabled() -> bool:
    return os.environ.get("DH_KINEMATICS_NO_CACHE", "") not in ("1", "true", "yes")


def path_for(key: str) -> Path:
    """The cache file of ``key``."""
    return cache_dir() / f"seed_table_{key}.npz"


def exists(robot: RobotModel, size: int, rotation_weight: float, cell_size: float) -> bool:
    """Whether the seed table of ``robot`` (seed 0, the weight [m/rad] and cell [m]) is on disk."""
    if not _enabled():
        return False
    key = table_key(robot, size, 0, rotation_weight, cell_size)
    return path_for(key).is_file()


#: The arrays a cached seed table holds (:func:`kin.ik.numeric.seed_table.build_seed_table`).
CACHED_ARRAYS = ("q", "positions", "rotations", "keys", "spans", "owners", "origin", "shape")


def load(key: str) -> dict[str, np.ndarray] | None:
    """The cached arrays of ``key`` (:data:`CACHED_ARRAYS`), or None (no file, unreadable, corrupt)."""
    if not _enabled():
        return None
    path = path_for(key)
    try:
        with np.load(path, allow_pickle=False) as stored:
            arrays = {name: stored[name] for name in CACHED_ARRAYS}
    except FileNotFoundError:
        return None
    except Exception as err:  # noqa: BLE001 - any damage: rebuild
        logger.info("seed table cache %s unreadable (%s): rebuilding", path, err)
        return None
    if not _consistent(arrays):
        logger.info("seed table cache %s inconsistent: rebuilding", path)
        return None
    return arrays


def _consistent(arrays: dict[str, np.ndarray]) -> bool:
    """Shapes that fit together (a truncated or hand-edited file fails here)."""
    q, positions, rotations = arrays["q"], arrays["positions"], arrays["rotations"]
    n = len(q)
    spans, owners = arrays["spans"], arrays["owners"]
    return (
        q.ndim == 2
        and positions.shape == (n, 3)
        and rotations.shape == (n, 9)
        and spans.ndim == 2
        and spans.shape[1:] == (2,)
        and arrays["keys"].shape == (len(spans),)
        and arrays["origin"].shape == (3,)
        and arrays["shape"].shape == (3,)
        and owners.ndim == 1
        and (not owners.size or (0 <= int(owners.min()) and int(owners.max()) < n))
        and (not spans.size or (0 <= int(spans.min()) and int(spans.max()) <= len(owners)))
        and bool(np.isfinite(positions).all())
    )


def store(key: str, arrays: dict[str, np.ndarray]) -> None:
    """Write the arrays of ``key`` atomically; a failure (read-only home) is only logged."""
    if not _enabled():
        return
    directory = cache_dir()
    try:
        directory.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(prefix=".seed_table_", suffix=".npz", dir=directory)
        try:
            with os.fdopen(handle, "wb") as file:
                np.savez(file, **arrays)  # type: ignore[arg-type]
            os.replace(temporary, path_for(key))
        except BaseException:
            os.unlink(temporary)
            raise
    except OSError as err:
        logger.info("seed table cache not written to %s: %s", directory, err)
