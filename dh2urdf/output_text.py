"""Words of text output: names read from files shown on one line, counts with the right plural.

A name read from an input file (a link, a joint, a scene object, a robot) may hold any
character: a newline in a scene object's name would print a line of its own, one that can pass
for the command's output (``kin check: ...``), and an escape sequence or a bidirectional
override can hide or reorder what a terminal shows. Every command prints such a name as
:func:`shown_name` of it. Counts are written with :func:`counted`: ``1 scene object``,
``2 scene objects``.
"""

from __future__ import annotations

__all__ = ["counted", "shown_name"]


def shown_name(name: str) -> str:
    r"""``name`` as text output shows it: on one line, never passing for another output line.

    A name of printable characters only (:meth:`str.isprintable`: no newline, tab, escape,
    line or paragraph separator, bidirectional override...) that does not begin with a quote is
    shown as it is; any other is shown as its ``repr``: in quotes, those characters escaped
    (``'a\nkin check: free'``). A quoted name is thus always an escaped one.

    Args:
        name: A name read from an input file.
    """
    text = str(name)
    if text.isprintable() and not text.startswith(("'", '"')):
        return text
    return repr(text)


def counted(count: int, noun: str, plural: str | None = None) -> str:
    """``count`` and ``noun`` in the number it takes: ``"1 pair"``, ``"0 pairs"``, ``"2,000 pairs"``.

    Args:
        count: How many.
        noun: The singular (``"scene object"``, ``"link pair"``).
        plural: The plural when it is not ``noun + "s"``.
    """
    return f"{count:,} {noun if count == 1 else plural or noun + 's'}"
