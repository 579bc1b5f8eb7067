"""What an answer of ``kin ik`` shows and what it leaves out, counted the same in every output.

The JSON answers (``--json``, ``--stdin``) carry ``"counts"``
(:func:`kin.ik.result.counts_record`: every valid solution listed, the rejected ones with
``--all`` / ``"all": true`` or when none is valid); the text header says the same numbers when
its rows leave answers out (:func:`hidden_note`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..ik.result import IKResult


def shown_rows(result: IKResult, show_all: bool) -> list[Any]:
    """The answers the text prints: all with ``--all``, else the best (or the best attempt)."""
    if show_all:
        return [*result.solutions, *result.rejected]
    return list(result.solutions[:1] or result.rejected[:1])


def hidden_note(result: IKResult, shown: list[Any]) -> str:
    """``""`` when the rows ``shown`` are every answer, else the header's count of the rest."""
    solutions, rejected = len(result.solutions), len(result.rejected)
    shown_solutions = min(len(shown), solutions)
    shown_rejected = len(shown) - shown_solutions
    if shown_solutions == solutions and shown_rejected == rejected:
        return ""
    return (
        f"; shown: {shown_solutions} of {solutions} solution(s), {shown_rejected} of {rejected} "
        "rejected (--all lists them all)"
    )
