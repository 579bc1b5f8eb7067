"""The compiled twins: every C source and header in this folder, and the one loader of their modules.

A twin repeats a Python module's arithmetic in C where a benchmark shows it pays; the Python
module is the reference and the fallback, and a parity test holds the two to the same numbers
(:data:`PARITY_TESTS`). The extensions are optional (``[tool.setuptools] ext-modules`` in
pyproject.toml): built at install when a C compiler is there. Each keeps the name of the Python
module it serves (``kin.ik.analytic.seven_r._closed7`` next to ``seven_dof.py``), so the sources
sit here while the built modules sit beside their Python forms.

The sources live inside the package (not in a top-level ``csrc/``) so that the one folder is
found from the module that loads it and travels in the sdist with the package it belongs to.

:func:`twin` is the only way a Python module imports a twin: the module, or None when it is not
built, with the reason kept for a diagnostic (:func:`why_missing`). This module imports nothing
heavy: ``import kin`` stays light.
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["PARITY_TESTS", "TWINS", "twin", "why_missing"]

#: Each twin's name (its C source's stem) -> the extension module it builds.
TWINS: dict[str, str] = {
    "_closed7": "kin.ik.analytic.seven_r._closed7",
    "_damped_step": "kin.ik.numeric._damped_step",
    "_general6r": "kin.ik.analytic.six_r._general6r",
    "_plain_lines": "kin.commands._plain_lines",
    "_pitch_sweep": "kin.ik.analytic.planar._pitch_sweep",
    "_pieper_arms": "kin.ik.analytic.six_r._pieper_arms",
    "_pose_check": "kin.ik._pose_check",
    "_shoulder7": "kin.ik.analytic.seven_r._shoulder7",
    "_three_parallel": "kin.ik.analytic.six_r._three_parallel",
}

#: Each twin's name -> the test file (under ``tests/``) that compares it with its NumPy form.
PARITY_TESTS: dict[str, str] = {
    "_closed7": "test_closed7_parity.py",
    "_damped_step": "test_damped_step.py",
    "_general6r": "test_general6r_twin.py",
    "_plain_lines": "test_plain_lines.py",
    "_pitch_sweep": "test_pitch_sweep.py",
    "_pieper_arms": "test_six_r_family_twins.py",
    "_pose_check": "test_pose_check.py",
    "_shoulder7": "test_shoulder7_parity.py",
    "_three_parallel": "test_six_r_family_twins.py",
}

#: Why a twin asked for is not there (its name -> the import error's text).
_MISSING: dict[str, str] = {}


def twin(name: str) -> ModuleType | None:
    """The compiled twin ``name`` (a key of :data:`TWINS`), or None when it is not built.

    Args:
        name: The twin's name, its C source's stem (``"_closed7"``).

    Returns:
        The extension module, or None (its reason kept for :func:`why_missing`).

    Raises:
        KeyError: ``name`` is not a twin (a programming error; the message lists the twins).
    """
    if name not in TWINS:
        raise KeyError(f"no compiled twin {name!r}; the twins: {', '.join(sorted(TWINS))}")
    try:
        module = importlib.import_module(TWINS[name])
    except ImportError as error:
        _MISSING[name] = f"{TWINS[name]} is not built ({error}); the Python form runs alone"
        return None
    _MISSING.pop(name, None)
    return module


def why_missing(name: str) -> str | None:
    """Why the twin ``name`` was not found when last asked for, or None when it was (or not asked)."""
    return _MISSING.get(name)
