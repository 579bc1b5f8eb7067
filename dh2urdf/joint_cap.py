"""The cap on joints: how many a table or a URDF may have, checked before any model is built.

Pinocchio's ``Data`` holds second-order derivative tensors of ``nv^3`` entries (about
``64 nv^3`` bytes: 17 MB at 64 joints, 513 MB at 200, 68 GB at 1,000) and its URDF parser
recurses down the tree (a chain of thousands of joints overflows the C stack). So:

- a DH table has at most :data:`MAX_JOINTS` rows;
- the chain read from a URDF has at most :data:`MAX_JOINTS` moving joints, and the whole file
  at most :data:`MAX_URDF_MOVING_JOINTS` moving joints (Pinocchio builds every branch: hands,
  grippers) and :data:`MAX_URDF_JOINTS` joints of any type. They are counted in the XML, before
  Pinocchio parses it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree

#: Most joints of a DH table, or of the chain read from a URDF.
MAX_JOINTS = 64
#: Most moving (not ``fixed``) joints in a whole URDF file (every branch, not only the chain).
MAX_URDF_MOVING_JOINTS = 2 * MAX_JOINTS
#: Most ``<joint>`` elements of any type in a URDF file.
MAX_URDF_JOINTS = 16 * MAX_JOINTS


def urdf_joint_count_problem(
    root: ElementTree.Element, base: str | None = None, tip: str | None = None
) -> str | None:
    """What makes a URDF's joints too many for the cap, or None when they fit.

    Args:
        root: The ``<robot>`` element.
        base: Base link of the chain (default: the link no joint moves, the root).
        tip: Tip link of the chain (default: any leaf; the longest chain counts).

    Returns:
        One sentence naming the count and the cap, or None.
    """
    joints = root.findall("joint")
    moving = [joint for joint in joints if joint.get("type", "") != "fixed"]
    if len(joints) > MAX_URDF_JOINTS:
        return f"{len(joints)} joints; a URDF may have at most {MAX_URDF_JOINTS}"
    if len(moving) > MAX_URDF_MOVING_JOINTS:
        return (
            f"{len(moving)} moving joints in the file; at most {MAX_URDF_MOVING_JOINTS} "
            f"(and {MAX_JOINTS} on the chain) are supported"
        )
    if len(moving) <= MAX_JOINTS:
        return None
    # child link -> (parent link, 1 for a moving joint)
    parent: dict[str, tuple[str, int]] = {}
    for joint in joints:
        parent_element, child_element = joint.find("parent"), joint.find("child")
        if parent_element is None or child_element is None:
            continue
        parent[child_element.get("link", "")] = (
            parent_element.get("link", ""),
            int(joint.get("type", "") != "fixed"),
        )
    parents = {link for link, _ in parent.values()}
    ends = [tip] if tip is not None else [link for link in parent if link not in parents]
    longest = 0
    for link in ends:
        count, steps = 0, 0
        while link != base and link in parent and steps <= len(joints):  # steps: no endless loop
            link, moves = parent[link]
            count, steps = count + moves, steps + 1
        longest = max(longest, count)
    if longest > MAX_JOINTS:
        chain = f"to {tip!r}" if tip is not None else "to its deepest link"
        return (
            f"the chain {chain} has {longest} moving joints; at most {MAX_JOINTS} are supported "
            "(choose a --tip nearer the base)"
        )
    return None
