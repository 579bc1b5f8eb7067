"""Input quoted in an error message, cut short: a line of 1.5 million numbers is not repeated.

Every message that shows a value the user gave (``got [...]``) shows :func:`quoted` of it: its
``repr`` with long lists, long strings and deep nesting elided (:mod:`reprlib`, which never
recurses without bound), then cut to :data:`QUOTE_LIMIT` characters and ``"..."``.
"""

from __future__ import annotations

import reprlib
from typing import Any

__all__ = ["QUOTE_LIMIT", "quoted"]

#: Most characters of a value shown in a message (then ``"..."``).
QUOTE_LIMIT = 80

_REPR = reprlib.Repr()
_REPR.maxlevel = 3
_REPR.maxlist = _REPR.maxtuple = _REPR.maxset = _REPR.maxdict = 12
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = QUOTE_LIMIT


def quoted(value: Any, limit: int = QUOTE_LIMIT) -> str:
    """``repr(value)``, at most ``limit`` characters then ``"..."`` (lists and nesting elided).

    Args:
        value: What the user gave (a number, string, list, table...).
        limit: Most characters kept [characters].
    """
    try:
        text = _REPR.repr(value)
    except Exception:  # noqa: BLE001 - a hostile __repr__: say what it is
        text = f"<{type(value).__name__}>"
    return text if len(text) <= limit else text[:limit] + "..."
