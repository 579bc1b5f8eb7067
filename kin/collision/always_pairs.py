"""Link pairs of a DH drawing that are in contact at every configuration: not checked by default.

A DH table's collision shapes are the URDF writer's link cylinders (the row's ``radius``), drawn
from joint to joint. Where a link has no length of its own (``a = 0``, a short ``d``), the two
links beside it meet at one joint with nothing between them, and their cylinders touch there
whatever the joints do: pickplace3's column (``frame0``) and upper arm (``link2``) meet at the
shoulder, 10 mm apart, in every configuration. Such a contact is the drawing, not the arm.

The rule is MoveIt's setup assistant's "always in collision", applied to DH shapes when the model
is built: a link pair in contact without padding (closer than
:data:`~kin.collision.requests.CONTACT_TOLERANCE`) at every one of :data:`SAMPLES`
configurations drawn uniformly within the joint limits (an unbounded joint within +-pi) by NumPy's
``default_rng(`` :data:`SEED` ``)`` is disabled with the reason ``"always"``, and the model's
``shape_note`` names it. The draw is reproducible; a pair that leaves contact anywhere in the
samples stays checked (scorbot's upper arm against its column, which it really crosses).

The padding plays no part: a safety margin never removes a pair from the check. With a padding of
1 m every link pair of a DH arm touches in every sample, and the model then reports them all as
in collision instead of dropping them (a larger margin checked less before).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .pair_contacts import PairContacts, sampling_bounds

__all__ = ["SAMPLES", "SEED", "always_in_contact", "sample_configurations"]

#: Configurations sampled [count].
SAMPLES = 1000
#: Seed of NumPy's ``default_rng`` for the samples.
SEED = 0


def always_in_contact(
    model: pin.Model,
    geometry_model: pin.GeometryModel,
    pair_owners: tuple[tuple[str, str], ...],
    candidates: set[tuple[str, str]],
) -> set[tuple[str, str]]:
    """The ``candidates`` in contact at every sampled configuration (see the module).

    Args:
        model: The arm's Pinocchio model (its limits bound the samples).
        geometry_model: The shapes, with a collision pair per shape pair of :attr:`pair_owners`.
        pair_owners: Per collision pair of ``geometry_model``, its ``(a, b)``.
        candidates: The ``(a, b)`` to test (link pairs).

    Returns:
        The candidates in contact at all :data:`SAMPLES` configurations.
    """
    contacts = PairContacts(model, geometry_model, pair_owners)
    left = set(candidates) & contacts.pairs
    for q in sample_configurations(model, SAMPLES):
        if not left:
            break
        left = contacts.at(q, left)
    return left


def sample_configurations(model: pin.Model, count: int) -> np.ndarray:
    """``count`` joint vectors drawn uniformly within the limits by ``default_rng(SEED)``.

    An unbounded joint is drawn within +-pi [rad]. Returns shape (count, nq).
    """
    lower, upper = sampling_bounds(model)
    return np.random.default_rng(SEED).uniform(lower, upper, (count, model.nq))
