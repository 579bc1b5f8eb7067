"""The weighted residuals of a parameter vector and their least-squares fit (scipy).

Residuals per row: the predicted minus the measured point of every marker, divided by the
position noise ``sigma_p`` [m]; for full poses also the rotation ``log(R_measured^T R_predicted)``
(the rotation vector of the error on SO(3), never a difference of roll-pitch-yaw angles) divided
by the rotation noise ``sigma_r`` [rad]. The fit is scipy's ``least_squares``: Levenberg-Marquardt
(``method="lm"``) for the plain squared loss, the trust-region reflective method with a robust
loss (``soft_l1``, ``huber``, ``cauchy``: residuals beyond 3 noise units count less) otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from .measurements import Measurements
from .parameters import ParameterModel
from .prediction import predict

LOSSES = ("linear", "soft_l1", "huber", "cauchy")
#: Residual [noise units] beyond which a robust loss counts a residual less.
ROBUST_SCALE = 3.0


@dataclass(frozen=True)
class Noise:
    """Measurement noise that weights the residuals.

    Attributes:
        position: Standard deviation of a measured coordinate [m].
        rotation: Standard deviation of a measured rotation about each axis [rad].
    """

    position: float = 5e-5
    rotation: float = float(np.radians(0.01))


def _inverse_right_jacobian(phi: np.ndarray) -> np.ndarray:
    """SO(3) ``J_r^-1`` of rotation vectors (N, 3): ``log(R Exp(d)) = phi + J_r^-1 d``."""
    theta = np.linalg.norm(phi, axis=1)
    k = np.zeros((len(phi), 3, 3))
    k[:, 0, 1], k[:, 0, 2], k[:, 1, 2] = -phi[:, 2], phi[:, 1], -phi[:, 0]
    k = k - np.transpose(k, (0, 2, 1))
    small = theta < 1e-6
    t = np.where(small, 1.0, theta)
    coef = np.where(small, 1.0 / 12.0, 1.0 / t**2 - (1.0 + np.cos(t)) / (2.0 * t * np.sin(t)))
    return np.eye(3) + 0.5 * k + coef[:, None, None] * (k @ k)


def rotation_errors(measured: np.ndarray, predicted: np.ndarray) -> np.ndarray:
    """``log(R_measured^T R_predicted)`` as rotation vectors (N, 3) [rad]."""
    return Rotation.from_matrix(np.transpose(measured, (0, 2, 1)) @ predicted).as_rotvec()


def residuals(
    model: ParameterModel,
    x: np.ndarray,
    data: Measurements,
    noise: Noise,
    jacobian: bool = False,
) -> tuple[np.ndarray, np.ndarray | None]:
    """Weighted residuals (M,) and, if asked, their Jacobian (M, P) [1 per parameter unit]."""
    pred = predict(model, x, data.q, jacobian)
    parts = [((pred.points - data.points) / noise.position).reshape(len(data.q), -1)]
    rows = []
    if jacobian:
        assert pred.point_jacobian is not None
        rows.append(pred.point_jacobian.reshape(len(data.q), -1, len(x)) / noise.position)
    if data.rotations is not None:
        assert pred.rotations is not None
        error = rotation_errors(data.rotations, pred.rotations)
        parts.append(error / noise.rotation)
        if jacobian:
            assert pred.rotation_jacobian is not None
            body = np.transpose(pred.rotations, (0, 2, 1)) @ pred.rotation_jacobian
            rows.append(_inverse_right_jacobian(error) @ body / noise.rotation)
    r = np.concatenate(parts, axis=1).ravel()
    J = np.concatenate(rows, axis=1).reshape(len(r), len(x)) if jacobian else None
    return r, J


@dataclass(frozen=True)
class FitResult:
    """A fitted parameter vector.

    Attributes:
        x: All parameters (the fixed ones at their starting values).
        evaluations: Residual evaluations the solver made.
        cost: Half the sum of squared weighted residuals at ``x`` [1].
    """

    x: np.ndarray
    evaluations: int
    cost: float


def fit(
    model: ParameterModel,
    x0: np.ndarray,
    free: np.ndarray,
    data: Measurements,
    noise: Noise,
    loss: str = "linear",
) -> FitResult:
    """Fit the ``free`` parameters (mask) of ``x0`` to ``data`` (scipy ``least_squares``)."""
    index = np.flatnonzero(free)
    base = np.array(x0, dtype=float)

    def full(z: np.ndarray) -> np.ndarray:
        x = base.copy()
        x[index] = z
        return x

    def fun(z: np.ndarray) -> np.ndarray:
        return residuals(model, full(z), data, noise)[0]

    def jac(z: np.ndarray) -> np.ndarray:
        J = residuals(model, full(z), data, noise, jacobian=True)[1]
        assert J is not None
        return J[:, index]

    method = "lm" if loss == "linear" else "trf"
    kwargs = {} if loss == "linear" else {"loss": loss, "f_scale": ROBUST_SCALE}
    result = least_squares(
        fun,
        base[index],
        jac,
        method=method,
        x_scale="jac",
        ftol=1e-12,
        xtol=1e-12,
        gtol=1e-12,
        max_nfev=200,
        **kwargs,
    )
    return FitResult(full(result.x), int(result.nfev), float(result.cost))
