"""Read back a joint path written by ``kin path --json`` (SI units), e.g. to preview it.

The file is one JSON object with ``q`` (list of joint vectors [rad] / [m], as its ``q_units``
say), optionally ``robot`` (the name it was computed for) and ``t_s`` (sample times [s], when
the path was timed).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass

import numpy as np

from dh2urdf.input_file import read_input
from dh2urdf.long_numbers import long_integer_problem

from .exceptions import PathError


@dataclass(frozen=True)
class JointPath:
    """Joint vectors along a path and their times.

    Attributes:
        q: Joint vectors, shape (K, nq) [rad] for revolute, [m] for prismatic joints.
        t: Sample times [s], shape (K,), increasing; None when the path was not timed.
        robot: Name of the robot the path was computed for ("" when the file does not say).
    """

    q: np.ndarray
    t: np.ndarray | None
    robot: str


def read_joint_path(path: str | os.PathLike[str], dof: int) -> JointPath:
    """The joint path of a ``kin path --json`` file, checked for ``dof`` joints.

    Args:
        path: The JSON file.
        dof: Number of joints of the robot the path is for.

    Returns:
        The joint path (at least two finite joint vectors of ``dof`` values).

    Raises:
        PathError: The file cannot be read, is not such JSON, or holds no usable path; the
            message names the file and the field.
    """
    name = os.fspath(path)
    text = ""
    try:
        text = read_input(path).decode("utf-8")
        document = json.loads(text)
    except OSError as err:
        raise PathError(f"{name}: cannot read the path file ({err.strerror})", "path") from err
    except (UnicodeDecodeError, ValueError) as err:
        if (too_long := long_integer_problem(text, err)) is not None:
            raise PathError(f"{name}: {too_long}", "path") from None
        raise PathError(f"{name}: not JSON ({err}); write it with kin path --json", "path") from err
    if not isinstance(document, dict) or "q" not in document:
        raise PathError(f"{name}: no 'q' list of joint vectors (kin path --json output)", "q")
    try:
        q = np.array(document["q"], dtype=float)
    except (TypeError, ValueError) as err:
        raise PathError(f"{name}: 'q' is not a list of numeric joint vectors ({err})", "q") from err
    if q.ndim != 2 or q.shape[1] != dof or len(q) < 2:
        robot = document.get("robot")
        made_for = f" (the file's path is for '{robot}')" if robot else ""
        raise PathError(
            f"{name}: 'q' must hold at least 2 joint vectors of {dof} values, got shape "
            f"{q.shape}{made_for}",
            "q",
        )
    if not np.isfinite(q).all():
        raise PathError(f"{name}: 'q' holds a non-finite value (a stopped path?)", "q")
    units = document.get("q_units")
    if units is not None and any(unit not in ("rad", "m") for unit in units):
        raise PathError(f"{name}: 'q_units' must be rad / m (SI), got {units}", "q_units")
    t = None
    if document.get("t_s") is not None:
        t = np.array(document["t_s"], dtype=float)
        if t.shape != (len(q),) or not np.isfinite(t).all() or (np.diff(t) <= 0.0).any():
            raise PathError(f"{name}: 't_s' must be {len(q)} increasing times [s]", "t_s")
    robot = document.get("robot", "")
    return JointPath(q=q, t=t, robot=str(robot) if robot is not None else "")


def animation_frames(
    joint_path: JointPath, duration: float, fps: float = 30.0
) -> tuple[np.ndarray, float]:
    """Joint vectors at a fixed frame rate, for an animation that plays in real time.

    A timed path is resampled at ``fps`` over its own times (joint values interpolated linearly
    between samples); an untimed one is spread evenly over ``duration`` [s], sample by sample.

    Returns:
        The frames, shape (F, nq), and the time between two frames [s].
    """
    if joint_path.t is None:
        return joint_path.q, duration / (len(joint_path.q) - 1)
    t = joint_path.t - joint_path.t[0]
    count = max(2, int(math.ceil(t[-1] * fps)) + 1)
    grid = np.linspace(0.0, t[-1], count)
    frames = np.column_stack([np.interp(grid, t, column) for column in joint_path.q.T])
    return frames, float(t[-1]) / (count - 1)
