"""Named joint vectors of a DH table: its ``[states]`` section (``ready``, ``home``...).

Table syntax (revolute values in the table's ``angle_unit``, prismatic ones in its
``length_unit``; one value per row, within the row's limits)::

    [states]
    ready = [0.0, -45.0, 0.0, -135.0, 0.0, 90.0, 45.0]

As an SRDF's ``<group_state>``: ``kin`` takes a name where it takes a seed (``--seed-q ready``,
:mod:`kin.named_states`).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from .dh_table import DHRow, NamedState
from .exceptions import TableError
from .quoted_input import quoted
from .table_values import number as _number

__all__ = ["STATE_NAME", "parse_states"]

#: A state's name: a letter, then letters, digits, ``_`` or ``-`` (what a command line passes).
STATE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_-]*")


def parse_states(
    path: str, data: Any, rows: Sequence[DHRow], meters: float, radians: float
) -> tuple[NamedState, ...]:
    """The table's ``[states]``, in the file's order.

    Raises:
        TableError: ``[states]`` is not a table, a name is not a word, a vector has not one
            finite number per row, or a value lies outside its row's limits.
    """
    if not isinstance(data, dict):
        raise TableError(path, f"expected a [states] table, got {quoted(data)}", None, "states")
    states = []
    for name, values in data.items():
        field = f"states.{name}"
        if not STATE_NAME.fullmatch(name) or name.lower() in ("inf", "infinity", "nan"):
            raise TableError(
                path,
                "a state's name is a letter, then letters, digits, '_' or '-' (not a number)",
                None,
                quoted(field)[1:-1],
            )
        if not isinstance(values, list) or len(values) != len(rows):
            raise TableError(
                path,
                f"expected {len(rows)} values, one per joint row, got {quoted(values)}",
                None,
                field,
            )
        q = []
        for row, value in zip(rows, values, strict=True):
            factor = radians if row.joint_type == "revolute" else meters
            si = _number(path, value, None, field) * factor
            if not row.lower - 1e-12 <= si <= row.upper + 1e-12:
                raise TableError(
                    path,
                    f"{value!r} is outside the limits of joint row {row.index} ({row.name})",
                    None,
                    field,
                )
            q.append(min(max(si, row.lower), row.upper))
        states.append(NamedState(name, tuple(q)))
    return tuple(states)
