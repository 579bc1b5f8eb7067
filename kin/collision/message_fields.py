"""Fields of a message read from a JSON or YAML document (a MoveIt PlanningScene), checked.

Each reader returns the value or raises one :class:`~kin.exceptions.CollisionModelError` naming
the file and the field (``world.collision_objects[2].pose``).
"""

from __future__ import annotations

from typing import Any

from dh2urdf.quoted_input import quoted

from ..exceptions import CollisionModelError

__all__ = ["field_list", "field_mapping", "known_keys"]


def known_keys(where: str, field: str, value: dict[Any, Any], keys: tuple[str, ...]) -> None:
    """Raise unless every key of ``value`` (at ``field``) is one of ``keys``."""
    for key in value:
        if key not in keys:
            at = f"{field}.{key}" if field else str(key)
            raise CollisionModelError(
                where, f"{quoted(at)[1:-1]}: unknown key; choose: {', '.join(keys)}"
            )


def field_list(where: str, field: str, value: Any) -> list[Any]:
    """``value`` when it is a list, else one error naming ``field``."""
    if not isinstance(value, list):
        raise CollisionModelError(where, f"{field}: {quoted(value)} is not a list")
    return value


def field_mapping(where: str, field: str, value: Any, keys: tuple[str, ...]) -> dict[str, Any]:
    """``value`` when it is a mapping of ``keys`` only, else one error naming the field."""
    if not isinstance(value, dict):
        raise CollisionModelError(where, f"{field}: {quoted(value)} is not a mapping")
    known_keys(where, field, value, keys)
    return value
