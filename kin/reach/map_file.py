"""A reachability map on disk: ``.npz`` written whole or not at all, and read back checked."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from dh2urdf.input_file import open_input

from ..exceptions import KinError
from .grid import ReachMap

__all__ = ["MAX_REACH_MAP_BYTES", "load_reach_map", "save_reach_map", "write_whole"]

#: Largest reach map file read [bytes]: 1 GiB, four times a 1 cm map of a 2 m cube (8 million
#: voxels, about 250 MB of arrays before compression); more is not a file kin reach wrote.
MAX_REACH_MAP_BYTES = 2**30


def write_whole(path: Path, write: Callable[[Any], object]) -> None:
    """Put what ``write`` writes on a binary handle at ``path``, whole or not at all.

    Raises:
        OutputFileError: ``path`` is not a regular file or a new path in a writable folder.
        OutputWriteError: The disk filled up part-way; the old file is unchanged.
    """
    from dh2urdf.output_file import write_atomic

    from ..exceptions import OutputFileError, OutputWriteError

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
    write_whole(path, lambda handle: np.savez_compressed(handle, **arrays))
    return path


def load_reach_map(path: str | Path) -> ReachMap:
    """The :class:`ReachMap` written by :func:`save_reach_map`.

    Raises:
        KinError: Not such a file (missing, unreadable, or arrays missing or misshapen).
    """
    try:
        handle = open_input(path, MAX_REACH_MAP_BYTES)
    except FileNotFoundError as err:
        raise KinError(f"{path}: no such file; write one with kin reach -o FILE.npz") from err
    except OSError as err:
        raise KinError(f"{path}: cannot read the reachability map ({err.strerror})") from err
    try:
        with handle:
            if handle.read(4) != b"PK\x03\x04":
                raise ValueError("not a .npz file")
            handle.seek(0)
            with np.load(handle, allow_pickle=False) as data:
                fields = {name: data[name] for name in data.files}
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
