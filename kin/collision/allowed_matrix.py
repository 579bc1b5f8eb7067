"""A MoveIt PlanningScene's allowed collision matrix: the pairs it lets touch.

``entry_names``, ``entry_values[i].enabled[j]`` (true: the pair may touch, MoveIt's meaning) and
``default_entry_names``/``default_entry_values`` for pairs the matrix leaves out (both named:
both must allow). Allowed link pairs and link-object pairs are not checked (reason ``"acm"``), as
an SRDF's pairs (:mod:`kin.collision.model`).
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass
from typing import Any

from dh2urdf.quoted_input import quoted

from ..exceptions import CollisionModelError
from .message_fields import field_list, field_mapping

__all__ = ["AllowedMatrix", "read_matrix"]

#: The fields of moveit_msgs/AllowedCollisionMatrix.
_MATRIX = ("default_entry_names", "default_entry_values", "entry_names", "entry_values")


@dataclass(frozen=True)
class AllowedMatrix:
    """A PlanningScene's allowed collision matrix.

    Attributes:
        entries: ``(a, b) -> allowed`` for every pair the matrix holds, both orders.
        defaults: ``name -> allowed`` for pairs the matrix leaves out.
        fields: ``name -> field`` where the file names it (for errors).
    """

    entries: dict[tuple[str, str], bool]
    defaults: dict[str, bool]
    fields: dict[str, str]

    def allows(self, a: str, b: str) -> bool:
        """Whether ``a`` and ``b`` may touch (MoveIt's rule for pairs the matrix leaves out)."""
        if (a, b) in self.entries:
            return self.entries[(a, b)]
        if a in self.defaults and b in self.defaults:
            return self.defaults[a] and self.defaults[b]
        return self.defaults.get(a, self.defaults.get(b, False))

    def pairs(
        self, where: str, known: Collection[str], links: Collection[str], objects: Collection[str]
    ) -> dict[tuple[str, str], str]:
        """The allowed pairs of two ``links``, or a link and one of ``objects``: ``"acm"``.

        Raises:
            CollisionModelError: The matrix names what is in ``known`` (the robot's links, the
                scene's objects) not.
        """
        for name, field in self.fields.items():
            if name not in known:
                raise CollisionModelError(
                    where,
                    f"{field}: {quoted(name)} is neither a link of the robot nor an object of "
                    "the scene",
                )
        used = [*links, *objects]
        return {
            (a, b): "acm"
            for i, a in enumerate(used)
            for b in used[i + 1 :]
            if (a in links or b in links) and self.allows(a, b)
        }


def read_matrix(where: str, value: Any) -> AllowedMatrix:
    """A moveit_msgs/AllowedCollisionMatrix (square, symmetric)."""
    field = "allowed_collision_matrix"
    value = field_mapping(where, field, value, _MATRIX)
    names = _names(where, f"{field}.entry_names", value.get("entry_names", []))
    rows = field_list(where, f"{field}.entry_values", value.get("entry_values", []))
    if len(rows) != len(names):
        raise CollisionModelError(
            where, f"{field}.entry_values: {len(rows)} rows for {len(names)} entry_names"
        )
    flags = []
    for i, row in enumerate(rows):
        at = f"{field}.entry_values[{i}].enabled"
        row = field_mapping(where, f"{field}.entry_values[{i}]", row, ("enabled",))
        flags.append(_flags(where, at, row.get("enabled"), len(names)))
    entries: dict[tuple[str, str], bool] = {}
    for i, a in enumerate(names):
        for j, b in enumerate(names):
            if flags[i][j] != flags[j][i]:
                raise CollisionModelError(
                    where,
                    f"{field}.entry_values[{i}].enabled[{j}]: {flags[i][j]} where "
                    f"entry_values[{j}].enabled[{i}] is {flags[j][i]}; the matrix is symmetric",
                )
            entries[(a, b)] = flags[i][j]
    default_names = _names(
        where, f"{field}.default_entry_names", value.get("default_entry_names", [])
    )
    default_values = _flags(
        where,
        f"{field}.default_entry_values",
        value.get("default_entry_values", []),
        len(default_names),
    )
    fields = {n: f"{field}.entry_names[{i}]" for i, n in enumerate(names)}
    for i, n in enumerate(default_names):
        fields.setdefault(n, f"{field}.default_entry_names[{i}]")
    return AllowedMatrix(entries, dict(zip(default_names, default_values)), fields)


def _names(where: str, field: str, value: Any) -> list[str]:
    names = field_list(where, field, value)
    for i, name in enumerate(names):
        if not isinstance(name, str) or not name:
            raise CollisionModelError(where, f"{field}[{i}]: {quoted(name)} is not a name")
        if name in names[:i]:
            raise CollisionModelError(where, f"{field}[{i}]: {name!r} is named twice")
    return names


def _flags(where: str, field: str, value: Any, size: int) -> list[bool]:
    if (
        not isinstance(value, list)
        or len(value) != size
        or not all(isinstance(v, bool) for v in value)
    ):
        raise CollisionModelError(
            where, f"{field}: {quoted(value)} is not a list of {size} true/false"
        )
    return value
