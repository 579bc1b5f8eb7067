"""JSON output of every command: strict JSON, never ``NaN`` or ``Infinity``.

Python's :mod:`json` writes a non-finite float as ``NaN``, ``Infinity`` or ``-Infinity``, which
no JSON parser but Python's and JavaScript's ``eval`` reads. Every command writes its ``--json``
records and its ``--stdin`` answers with :func:`dumps`: a record of finite numbers is encoded as
it is, in one pass; one with a non-finite number (a witness point of coal's at a scene object
1e308 m away, say) has each such number written as ``null``, and one warning line names the
fields (``kin check: warning: --json: 3 non-finite numbers written as null: ...``).
"""

from __future__ import annotations

import json
import math
import warnings
from typing import Any

from dh2urdf.output_text import counted

__all__ = ["NonFiniteWarning", "dumps"]

#: Fields named in the warning (then "...").
_NAMED_FIELDS = 4

# Fresh trees of dicts and lists made by the commands: no cycles to look for.
_STRICT = json.JSONEncoder(check_circular=False, allow_nan=False)


class NonFiniteWarning(UserWarning):
    """A JSON record held a non-finite number, written as ``null``."""


def _finite_or_null(value: Any, path: str = "", found: list[str] | None = None) -> Any:
    """``value`` with every non-finite float replaced by None, the fields' paths in ``found``.

    Args:
        value: A tree of dicts, lists, tuples and scalars.
        path: The path of ``value`` in the record (``"contacts[0].point_a_m"``).
        found: Where the paths of the replaced numbers are added.
    """
    if isinstance(value, float):
        if math.isfinite(value):
            return value
        if found is not None:
            found.append(path or "the record")
        return None
    if isinstance(value, dict):
        return {
            key: _finite_or_null(item, f"{path}.{key}" if path else str(key), found)
            for key, item in value.items()
        }
    if isinstance(value, (list, tuple)):
        return [
            _finite_or_null(item, f"{path}[{index}]", found) for index, item in enumerate(value)
        ]
    return value


def dumps(record: Any) -> str:
    """``record`` as strict JSON (one line); non-finite numbers as ``null``, with one warning.

    Raises:
        TypeError: A value JSON cannot hold (a bug of the caller, not bad input).
    """
    try:
        return _STRICT.encode(record)
    except ValueError:  # a NaN or an infinity somewhere: rare, so looked for only now
        pass
    found: list[str] = []
    text = _STRICT.encode(_finite_or_null(record, "", found))
    named = ", ".join(found[:_NAMED_FIELDS]) + (", ..." if len(found) > _NAMED_FIELDS else "")
    warnings.warn(
        f"--json: {counted(len(found), 'non-finite number')} written as null: {named}",
        NonFiniteWarning,
        stacklevel=2,
    )
    return text
