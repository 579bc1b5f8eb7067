"""Moved after 0.3.0 to :mod:`kin.ik.targets.target` (the targets have a folder, ``kin/ik/targets/``).

Its names stay importable from here, with a :class:`DeprecationWarning`; :mod:`kin.ik` exports
the targets themselves.
"""

import warnings

from .targets.target import *  # noqa: F403 (the moved module's names)
from .targets.target import __all__ as __all__

warnings.warn(
    "kin.ik.target is deprecated: import from kin.ik (or kin.ik.targets.target)",
    DeprecationWarning,
    stacklevel=2,
)
