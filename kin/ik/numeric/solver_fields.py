"""The read-only view of :class:`~.solver.NumericIK`'s context and settings, and its batch route.

``solver.closed_form``, ``solver.judge``, ``solver.near_seed``, ...: every public field,
property and method of its :class:`~.context.NumericContext` (first) and
:class:`~.settings.NumericSettings`, as a read-only property of the solver class
(:func:`read_only_fields`), so that nothing is forwarded through ``__getattr__``; and
:func:`free_joint_route`, what a batch asks of it (:meth:`kin.ik.solver.IKSolver.batch_route`).
"""

from __future__ import annotations

import dataclasses
import operator
from typing import Any

from ..solver import FreeJointRoute
from .context import NumericContext
from .settings import NumericSettings

#: The attributes :class:`~.solver.NumericIK` sets itself (not read from its context or settings).
_OWN = frozenset(("settings", "context", "robot", "nq", "lower", "upper", "stages", "seeded_many"))


def read_only_fields(cls: type) -> None:
    """Every field of the context and the settings read as ``solver.<field>`` (read-only).

    One property per field, each reading ``solver.context.<field>`` (or
    ``solver.settings.<field>``): the names the callers and the tests read
    (``solver.closed_form``, ``solver.judge``, ``solver.near_seed``, ...), with no
    ``__getattr__`` forwarding.
    """
    taken = set(vars(cls)) | _OWN
    for source, names in (
        ("context", _public(NumericContext)),
        ("settings", _public(NumericSettings)),
    ):
        for name in names:
            if name in taken:
                continue
            taken.add(name)
            getter = operator.attrgetter(f"{source}.{name}")
            setattr(cls, name, property(getter, doc=f"``{source}.{name}``, read-only."))


def _public(cls: type) -> list[str]:
    """The fields, properties and methods of a dataclass whose names do not start with ``_``."""
    names = [field.name for field in dataclasses.fields(cls)]
    return names + [name for name in dir(cls) if not name.startswith("_") and name not in names]


def free_joint_route(
    context: NumericContext, settings: NumericSettings, seeded_many: Any
) -> FreeJointRoute | None:
    """Stage 0 of a batch of poses (:mod:`kin.ik.free_joint_batch`), or None.

    The free-joint closed form of an arm that has one, not on an idealised table.
    """
    if context.closed_form is None or context.idealised is not None:
        return None
    return FreeJointRoute(
        context.closed_form,
        seeded_many,
        bool(context.compiled),
        tuple(settings.closed_form_steps),
        settings.near_seed,
        settings.seed_near,
        settings.seed_reach,
        settings.seed_radius,
        settings.seed_turn,
    )
