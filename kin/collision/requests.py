"""The coal collision requests of a Pinocchio ``GeometryData``: padding, contacts, GJK settings.

Every query of a collision model (the checker's verdicts, contacts and batches, and the sampling
of :mod:`kin.collision.always_pairs`) asks coal through requests set here, so that they all give
the same verdict, whatever ran before on the same data.

GJK starts from coal's default guess at every call: Pinocchio's geometry data asks coal to start
from the previous call's answer (``enable_cached_gjk_guess``), and from such a start the verdict-only
GJK called lab5's upper arm and wrist free where their axes cross (3 of 5,000 random
configurations; from the default start, none). That history is also what made a reused batch
pool call a Panda configuration free whose links overlap by 2.9 cm.

GJK stops as soon as it proves a pair farther apart than the padding (coal's
``distance_upper_bound``, set to the padding plus :data:`EARLY_STOP_SLACK`): a request asks
whether the pair is in contact, not how far apart it is. The proof is a separating plane (the
support point's distance along GJK's direction, a lower bound of the true distance), so no pair
in contact can be called free by it; where GJK would go on to the nearest points it stops after a
step or two (Panda's hull pairs in the batch: 9.8 -> 8.3 us a configuration).
"""

from __future__ import annotations

import warnings

import coal
import pinocchio as pin

__all__ = ["EARLY_STOP_SLACK", "GJK_TOLERANCE", "prepare_requests"]

#: GJK's stopping tolerance in every collision request. coal's default 1e-6 let a verdict-only
#: query call one UR5 configuration in 10,000 free whose forearm and wrist_2 hulls overlap by 2 cm
#: (tests/test_collision_broad_phase.py); 1e-8 costs no measurable time.
GJK_TOLERANCE = 1e-8
#: How far beyond the padding a pair must be proven apart for GJK to stop early [m]: above coal's
#: contact threshold (1e-12 m), so a pair stopped early is never one coal would call in contact.
EARLY_STOP_SLACK = 1e-9


def prepare_requests(geometry_data: pin.GeometryData, padding: float, contact: bool) -> None:
    """Set every collision request of ``geometry_data``.

    Args:
        geometry_data: Pinocchio's geometry data of the model.
        padding: Distance below which a pair is in collision [m] (coal's security margin).
        contact: Whether coal computes contact points and depths (else the verdict only).
    """
    with warnings.catch_warnings():  # coal marks the cached-guess switch deprecated, not gone
        warnings.simplefilter("ignore", DeprecationWarning)
        for request in geometry_data.collisionRequests:
            request.security_margin = padding
            request.enable_contact = contact
            request.gjk_tolerance = GJK_TOLERANCE
            request.gjk_initial_guess = coal.GJKInitialGuess.DefaultGuess
            request.enable_cached_gjk_guess = False
            request.distance_upper_bound = padding + EARLY_STOP_SLACK
