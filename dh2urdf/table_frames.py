"""The ``[base]`` and ``[tool]`` sections of a DH table file as 4x4 transforms.

Three forms, in the table's units: ``xyz`` + ``rpy``, ``xyz`` + ``quat_wxyz`` (W X Y Z, unit: the
form the tables read from URDFs write, exact where roll-pitch-yaw is not) or a DH-style row
``a``/``alpha``/``d``/``theta`` in the table's convention. Errors name the file and field.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .dh_table import dh_link_transform
from .exceptions import TableError
from .quoted_input import quoted
from .table_values import length as _length
from .table_values import number as _number
from .transforms import xyz_rpy
from .units import angle_to_radians

__all__ = ["fixed_transform"]


def fixed_transform(
    path: str, data: Any, key: str, convention: str, meters: float, radians: float
) -> np.ndarray:
    """``[base]`` or ``[tool]`` (``key``) as a 4x4 transform, in the table's units.

    xyz + rpy, xyz + quat_wxyz, or a DH-style row a/alpha/d/theta; ``meters`` and ``radians``
    are the scales of the table's length and angle units.

    Raises:
        TableError: Another form, or a value that is not a finite number in range.
    """
    if not isinstance(data, dict):
        raise TableError(path, "expected a table ([base] / [tool])", None, key)
    dh_keys = {"a", "alpha", "d", "theta"}
    if "quat_wxyz" in data and set(data) <= {"xyz", "quat_wxyz"}:
        return _xyz_quaternion(path, data, key, meters)
    if set(data) <= {"xyz", "rpy"}:
        xyz = data.get("xyz", [0.0, 0.0, 0.0])
        rpy = data.get("rpy", [0.0, 0.0, 0.0])
        values: list[tuple[float, float, float]] = []
        for sub, vec, scale in (("xyz", xyz, meters), ("rpy", rpy, radians)):
            if not isinstance(vec, list) or len(vec) != 3:
                raise TableError(
                    path, f"expected a list of 3 numbers, got {quoted(vec)}", None, f"{key}.{sub}"
                )
            if sub == "xyz":
                x, y, z = (_length(path, v, None, f"{key}.xyz", meters) for v in vec)
            else:
                x, y, z = (
                    angle_to_radians(_number(path, v, None, f"{key}.rpy"), scale) for v in vec
                )
            values.append((x, y, z))
        return xyz_rpy(values[0], values[1])
    if set(data) <= dh_keys:
        p = {k: _number(path, data.get(k, 0.0), None, f"{key}.{k}") for k in dh_keys}
        return dh_link_transform(
            convention,  # type: ignore[arg-type]
            _length(path, p["a"], None, f"{key}.a", meters),
            angle_to_radians(p["alpha"], radians),
            _length(path, p["d"], None, f"{key}.d", meters),
            angle_to_radians(p["theta"], radians),
        )
    raise TableError(
        path,
        "give either xyz/rpy, xyz/quat_wxyz or a DH-style row a/alpha/d/theta, not "
        + ", ".join(sorted(data)),
        None,
        key,
    )


def _xyz_quaternion(path: str, data: dict[str, Any], key: str, meters: float) -> np.ndarray:
    """``xyz`` [length_unit] and a unit quaternion ``quat_wxyz`` (W X Y Z) as a 4x4 transform.

    The quaternion is exact where roll-pitch-yaw is not (near pitch +-90 deg), so the tables
    read from URDFs (:mod:`.urdf_to_dh`) write it.
    """
    xyz = data.get("xyz", [0.0, 0.0, 0.0])
    quat = data["quat_wxyz"]
    for sub, vec, size in (("xyz", xyz, 3), ("quat_wxyz", quat, 4)):
        if not isinstance(vec, list) or len(vec) != size:
            raise TableError(
                path, f"expected a list of {size} numbers, got {quoted(vec)}", None, f"{key}.{sub}"
            )
    x, y, z = (_length(path, v, None, f"{key}.xyz", meters) for v in xyz)
    w, qx, qy, qz = (_number(path, v, None, f"{key}.quat_wxyz") for v in quat)
    norm = math.sqrt(w * w + qx * qx + qy * qy + qz * qz)
    if not abs(norm - 1.0) < 1e-6:
        raise TableError(
            path,
            f"expected a unit quaternion (W X Y Z), got norm {norm:.6g}",
            None,
            f"{key}.quat_wxyz",
        )
    w, qx, qy, qz = w / norm, qx / norm, qy / norm, qz / norm
    out = np.eye(4)
    out[:3, :3] = [
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * w), 2 * (qx * qz + qy * w)],
        [2 * (qx * qy + qz * w), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * w)],
        [2 * (qx * qz - qy * w), 2 * (qy * qz + qx * w), 1 - 2 * (qx * qx + qy * qy)],
    ]
    out[:3, 3] = (x, y, z)
    return out
