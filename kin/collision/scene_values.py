"""The values of a scene file (TOML or a MoveIt PlanningScene): numbers, sizes, coordinates.

Each reader takes the file (``where``), the field's name as the file writes it (``box[0].size``,
``world.collision_objects[2].primitives[0].dimensions``) and the value as parsed, and returns a
float in SI units or raises one :class:`~kin.exceptions.CollisionModelError` line naming both.
Sizes and coordinates obey :mod:`.bounds`; ``slip`` is the unit hint a value beyond those
bounds adds (a millimetre read as a meter, :mod:`.scene_units`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from dh2urdf.quoted_input import quoted

from ..exceptions import CollisionModelError
from .bounds import MAX_COORDINATE, MAX_SIZE, check_coordinates, check_sizes

__all__ = ["coordinate", "factor", "length", "number", "vector"]


def number(where: str, field: str, value: Any) -> float:
    """A finite number (an angle, a scale factor, a length before its unit)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CollisionModelError(where, f"{field}: {quoted(value)} is not a number")
    try:
        result = float(value)
    except OverflowError:  # an integer beyond float range
        raise CollisionModelError(where, f"{field}: the number is not finite") from None
    if not math.isfinite(result):
        raise CollisionModelError(where, f"{field}: {value!r} is not finite")
    return result


def length(where: str, field: str, value: Any, meters: float = 1.0, slip: str = "") -> float:
    """A size [m] in (0, MAX_SIZE]: ``value`` [unit] times ``meters`` [m/unit]."""
    size = number(where, field, value) * meters
    if size > MAX_SIZE and slip:
        raise CollisionModelError(
            where, f"{field}: {size:g} m is more than the {MAX_SIZE:g} m a shape measures: {slip}"
        )
    check_sizes(where, field, (size,))
    return size


def coordinate(where: str, field: str, value: Any, meters: float = 1.0, slip: str = "") -> float:
    """A coordinate [m] within +-MAX_COORDINATE: ``value`` [unit] times ``meters`` [m/unit]."""
    place = number(where, field, value) * meters
    if abs(place) > MAX_COORDINATE and slip:
        raise CollisionModelError(
            where, f"{field}: {place:g} m is beyond +-{MAX_COORDINATE:g} m from the origin: {slip}"
        )
    check_coordinates(where, field, (place,))
    return place


def factor(where: str, field: str, value: Any) -> float:
    """A scale factor > 0."""
    result = number(where, field, value)
    if result <= 0.0:
        raise CollisionModelError(where, f"{field}: {result!r} must be > 0")
    return result


def vector(
    where: str, field: str, value: Any, read: Callable[[str, str, Any], float], size: int = 3
) -> np.ndarray:
    """``size`` values, each read by ``read`` (as :func:`length`, :func:`coordinate`...)."""
    if not isinstance(value, list) or len(value) != size:
        raise CollisionModelError(
            where, f"{field}: {quoted(value)} is not a list of {size} numbers"
        )
    return np.array([read(where, f"{field}[{i}]", v) for i, v in enumerate(value)])
