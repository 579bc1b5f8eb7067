"""Moved after 0.3.0 to :mod:`kin.reach.map` (the reachability maps have a folder, ``kin/reach/``).

Its names stay importable from here, with a :class:`DeprecationWarning`.
"""

import warnings

from .reach.map import *  # noqa: F403 (the moved module's names)
from .reach.map import __all__ as __all__

warnings.warn(
    "kin.reach_map is deprecated: import from kin.reach.map", DeprecationWarning, stacklevel=2
)
