"""Integers longer than Python converts: one line naming the place, not a traceback.

Python (3.11, and 3.10 from 3.10.7) refuses to turn a string of more than
``sys.get_int_max_str_digits()`` digits (4300 by default) into an ``int``: :mod:`tomllib` and
:mod:`json` then raise a bare :class:`ValueError` whose message advises calling
``sys.set_int_max_str_digits()``, which is advice for a programmer, not for the author of a file.
:func:`long_integer_problem` finds the number in the text and says where it is.
"""

from __future__ import annotations

import re
import sys

__all__ = ["long_integer_problem"]


def _digit_limit() -> int:
    """Python's integer-string limit [digits] (0: no limit, before 3.10.7)."""
    get = getattr(sys, "get_int_max_str_digits", None)
    return int(get()) if get is not None else 0


def long_integer_problem(text: str, err: ValueError) -> str | None:
    """Why ``text`` could not be read when ``err`` is Python's integer-string limit, else None.

    Args:
        text: The file's text (TOML, JSON).
        err: What the reader raised.

    Returns:
        ``"line L, column C: an integer of N digits, more than the 4300 ..."``, or None when
        ``err`` is another error.
    """
    if "integer string conversion" not in str(err):
        return None
    limit = _digit_limit() or 4300
    found = re.search(r"\d(?:_?\d){" + str(limit) + ",}", text)  # TOML allows 1_000 separators
    if found is None:
        return f"an integer of more than {limit} digits, more than Python reads; shorten it"
    line = text.count("\n", 0, found.start()) + 1
    column = found.start() - (text.rfind("\n", 0, found.start()) + 1) + 1
    digits = sum(c.isdigit() for c in found.group())
    return (
        f"line {line}, column {column}: an integer of {digits} digits, more than the {limit} "
        "Python reads; write the value with fewer digits"
    )
