"""Which parameters the measurements determine: a rank decision on the regressor, stated.

The regressor (the Jacobian of the weighted residuals with respect to every parameter, at the
starting point) has its columns scaled to unit norm and orthogonalised one by one (Gram-Schmidt,
twice: a QR factorisation without pivoting) in a fixed order of preference: the measurement frame
and the tool or markers first (unknown by nature), then the joints' DH values; the zero offsets of
joints that never move in the data are not estimated (a fixed angle there is the geometry's). A
column whose part outside the span of the columns kept before it is less than ``tolerance``
(relative, default 1e-3) is unidentifiable: its parameter stays at its starting value and the
report names the combination of kept parameters that absorbs it (the least-squares coefficients
of its column on theirs, from the factorisation's R), such as the first joint's zero against the
base's yaw or the last row's ``d`` against the tool's offset along the last joint's axis. The
condition number is that of the kept scaled columns (R's singular values).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

#: Relative size of a scaled column's new part below which its parameter is not identifiable.
RANK_TOLERANCE = 1e-3
#: Share of a combination's terms shown (relative contribution).
SHOWN_SHARE = 0.05


@dataclass(frozen=True)
class Unidentifiable:
    """A parameter the measurements do not determine.

    Attributes:
        name: The parameter.
        combination: ``(other parameter, coefficient)`` whose sum moves the measurements as a
            unit change of this one does (coefficients in the units' ratio, e.g. m/rad).
        reason: Why, in words (``"joint 'x' never moves in the data"``), or ``""``.
    """

    name: str
    combination: tuple[tuple[str, float], ...]
    reason: str = ""


@dataclass(frozen=True, eq=False)
class Identifiability:
    """The rank decision.

    Attributes:
        identifiable: Mask over the parameters (P,).
        unidentifiable: The others, in the order of preference, with what absorbs them.
        condition_number: Of the column-scaled regressor of the identifiable parameters [1].
        tolerance: The relative tolerance used [1].
    """

    identifiable: np.ndarray
    unidentifiable: tuple[Unidentifiable, ...]
    condition_number: float
    tolerance: float

    @property
    def rank(self) -> int:
        """Number of identifiable parameters."""
        return int(self.identifiable.sum())


def identify(
    regressor: np.ndarray,
    names: tuple[str, ...],
    order: list[int],
    tolerance: float = RANK_TOLERANCE,
    reasons: dict[str, str] | None = None,
    excluded: tuple[int, ...] = (),
) -> Identifiability:
    """Decide the identifiable parameters of ``regressor`` (M, P), preferring ``order``'s first.

    Args:
        regressor: Jacobian of the weighted residuals (M, P).
        names: Parameter names (P,).
        order: Parameter indices, most preferred first; indices left out are not estimated.
        tolerance: Relative size of a column's new part below which it is dropped [1].
        reasons: Words to give for some parameters when they are dropped.
        excluded: Parameters not estimated whatever their columns (a still joint's zero
            offset: a fixed angle that data of one joint value cannot tell from the geometry);
            listed as unidentifiable with what absorbs them.
    """
    norms = np.linalg.norm(regressor, axis=0)
    size_max = len(order)
    basis = np.zeros((regressor.shape[0], size_max))  # Q of the kept scaled columns
    upper = np.zeros((size_max, size_max))  # their R: scaled kept columns = Q R
    kept: list[int] = []
    dropped: list[int] = []
    for index in order:
        if norms[index] == 0.0:
            dropped.append(index)
            continue
        k = len(kept)
        column = regressor[:, index] / norms[index]
        for _ in range(2):  # twice is enough (Kahan, Parlett)
            part = basis[:, :k].T @ column
            upper[:k, k] += part
            column = column - basis[:, :k] @ part
        size = float(np.linalg.norm(column))
        if size < tolerance:
            upper[:k, k] = 0.0
            dropped.append(index)
            continue
        basis[:, k] = column / size
        upper[k, k] = size
        kept.append(index)
    dropped += list(excluded)
    mask = np.zeros(len(names), dtype=bool)
    mask[kept] = True
    k = len(kept)
    R = upper[:k, :k]
    # the scaled columns' singular values are R's (Q has orthonormal columns)
    singular = np.linalg.svd(R, compute_uv=False) if k else np.ones(1)
    condition = float(singular[0] / singular[-1]) if singular[-1] > 0 else float("inf")
    out = []
    explained = [i for i in dropped if norms[i] > 0.0] if k else []
    coefficients: dict[int, np.ndarray] = {}
    if explained:
        # least squares of each dropped scaled column on the kept ones: R y = Q^T c
        scaled = regressor[:, explained] / norms[explained]
        y = scipy.linalg.solve_triangular(R, basis[:, :k].T @ scaled)
        coefficients = dict(
            zip(explained, (y * norms[explained] / np.asarray(norms)[kept, None]).T)
        )
    for index in dropped:
        combination: tuple[tuple[str, float], ...] = ()
        if index in coefficients:
            coef = coefficients[index]
            share = np.abs(coef) * norms[kept] / norms[index]
            terms = [
                (names[kept[j]], float(coef[j]))
                for j in np.argsort(-share)
                if share[j] >= SHOWN_SHARE
            ]
            combination = tuple(terms[:4])
        reason = (reasons or {}).get(
            names[index], "" if norms[index] > 0.0 else "no effect on the measurements"
        )
        out.append(Unidentifiable(names[index], combination, reason))
    return Identifiability(mask, tuple(out), condition, tolerance)
