"""On-disk cache of seed tables, one file per table hash, in the user's cache directory.

A seed table costs a few hundred milliseconds to sample and index; a command-line solve must not
pay that on every process start. The arrays are stored with ``np.savez`` under
``$XDG_CACHE_HOME/dh-kinematics`` (else ``~/.cache/dh-kinematics``), named by a hash of
everything the table depends on: the table's SI rows (joint types, DH parameters, limits), the
base and tool transforms, the model's joint limits and tool frame, the table size, the random
seed, the grid parameters and the package version. A file is written to a temporary name and moved into place with
``os.replace`` (a reader never sees half a file); a damaged file is rebuilt with one warning naming
it, and a path that is not a regular file (a FIFO, directory or device, or a link to one) is
skipped with one warning, never opened in a way that waits. Each read touches the file's time of
last modification; after each write the oldest files go until the folder holds at most
:data:`MAX_BYTES` (least recently used first). ``DH_KINEMATICS_NO_CACHE=1`` turns the cache off.
"""

from __future__ import annotations

import hashlib
import logging
import os
import stat
import tempfile
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .sampling_box import sampling_limits

if TYPE_CHECKING:
    from kin import RobotModel

logger = logging.getLogger(__name__)

#: Bumped when the cached arrays change meaning.
FORMAT = 3

#: Number of seed tables sampled in this process (a test sees whether the cache was used).
BUILDS = 0

#: Most bytes the cache folder's seed tables take after a write [B]; the least recently used go.
MAX_BYTES = 100_000_000

#: The names of the cache's files, and of those being written (left by a process killed meanwhile).
_PATTERNS = ("seed_table_*.npz", ".seed_table_*.npz")


class CacheWarning(UserWarning):
    """A seed-table cache file that could not be used (damaged, or not a regular file)."""


@dataclass(frozen=True)
class CacheUsage:
    """The cache's files: where, how many, how large.

    Attributes:
        folder: The cache folder.
        files: Number of files (of :func:`clear`: every entry removed, whatever its kind).
        size: Their total size [B] (of the regular files).
        others: What those that are not regular files are (``"FIFO"``, ``"symbolic link"``...).
    """

    folder: Path
    files: int
    size: int
    others: tuple[str, ...] = ()


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
        part: tuple[object, ...] = (
            row.joint_type,
            row.a,
            row.alpha,
            row.d,
            row.theta,
            row.lower,
            row.upper,
        )
        # A reversed joint or a tilted row (Hayati's beta) changes the samples; the keys of the
        # other rows stay as they were.
        if row.direction != 1:
            part = (*part, "direction", row.direction)
        parts.append(part if row.beta == 0.0 else (*part, "beta", row.beta))
    digest = hashlib.sha256(repr(parts).encode())
    for matrix in (table.T_world_base, table.T_last_tool):
        digest.update(np.ascontiguousarray(matrix, dtype=float).tobytes())
    digest.update(np.ascontiguousarray(robot.model.lowerPositionLimit, dtype=float).tobytes())
    digest.update(np.ascontiguousarray(robot.model.upperPositionLimit, dtype=float).tobytes())
    # A long rail's samples come from a cut box (.sampling_box): keyed apart from the tables
    # drawn over its whole travel; every other arm's key stays as it was.
    lower, upper = robot.model.lowerPositionLimit, robot.model.upperPositionLimit
    draw_lower, draw_upper = sampling_limits(table, lower, upper)
    if draw_lower is not lower:
        digest.update(b"sampling box")
        digest.update(np.ascontiguousarray(draw_lower, dtype=float).tobytes())
        digest.update(np.ascontiguousarray(draw_upper, dtype=float).tobytes())
    return digest.hexdigest()[:32]


def enabled() -> bool:
    """Whether the cache is on (``DH_KINEMATICS_NO_CACHE`` not set to 1, true or yes)."""
    return os.environ.get("DH_KINEMATICS_NO_CACHE", "") not in ("1", "true", "yes")


def path_for(key: str) -> Path:
    """The cache file of ``key``."""
    return cache_dir() / f"seed_table_{key}.npz"


def exists(robot: RobotModel, size: int, rotation_weight: float, cell_size: float) -> bool:
    """Whether the seed table of ``robot`` (seed 0, the weight [m/rad] and cell [m]) is on disk."""
    if not enabled():
        return False
    key = table_key(robot, size, 0, rotation_weight, cell_size)
    return path_for(key).is_file()


#: The arrays a cached seed table holds (:func:`kin.ik.numeric.seed_table.build_seed_table`).
CACHED_ARRAYS = ("q", "positions", "rotations", "keys", "spans", "owners", "origin", "shape")


def load(key: str) -> dict[str, np.ndarray] | None:
    """The cached arrays of ``key`` (:data:`CACHED_ARRAYS`), or None (no file, unusable).

    A damaged file, or a path that is not a regular file, gives one :class:`CacheWarning`
    naming it; a file read is touched (its time of last use, for :func:`trim`).
    """
    if not enabled():
        return None
    path = path_for(key)
    try:
        # Non-blocking: a FIFO put at the path does not wait for a writer; then checked by fstat.
        flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
        handle = os.open(path, flags)
    except FileNotFoundError:
        return None
    except OSError as err:  # a directory (on some systems), no permission
        _warn(f"seed table cache {path} not readable ({err.strerror}): rebuilding the table")
        return None
    mode = os.fstat(handle).st_mode
    if not stat.S_ISREG(mode):
        os.close(handle)
        _warn(
            f"seed table cache {path} is a {_kind(mode)}, not a file: skipped (remove it to "
            f"cache the table)"
        )
        return None
    with os.fdopen(handle, "rb") as file:
        try:
            with np.load(file, allow_pickle=False) as stored:
                arrays = {name: stored[name] for name in CACHED_ARRAYS}
        except Exception as err:  # noqa: BLE001 - any damage: rebuild
            _warn(f"seed table cache {path} is damaged ({_short(err)}): rebuilding the table")
            return None
    if not _consistent(arrays):
        _warn(f"seed table cache {path} is damaged (inconsistent arrays): rebuilding the table")
        return None
    try:
        os.utime(path)  # used now: trimmed last
    except OSError:
        pass
    return arrays


def _warn(message: str) -> None:
    """One :class:`CacheWarning` (a command shows it as one line on stderr)."""
    warnings.warn(message, CacheWarning, stacklevel=3)


def _short(err: Exception) -> str:
    """An exception as one short phrase."""
    text = " ".join(str(err).split()) or type(err).__name__
    return text if len(text) <= 80 else text[:77] + "..."


def _kind(mode: int) -> str:
    """What a non-regular file of ``mode`` is, in words."""
    if stat.S_ISLNK(mode):
        return "symbolic link"
    if stat.S_ISFIFO(mode):
        return "FIFO"
    if stat.S_ISDIR(mode):
        return "directory"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "device"
    if stat.S_ISSOCK(mode):
        return "socket"
    return "special file"


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
    """Write the arrays of ``key`` atomically, then :func:`trim` the folder.

    A failure (read-only home), or a path taken by something other than a regular file (left
    as it is), is only logged.
    """
    if not enabled():
        return
    directory = cache_dir()
    path = path_for(key)
    try:
        if path.exists() and not path.is_file():
            logger.info("seed table cache not written: %s is not a regular file", path)
            return
        directory.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(prefix=".seed_table_", suffix=".npz", dir=directory)
        try:
            with os.fdopen(handle, "wb") as file:
                np.savez(file, **arrays)  # type: ignore[arg-type]
            os.replace(temporary, path)
        except BaseException:
            os.unlink(temporary)
            raise
    except OSError as err:
        logger.info("seed table cache not written to %s: %s", directory, err)
        return
    trim()


def _entries(directory: Path) -> list[tuple[Path, os.stat_result]]:
    """Every entry of ``directory`` named as the cache's files, of any kind, with its ``lstat``."""
    found = []
    for pattern in _PATTERNS:
        for path in directory.glob(pattern):
            try:
                found.append((path, path.lstat()))
            except OSError:  # removed meanwhile
                continue
    return found


def _files(directory: Path) -> list[tuple[Path, os.stat_result]]:
    """The cache's regular files in ``directory`` (links and others left alone), with their stats."""
    return [item for item in _entries(directory) if stat.S_ISREG(item[1].st_mode)]


def usage() -> CacheUsage:
    """The cache folder, its number of files and their total size [B]."""
    directory = cache_dir()
    files = _files(directory)
    return CacheUsage(directory, len(files), sum(status.st_size for _, status in files))


def trim(max_bytes: int | None = None) -> int:
    """Remove the least recently used seed tables until the rest take at most ``max_bytes``.

    The most recently used file is kept whatever its size; files being written by another
    process (temporary names) are left alone.

    Args:
        max_bytes: Most bytes the tables keep [B] (default :data:`MAX_BYTES`).

    Returns:
        The number of files removed.
    """
    limit = MAX_BYTES if max_bytes is None else max_bytes
    tables = [item for item in _files(cache_dir()) if item[0].name.startswith("seed_table_")]
    tables.sort(key=lambda item: item[1].st_mtime, reverse=True)  # newest first
    kept = 0
    removed = 0
    for rank, (path, status) in enumerate(tables):
        kept += status.st_size
        if rank == 0 or kept <= limit:
            continue
        try:
            path.unlink()
            removed += 1
        except FileNotFoundError:  # another process trimmed it
            pass
        except OSError as err:
            logger.info("seed table cache %s not removed: %s", path, err)
    if removed:
        logger.info("seed table cache trimmed: %d file(s) removed", removed)
    return removed


def clear() -> CacheUsage:
    """Remove what holds the cache's names: tables, temporaries, and whatever was put there.

    A FIFO, socket, device node or symbolic link at a cache file's name is removed too (the
    entry only: a link's target is left), counted and named by kind; a directory at such a name
    is left, with one :class:`CacheWarning` naming it. Nothing else in the folder is touched.

    Returns:
        What was removed: the folder, the number of entries, the regular files' total size [B]
        and the kinds of the others.

    Raises:
        OSError: An entry that could not be removed (no permission).
    """
    directory = cache_dir()
    files = removed = 0
    others: list[str] = []
    for path, status in _entries(directory):
        if stat.S_ISDIR(status.st_mode):
            _warn(f"{path} is a directory, not a seed table: left as it is")
            continue
        try:
            path.unlink()
        except FileNotFoundError:
            continue
        files += 1
        if stat.S_ISREG(status.st_mode):
            removed += status.st_size
        else:
            others.append(_kind(status.st_mode))
    return CacheUsage(directory, files, removed, tuple(others))
