"""Moved after 0.3.0 to :mod:`kin.mimic.arm` (the mimic arms have a folder, ``kin/mimic/``).

Its names stay importable from here, with a :class:`DeprecationWarning`.
"""

import warnings

from .mimic.arm import *  # noqa: F403 (the moved module's names)
from .mimic.arm import __all__ as __all__

warnings.warn(
    "kin.mimic_arm is deprecated: import from kin.mimic.arm", DeprecationWarning, stacklevel=2
)
