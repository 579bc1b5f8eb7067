"""Moved after 0.3.0 to :mod:`kin.ik.collision.collision_aware`.

The IK side of collisions has a folder, ``kin/ik/collision/``.
Its names stay importable from here, with a :class:`DeprecationWarning`.
"""

import warnings

from .collision.collision_aware import *  # noqa: F403 (the moved module's names)
from .collision.collision_aware import __all__ as __all__

warnings.warn(
    "kin.ik.collision_aware is deprecated: import from kin.ik.collision.collision_aware",
    DeprecationWarning,
    stacklevel=2,
)
