"""The pairs a MoveIt SRDF allows to touch: its ``<disable_collisions link1= link2= reason=/>``.

A link the SRDF names must be a link of the robot's URDF or a scene object; a pair naming a link
without shapes is skipped. An SRDF whose ``<robot name=>``
differs from the URDF's gives one warning, not an error: the link names decide what it means.
"""

from __future__ import annotations

import logging
from collections.abc import Collection
from pathlib import Path
from xml.etree import ElementTree

from dh2urdf.input_file import read_input

from ..exceptions import CollisionModelError

__all__ = ["read_srdf", "srdf_root"]

logger = logging.getLogger("kin.collision")


def read_srdf(
    path: str | Path, robot_name: str, known: Collection[str], used: Collection[str]
) -> dict[tuple[str, str], str]:
    """The disabled pairs of the SRDF ``path``, as ``(a, b) -> "srdf: <reason>"``.

    Args:
        path: The SRDF file.
        robot_name: Name of the robot's URDF (``<robot name=>``), compared with the SRDF's.
        known: Every link of the robot's URDF and every scene object name.
        used: The names that have shapes in the model: pairs naming others are skipped.

    Raises:
        CollisionModelError: The file cannot be read, is not XML, its root is not ``<robot>``,
            a ``disable_collisions`` lacks ``link1``/``link2`` or names a link the robot lacks.
    """
    where = str(path)
    root = srdf_root(where)
    name = root.get("name")
    other = name is not None and name != robot_name  # a warning once its links are all known
    disabled: dict[tuple[str, str], str] = {}
    for index, element in enumerate(root.iter("disable_collisions")):
        pair = []
        for attribute in ("link1", "link2"):
            link = element.get(attribute)
            field = f"disable_collisions[{index}].{attribute}"
            if not link:
                raise CollisionModelError(where, f"{field}: missing")
            if link not in known:
                written = f"written for the robot {name!r}" if other else "for another robot?"
                raise CollisionModelError(
                    where,
                    f"{field}: the robot {robot_name!r} has no link {link!r} (an SRDF {written})",
                )
            pair.append(link)
        a, b = pair
        if a in used and b in used and a != b:
            key = (a, b) if (b, a) not in disabled else (b, a)
            disabled[key] = f"srdf: {element.get('reason') or 'no reason given'}"
    if other:  # not before: an SRDF naming links the robot lacks is one error line, no more
        logger.warning(
            "%s: written for the robot %r, not %r: its link names are used as they are",
            where,
            name,
            robot_name,
        )
    return disabled


def srdf_root(path: str | Path) -> ElementTree.Element:
    """The ``<robot>`` element of the SRDF ``path``.

    Raises:
        CollisionModelError: The file cannot be read, is not XML, or its root is not ``<robot>``.
    """
    where = str(path)
    try:
        root = ElementTree.fromstring(read_input(where))
    except OSError as err:
        raise CollisionModelError(where, f"cannot read the SRDF ({err.strerror})") from err
    except ElementTree.ParseError as err:
        raise CollisionModelError(where, f"not XML: {err}") from None
    if root.tag != "robot":
        raise CollisionModelError(where, f"not an SRDF: the root element is <{root.tag}>")
    return root
