"""Printed numbers: their precision, our value at that precision, and whether the two agree."""

from __future__ import annotations

from typing import Literal

Agreement = Literal["rounded", "truncated"]

#: Slack for values that sit on a rounding tie or a truncation edge (floating-point noise).
_EPS = 1e-9


def decimals(printed: str) -> int:
    """Number of decimals of a printed number (``"86.33"`` -> 2, ``"0"`` -> 0)."""
    return len(printed.split(".")[1]) if "." in printed else 0


def fmt(value: float, places: int) -> str:
    """``value`` with ``places`` decimals, without a minus sign on zero."""
    text = f"{value:.{places}f}"
    return text[1:] if text.startswith("-") and float(text) == 0.0 else text


def at_printed(value: float, printed: str) -> str:
    """``value`` at the precision of ``printed`` (rounded)."""
    return fmt(value, decimals(printed))


def agreement(value: float, printed: str) -> Agreement | None:
    """How ``value`` gives the printed number, if it does.

    Returns:
        ``"rounded"`` when rounding ``value`` to the printed decimals gives it (ties either way),
        ``"truncated"`` when only cutting the extra digits gives it, else ``None``.
    """
    target = float(printed)
    unit = 10.0 ** -decimals(printed)
    if abs(value - target) <= unit / 2 + _EPS:
        return "rounded"
    same_side = target == 0.0 or (value > 0) == (target > 0)
    if same_side and abs(target) <= abs(value) + _EPS and abs(value) - abs(target) < unit + _EPS:
        return "truncated"
    return None


def vector(values: tuple[float, ...] | list[float], places: int, unit: str) -> str:
    """A vector as ``(x, y, z) unit`` with ``places`` decimals (``unit`` may be empty)."""
    return "(" + ", ".join(fmt(v, places) for v in values) + ")" + (f" {unit}" if unit else "")
