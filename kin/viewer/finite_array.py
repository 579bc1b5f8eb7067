"""The check of a value a viewer is given: a float array of a stated shape, every entry finite."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .exceptions import ViewerInputError

__all__ = ["finite_array"]


def finite_array(values: npt.ArrayLike, shape: tuple[int, ...], what: str) -> np.ndarray:
    """``values`` as a float array of ``shape``, all finite.

    Args:
        values: The value given (a point, a rotation matrix).
        shape: The shape it must have.
        what: What it is, for the message ("target position").

    Raises:
        ViewerInputError: Not numbers, another shape or a non-finite value.
    """
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError) as err:
        raise ViewerInputError(f"{what} must be numbers, got {values!r}") from err
    if array.shape != shape or not np.all(np.isfinite(array)):
        raise ViewerInputError(f"{what} must be finite numbers of shape {shape}, got {values!r}")
    return array
