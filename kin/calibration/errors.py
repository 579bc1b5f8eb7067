"""Errors of a calibrated (or nominal) arm against measurements: per row, summed as RMS and max."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fit import rotation_errors
from .measurements import Measurements
from .parameters import ParameterModel
from .prediction import predict


@dataclass(frozen=True, eq=False)
class Errors:
    """Errors of a model against measurements, per row.

    Attributes:
        position: Distance predicted - measured per row and marker (N, K) [m].
        rotation: Rotation angle of ``R_measured^T R_predicted`` per row (N,) [rad], or None.
    """

    position: np.ndarray
    rotation: np.ndarray | None

    def rms(self) -> tuple[float, float | None]:
        """Root mean square position [m] and rotation [rad] error."""
        rot = None if self.rotation is None else float(np.sqrt(np.mean(self.rotation**2)))
        return float(np.sqrt(np.mean(self.position**2))), rot

    def max(self) -> tuple[float, float | None]:
        """Largest position [m] and rotation [rad] error."""
        rot = None if self.rotation is None else float(self.rotation.max())
        return float(self.position.max()), rot


def errors(model: ParameterModel, x: np.ndarray, data: Measurements) -> Errors:
    """Position (and rotation) errors of parameters ``x`` on ``data``."""
    pred = predict(model, x, data.q)
    position = np.linalg.norm(pred.points - data.points, axis=2)
    rotation = None
    if data.rotations is not None:
        assert pred.rotations is not None
        rotation = np.linalg.norm(rotation_errors(data.rotations, pred.rotations), axis=1)
    return Errors(position, rotation)
