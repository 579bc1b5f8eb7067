"""Checked values of a DH table file: finite numbers, bounded lengths, text XML can carry.

Every check raises :class:`TableError` naming the file, the joint row and the field, so that a
table which loads always gives finite link transforms and finite forward kinematics (lengths at
most ``MAX_LENGTH`` [m], angles finite) and a URDF that XML can carry.
"""

from __future__ import annotations

import math
import re
from typing import Any

from .exceptions import TableError
from .quoted_input import quoted

#: Largest length a table may give, after unit scaling [m] (a, d, base/tool xyz, radius,
#: prismatic limits). Anything longer is a typo and would overflow the link transforms.
MAX_LENGTH = 1e6
#: Largest mass of a link [kg].
MAX_MASS = 1e6
#: Largest revolute limit a table may give [rad] (160,000 turns): sampling inside the limits
#: stays finite (1e308 overflows it); a joint without limits is ``continuous = true``.
MAX_ANGLE = 1e6


def length(path: str, value: Any, row: int | None, key: str, meters: float) -> float:
    """A table length scaled to [m], finite and at most MAX_LENGTH in magnitude."""
    scaled = number(path, value, row, key) * meters
    if not math.isfinite(scaled) or abs(scaled) > MAX_LENGTH:
        raise TableError(
            path,
            f"must be a finite length below {MAX_LENGTH:g} m in magnitude, got {quoted(value)} "
            "(check the value and the table's length_unit)",
            row,
            key,
        )
    return scaled


def positive(path: str, value: Any, row: int, key: str, scale: float, bound: float) -> float:
    """A positive, finite value scaled by ``scale``, at most ``bound``."""
    scaled = number(path, value, row, key) * scale
    if not (0.0 < scaled <= bound):
        raise TableError(
            path, f"must be positive and at most {bound:g}, got {quoted(value)}", row, key
        )
    return scaled


def number(path: str, value: Any, row: int | None, key: str) -> float:
    """``value`` as a float, or a TableError if it is not a finite number (bools are not)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TableError(path, f"expected a number, got {quoted(value)}", row, key)
    if not math.isfinite(value):
        raise TableError(path, f"expected a finite number, got {quoted(value)}", row, key)
    return float(value)


# Characters XML 1.0 cannot carry (control characters, surrogates, U+FFFE/U+FFFF).
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def xml_text(path: str, value: str, row: int | None, key: str) -> str:
    """``value`` unchanged, or a TableError if the URDF (XML) cannot carry it."""
    bad = _NOT_XML.search(value)
    if bad:
        raise TableError(
            path, f"contains the character {bad.group()!r}, which XML cannot carry", row, key
        )
    return value


def check_keys(
    path: str, data: dict[str, Any], allowed: set[str], row: int | None, what: str
) -> None:
    """Refuse a field of ``data`` not in ``allowed``, naming the first unknown one (``what``: where)."""
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise TableError(
            path,
            f"unknown field in {what}; allowed fields: {', '.join(sorted(allowed))}",
            row,
            quoted(unknown[0])[1:-1],
        )
