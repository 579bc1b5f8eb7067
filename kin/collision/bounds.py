"""How large a collision shape and how far from the origin its placement may be [m].

A scene's or a URDF's shape beyond these bounds is bad input (as a DH table's length beyond
``dh2urdf.table_values.MAX_LENGTH``): coal's answers near contact are exact to
:data:`~kin.collision.requests.CONTACT_TOLERANCE` only for shapes of a cell's size. Its support
functions err by up to the shape's size times 1e-12 over GJK's step length
(:mod:`kin.collision.requests`); measured up to 2.2 um on shapes of 10 m, so :data:`MAX_SIZE` keeps
the error below the tolerance. A 1e308 m box or a box at 1e308 m gave NaN contact points.

Placements: a coordinate of :data:`MAX_COORDINATE` carries a rounding error of 2e-13 m (double
precision), far below the tolerance; a scene farther than a kilometre from the arm's base is a
unit slip (millimetres read as meters), not a cell.
"""

from __future__ import annotations

from collections.abc import Iterable

from ..exceptions import CollisionModelError

__all__ = [
    "MAX_COORDINATE",
    "MAX_SHAPES",
    "MAX_SIZE",
    "check_coordinates",
    "check_count",
    "check_sizes",
]

#: Largest size of a shape [m]: a box's side, a radius, a cylinder's or capsule's length, a
#: mesh's extent.
MAX_SIZE = 10.0
#: Largest coordinate of a shape's placement, and largest padding [m].
MAX_COORDINATE = 1000.0
#: Most shapes in a scene [count]. Pinocchio 4's geometry model keeps a square matrix of its
#: objects, copied at every object added: 1,000 objects load in 0.3 s, 3,000 in 25 s, 10,000 not
#: within 200 s, 100,000 would take 40 GB.
MAX_SHAPES = 1000


def check_sizes(where: str, field: str, values: Iterable[float]) -> None:
    """Raise unless every value is a size in (0, :data:`MAX_SIZE`] [m].

    Raises:
        CollisionModelError: Names ``where`` (the file) and ``field``.
    """
    for value in values:
        if not 0.0 < value <= MAX_SIZE:  # NaN fails too
            raise CollisionModelError(
                where, f"{field}: {value!r} m must be > 0 and at most {MAX_SIZE:g} m"
            )


def check_coordinates(where: str, field: str, values: Iterable[float]) -> None:
    """Raise unless every value is within +-:data:`MAX_COORDINATE` [m].

    Raises:
        CollisionModelError: Names ``where`` (the file) and ``field``.
    """
    for value in values:
        if not abs(value) <= MAX_COORDINATE:  # NaN fails too
            raise CollisionModelError(
                where, f"{field}: {value!r} m is beyond +-{MAX_COORDINATE:g} m from the origin"
            )


def check_count(where: str, count: int) -> None:
    """Raise when a scene holds more than :data:`MAX_SHAPES` shapes.

    Raises:
        CollisionModelError: Names ``where`` and the count.
    """
    if count > MAX_SHAPES:
        raise CollisionModelError(
            where,
            f"{count} shapes; a scene holds at most {MAX_SHAPES:,} (Pinocchio's geometry model "
            "grows with the square of its shapes): merge objects or keep those near the arm",
        )
