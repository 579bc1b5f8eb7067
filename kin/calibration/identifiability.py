"""Which parameters the measurements determine: a rank decision on the regressor, stated.

The regressor (the Jacobian of the weighted residuals with respect to every parameter, at the
starting point) has its columns scaled to unit norm and is orthogonalised column by column in a
fixed order of preference (a QR factorisation without pivoting): the measurement frame and the
tool or markers first (unknown by nature), then the joints' DH values; the zero offsets of joints
that never move in the data are not estimated (a fixed angle there is the geometry's). A column whose part outside the span of the columns kept before it is less than
``tolerance`` (relative, default 1e-3) is unidentifiable: its parameter stays at its starting
value and the report names the combination of kept parameters that absorbs it (the least-squares
coefficients of its column on theirs), such as the first joint's zero against the base's yaw or
the last row's ``d`` against the tool's offset along the last joint's axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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
    basis = np.zeros((regressor.shape[0], 0))
    kept: list[int] = []
    dropped: list[int] = []
    for index in order:
        if norms[index] == 0.0:
            dropped.append(index)
            continue
        column = regressor[:, index] / norms[index]
        for _ in range(2):  # twice is enough (Kahan, Parlett)
            column = column - basis @ (basis.T @ column)
        size = float(np.linalg.norm(column))
        if size < tolerance:
            dropped.append(index)
            continue
        basis = np.column_stack([basis, column / size])
        kept.append(index)
    dropped += list(excluded)
    mask = np.zeros(len(names), dtype=bool)
    mask[kept] = True
    scaled = regressor[:, kept] / norms[kept]
    singular = np.linalg.svd(scaled, compute_uv=False) if kept else np.ones(1)
    condition = float(singular[0] / singular[-1]) if singular[-1] > 0 else float("inf")
    out = []
    for index in dropped:
        combination: tuple[tuple[str, float], ...] = ()
        if norms[index] > 0.0 and kept:
            coef = np.linalg.lstsq(regressor[:, kept], regressor[:, index], rcond=None)[0]
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
