"""The coal requests of a Pinocchio ``GeometryData``: padding, contact tolerance, GJK settings.

Every query of a collision model (the checker's verdicts, contacts, distances and batches, and the
sampling of :mod:`kin.collision.always_pairs` and :mod:`kin.collision.pair_order`) asks coal
through requests set here, so that they all give the same verdict, whatever ran before on the
same data.

**One verdict.** A pair is in contact when coal's distance between its shapes is below the
padding plus :data:`CONTACT_TOLERANCE` (coal's ``security_margin``). The tolerance is what makes
the verdict-only query (no contact points, GJK stopped as soon as it proves the pair farther than
the margin) agree with the distance query near contact. coal's GJK is exact only up to its
tolerance, and its support functions of boxes, cylinders and capsules compare the components of
an unnormalised direction with 1e-12 absolutely: where GJK's direction is short (micrometers, near
contact) they return a point off the extreme one, and the early stop overstates the distance.
Measured with coal 3.0.3 on random and nearly axis-aligned pairs of boxes, spheres, cylinders,
capsules and hulls up to 10 m (tests/collision/test_collision_one_verdict.py): without the tolerance the
verdict called overlaps of up to 4.3 um free (10 um with GJK's tolerance at 1e-7), and coal's
distance erred by up to 2.2 um; with it, no overlap is called free and no pair closer than half
the tolerance.

So at every configuration: a pair whose distance (padding taken off) is below 0 is in contact, one
above :data:`CONTACT_TOLERANCE` is not, and one in between is in contact with depth 0 (within the
tolerance of touching). The shapes' sizes are bounded (:mod:`kin.collision.bounds`) so that coal's
error stays below the tolerance.

GJK starts from coal's default guess at every call: Pinocchio's geometry data asks coal to start
from the previous call's answer (``enable_cached_gjk_guess``), and from such a start the verdict-only
GJK called lab5's upper arm and wrist free where their axes cross (3 of 5,000 random
configurations; from the default start, none). That history is also what made a reused batch
pool call a Panda configuration free whose links overlap by 2.9 cm.
"""

from __future__ import annotations

import warnings

import coal
import pinocchio as pin

__all__ = ["CONTACT_TOLERANCE", "GJK_TOLERANCE", "prepare_requests"]

#: GJK's stopping tolerance in every request [m]. coal's default 1e-6 let a verdict-only query call
#: one UR5 configuration in 10,000 free whose forearm and wrist_2 hulls overlap by 2 cm (GJK's
#: estimate stopped below its tolerance, above a zero margin: tests/collision/test_collision_broad_phase.py);
#: 1e-8 costs no measurable time. Larger values make the support-function error above larger
#: (coal 3.0.3 also returned a distance of 1.8e308 at 1e-7 and 1e-6 for some touching pairs).
GJK_TOLERANCE = 1e-8
#: Distance beyond the padding below which two shapes are in contact [m] (see the module): five
#: times coal's largest error measured on shapes within the size bound.
CONTACT_TOLERANCE = 1e-5


def prepare_requests(geometry_data: pin.GeometryData, padding: float) -> None:
    """Set every collision and distance request of ``geometry_data``.

    Collision requests ask for the verdict only (no contact points: the distance query measures
    the pairs in contact), so that every verdict is the same query.

    Args:
        geometry_data: Pinocchio's geometry data of the model.
        padding: Margin around every shape [m]; a pair closer than ``padding`` +
            :data:`CONTACT_TOLERANCE` is in contact (coal's security margin).
    """
    margin = padding + CONTACT_TOLERANCE
    with warnings.catch_warnings():  # coal marks the cached-guess switch deprecated, not gone
        warnings.simplefilter("ignore", DeprecationWarning)
        for request in geometry_data.collisionRequests:
            request.security_margin = margin
            request.enable_contact = False
            request.gjk_tolerance = GJK_TOLERANCE
            request.gjk_initial_guess = coal.GJKInitialGuess.DefaultGuess
            request.enable_cached_gjk_guess = False
            # Pinocchio's computeCollision sets this to the margin + 1e-6 itself: GJK stops as soon
            # as a separating plane proves the pair farther apart (see the module for its error)
            request.distance_upper_bound = margin
        for request in geometry_data.distanceRequests:
            request.gjk_tolerance = GJK_TOLERANCE
            request.gjk_initial_guess = coal.GJKInitialGuess.DefaultGuess
            request.enable_cached_gjk_guess = False
            request.enable_signed_distance = True
