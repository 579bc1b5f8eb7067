"""Collision-aware kinematics: an arm's collision model, a scene, and collision queries.

``load_collision_model(robot, srdf=..., scene=..., padding=...)`` builds the shapes (the URDF's
``<collision>`` elements, or a DH table's link cylinders), the scene's objects and the pairs to
check; ``CollisionChecker(model)`` answers ``in_collision``, ``collisions``, ``distance`` and
their batched forms; ``model.attach(attached_object(...))`` and ``model.detach(name)`` give a
model with a held part or tool on a link. Lengths in meters, angles in radians. ``import kin``
does not load this.
"""

from ..exceptions import CollisionModelError
from .attached import AttachedObject, attached_object
from .checker import Closest, CollisionChecker, Contact
from .model import CollisionModel, load_collision_model

__all__ = [
    "AttachedObject",
    "Closest",
    "CollisionChecker",
    "CollisionModel",
    "CollisionModelError",
    "Contact",
    "attached_object",
    "load_collision_model",
]
