"""The link pairs a collision check may skip, found by the rules of MoveIt's setup assistant.

The rules are those of MoveIt 2's setup assistant, ``computeDefaultCollisions`` in
``moveit_setup_assistant/moveit_setup_srdf_plugins/src/compute_default_collisions.cpp``
(moveit/moveit2 at 8fcb5d2, August 2026; the line numbers below are that file's). Every pair of
the model's links (the links with shapes) gets the first reason that applies, in this order:

* ``Adjacent``: the links are joined by a joint, where a link without collision geometry joins
  all of its neighbours to one another, repeated until nothing changes (``computeConnectionGraph``,
  lines 340-385; ``disableAdjacentLinks``, lines 416-437). The joints are the URDF's (the
  robot's URDF file, or the one a DH table's writer emits), the whole tree, not the chain only.
* ``Default``: in contact at the default state: each joint at 0, or at the middle of its limits
  where 0 is outside them (``disableDefaultCollisions``, lines 442-463, with MoveIt's
  ``getVariableDefaultPositions`` of ``moveit_core/robot_model/src/revolute_joint_model.cpp``
  and ``prismatic_joint_model.cpp``).
* ``Always``: in batches of :data:`ALWAYS_BATCH` (200) random states, a pair still checked that is
  in contact in more than ``int(ALWAYS_BATCH * always_fraction)`` of a batch's states (190 of 200
  at the default :data:`ALWAYS_FRACTION`, 0.95: so 191 or more) is disabled and no longer
  counted; batches go on until one disables nothing new (``disableAlwaysInCollision``, lines
  468-536: ``SMALL_TRIAL_COUNT = 200`` at line 473, ``it->second > SMALL_TRIAL_LIMIT`` at line
  519, the stop at line 531; the fraction's default 0.95 at line 158 and in the assistant's
  window, ``default_collisions_widget.cpp`` line 126). As in MoveIt, a fraction of 1.0 disables
  nothing as Always (no count exceeds the batch).
* ``Never``: in contact in none of the states drawn, the Always batches' and ``samples`` more
  (``disableNeverInCollision``, lines 541-582: a pair never inserted in ``links_seen_colliding``,
  which the Always batches fill too, line 499). The assistant's default is 10,000 states
  (``default_collisions_widget.cpp`` lines 98 and 229): :data:`NEVER_SAMPLES`.

Where this differs from the assistant, on purpose or by construction:

* The states are drawn by NumPy's ``default_rng(random_seed)``, uniformly within the joint limits
  (an unbounded joint within +-pi, as MoveIt's continuous joints), Always batches first, then the
  Never samples: the same model, counts, fraction and seed give the same pairs, and
  :func:`srdf_text` the same bytes (it states them all). MoveIt's states are unseeded, and its
  Never pass runs ``num_trials / threads`` states per thread (so a few fewer than asked).
* A state moves the chain's joints only. MoveIt samples every joint; the joints off the chain (a
  gripper's fingers) stay where the model holds them (:mod:`.held_joints`: ``hold``, an SRDF
  group state, else 0), and :func:`srdf_text` says so. A pair that touches only at another
  value may come out Never: Panda's fingers never reach ``panda_link5`` held closed (0 m), and
  touch it at q = 0 held open (0.04 m); the maker's SRDF keeps those pairs checked.
* Contact is the model's verdict at zero padding (:mod:`.requests`): meshes as their convex hulls,
  closer than :data:`~kin.collision.requests.CONTACT_TOLERANCE`. MoveIt's FCL tests the meshes
  themselves, so a hull may touch where the mesh does not: fewer ``Never``, perhaps more
  ``Default``/``Always`` pairs here.
* Only the model's links are paired; a scene and an SRDF given to the model are ignored.

"Never over N samples" is a statistical claim: a pair that collides only in a small corner of the
joint space may be disabled; more samples make that less likely.
"""

from __future__ import annotations

from collections import Counter
from itertools import combinations
from typing import TYPE_CHECKING
from xml.etree.ElementTree import Element
from xml.sax.saxutils import quoteattr

import numpy as np

from ..exceptions import CollisionModelError
from .pair_contacts import PairContacts, sampling_bounds

if TYPE_CHECKING:  # pragma: no cover
    from ..robot_model import RobotModel
    from .model import CollisionModel

__all__ = [
    "ALWAYS_BATCH",
    "ALWAYS_FRACTION",
    "NEVER_SAMPLES",
    "REASONS",
    "generate_disabled_pairs",
    "srdf_text",
]

#: The reasons a pair is disabled, in the order they are tried.
REASONS = ("Adjacent", "Default", "Always", "Never")
#: States per batch of the Always rule [count] (MoveIt's ``SMALL_TRIAL_COUNT``).
ALWAYS_BATCH = 200
#: A pair in contact in more than ``int(ALWAYS_BATCH * ALWAYS_FRACTION)`` states of a batch is
#: disabled as Always (MoveIt's ``min_collision_fraction`` default).
ALWAYS_FRACTION = 0.95
#: States drawn for the Never rule [count] (the assistant's default sampling density).
NEVER_SAMPLES = 10_000


def _key(a: str, b: str) -> tuple[str, str]:
    return (a, b) if a <= b else (b, a)


def generate_disabled_pairs(
    model: CollisionModel,
    samples: int = NEVER_SAMPLES,
    random_seed: int = 0,
    *,
    always_fraction: float = ALWAYS_FRACTION,
    always_batch: int = ALWAYS_BATCH,
) -> dict[tuple[str, str], str]:
    """Link pairs to disable, each with its reason (see the module docstring).

    Args:
        model: A collision model; its links and shapes are used (its scene, SRDF pairs and
            padding are not: every pair of its links is judged afresh).
        samples: Random states for the Never rule [count], at least 1.
        random_seed: Seed of NumPy's ``default_rng``, at least 0.
        always_fraction: A pair in contact in more than ``int(always_batch * always_fraction)``
            states of a batch is Always, in (0, 1].
        always_batch: States per batch of the Always rule [count], at least 1.

    Returns:
        ``(link1, link2) -> reason``, names in sorted order within a pair, pairs sorted.

    Raises:
        CollisionModelError: An argument out of its range (the message names it).
    """
    _check_arguments(samples, random_seed, always_fraction, always_batch)
    robot = model.robot
    reasons = dict.fromkeys(sorted(adjacent_pairs(robot, model.links)), "Adjacent")
    pairs = [p for p in combinations(sorted(model.links), 2) if p not in reasons]
    contacts = PairContacts.of_pairs(robot.model, model.geometry_model, model.owners, pairs)
    for pair in sorted(contacts.at(default_state(robot))):
        reasons[pair] = "Default"
    lower, upper = sampling_bounds(robot.model)
    rng = np.random.default_rng(random_seed)
    seen: set[tuple[str, str]] = set()
    limit = int(always_batch * always_fraction)
    while True:
        checked = [p for p in pairs if p not in reasons]
        counts: Counter[tuple[str, str]] = Counter()
        for q in rng.uniform(lower, upper, (always_batch, robot.nq)):
            touching = contacts.at(q, checked)
            counts.update(touching)
            seen |= touching
        always = sorted(pair for pair, count in counts.items() if count > limit)
        reasons.update(dict.fromkeys(always, "Always"))
        if not always:
            break
    unseen = {p for p in pairs if p not in reasons} - seen
    for q in rng.uniform(lower, upper, (samples, robot.nq)):
        if not unseen:
            break  # the rest of the draw would decide nothing
        unseen -= contacts.at(q, unseen)
    reasons.update(dict.fromkeys(unseen, "Never"))
    return dict(sorted(reasons.items()))


def _check_arguments(samples: int, random_seed: int, fraction: float, batch: int) -> None:
    problems = [
        (samples < 1, f"samples must be at least 1, got {samples}"),
        (random_seed < 0, f"random_seed must be at least 0, got {random_seed}"),
        (not 0.0 < fraction <= 1.0, f"always_fraction must be in (0, 1], got {fraction!r}"),
        (batch < 1, f"always_batch must be at least 1, got {batch}"),
    ]
    for bad, message in problems:
        if bad:
            raise CollisionModelError("", message)


def default_state(robot: RobotModel) -> np.ndarray:
    """MoveIt's default state: each joint at 0, or mid-way between its limits where 0 is outside.

    Returns the joint vector [rad] or [m], shape (nq,).
    """
    lower, upper = sampling_bounds(robot.model)
    inside = (lower <= 0.0) & (upper >= 0.0)
    return np.where(inside, 0.0, (lower + upper) / 2.0)


def adjacent_pairs(robot: RobotModel, links: tuple[str, ...]) -> set[tuple[str, str]]:
    """The pairs of ``links`` joined by a joint, through links without geometry (MoveIt's rule).

    Args:
        robot: The robot; its URDF's ``<joint>`` elements (parent, child) are the graph, its
            links with a ``<collision>`` element (or in ``links``) the links with geometry.
        links: The links to pair (the collision model's, all with shapes).

    Returns:
        ``(a, b)`` in sorted order within a pair.
    """
    root = _urdf_root(robot)
    neighbours: dict[str, set[str]] = {}
    for joint in root.findall("joint"):  # the robot's joints, not a transmission's
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            continue
        a, b = parent.get("link", ""), child.get("link", "")
        neighbours.setdefault(a, set()).add(b)
        neighbours.setdefault(b, set()).add(a)
    shaped = set(links) | {
        link.get("name", "") for link in root.findall("link") if link.find("collision") is not None
    }
    changed = True
    while changed:  # a link without geometry joins its neighbours to one another
        changed = False
        for link in sorted(neighbours):
            if link in shaped:
                continue
            around = sorted(neighbours[link])
            for a, b in combinations(around, 2):
                if b not in neighbours[a]:
                    neighbours[a].add(b)
                    neighbours[b].add(a)
                    changed = True
    members = set(links)
    return {_key(a, b) for a in members & set(neighbours) for b in neighbours[a] if b in members}


def _urdf_root(robot: RobotModel) -> Element:
    """The root element of the robot's URDF (its file, or the URDF a DH table's writer emits)."""
    from dh2urdf.exceptions import UrdfChainError
    from dh2urdf.urdf_chain import urdf_text
    from dh2urdf.urdf_parse import parse_urdf_xml

    from ..exceptions import ModelLoadError

    try:
        if robot.urdf_source is None:
            return parse_urdf_xml(robot.urdf, str(robot.table.path or robot.name))[0]
        where = robot.urdf_source[0]
        return parse_urdf_xml(urdf_text(where), str(where))[0]
    except UrdfChainError as err:
        raise ModelLoadError(str(err)) from err


def srdf_text(
    robot_name: str,
    disabled: dict[tuple[str, str], str],
    samples: int,
    random_seed: int,
    *,
    always_fraction: float = ALWAYS_FRACTION,
    always_batch: int = ALWAYS_BATCH,
    held: str = "",
) -> str:
    """An SRDF holding ``disabled`` as ``<disable_collisions>`` elements, sorted; no date.

    Args:
        robot_name: The ``<robot name>``.
        disabled: ``(link1, link2) -> reason`` (:func:`generate_disabled_pairs`).
        samples: The Never rule's state count to state [count].
        random_seed: The seed to state.
        always_fraction: The Always rule's fraction to state.
        always_batch: The Always rule's batch to state [count].
        held: The joints the states hold still and their values (the model's ``held.note``),
            "" when none.
    """
    counts = {reason: sum(r == reason for r in disabled.values()) for reason in REASONS}
    shown = robot_name.replace("--", "- -")  # "--" may not stand in an XML comment
    limit = int(always_batch * always_fraction)
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        f"<!-- Generated by kin collisions for {shown}: {len(disabled)} disabled pairs "
        f"({', '.join(f'{n} {r}' for r, n in counts.items())}), by the rules of MoveIt's setup "
        "assistant.",
        "     Adjacent: joined by a joint (through links without geometry); Default: in contact "
        "with every joint at 0 (mid-limits where 0 is outside);",
        f"     Always: in contact in more than {limit} of {always_batch} states of a batch "
        f"(fraction {always_fraction:g}), batches repeated until one disables nothing new;",
        f"     Never: in contact in none of the batches' states and {samples} more.",
        "     States: uniform within the joint limits, batches first, "
        f"numpy default_rng({random_seed})"
        + (f"; held still, not sampled: {held.replace('--', '- -')}" if held else "")
        + ". -->",
        f"<robot name={quoteattr(robot_name)}>",
    ]
    for (a, b), reason in sorted(disabled.items()):
        lines.append(
            f"  <disable_collisions link1={quoteattr(a)} link2={quoteattr(b)} "
            f"reason={quoteattr(reason)}/>"
        )
    lines.append("</robot>")
    return "\n".join(lines) + "\n"
