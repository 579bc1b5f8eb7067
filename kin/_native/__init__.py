"""The compiled twins: their C sources and headers, and the one loader of their modules.

A twin repeats a Python module's arithmetic in C where a benchmark shows it pays; the Python
module is the reference and the fallback, and a parity test holds the two to the same numbers
(:data:`PARITY_TESTS`). The extensions are optional: ``setup.py`` declares one per entry of
:data:`TWINS` (``kin/_native/registry.py``, the one table) and they are built at install when a C
compiler is there. Each keeps the name of the Python module it serves
(``kin.ik.analytic.seven_r._closed7`` next to ``seven_dof.py``), and its source sits at the same
path below this folder (``kin/_native/ik/analytic/seven_r/_closed7.c``), as Pinocchio's binding
tree mirrors its C++ tree; headers shared across folders sit in ``kin/_native/include/``.

The sources live inside the package (not in a top-level ``csrc/``) so that they are found from
the module that loads them and travel in the sdist and the wheel with the package they belong to.

:func:`twin` is the only way a Python module imports a twin: the module, or None when it is not
built or when ``DH_KINEMATICS_PURE_PYTHON=1`` asks for the pure-Python modules alone (same
answers, slower), with the reason kept for a diagnostic (:func:`why_missing`). This module
imports nothing heavy: ``import kin`` stays light.
"""

from __future__ import annotations

import importlib
import os
from types import ModuleType

from kin._native.registry import PARITY_TESTS, PURE_PYTHON_VARIABLE, TWINS

__all__ = ["PARITY_TESTS", "PURE_PYTHON_VARIABLE", "TWINS", "pure_python", "twin", "why_missing"]

#: Why a twin asked for is not there (its name -> the import error's text).
_MISSING: dict[str, str] = {}


def pure_python() -> bool:
    """Whether ``DH_KINEMATICS_PURE_PYTHON`` is 1 (or true, yes): no twin loads, Python runs alone."""
    return os.environ.get(PURE_PYTHON_VARIABLE, "").strip().lower() in ("1", "true", "yes")


def twin(name: str) -> ModuleType | None:
    """The compiled twin ``name`` (a key of :data:`TWINS`), or None when it is not built or not wanted.

    Args:
        name: The twin's name, its C source's stem (``"_closed7"``).

    Returns:
        The extension module, or None (its reason kept for :func:`why_missing`): not built, or
        :func:`pure_python` asks for the Python forms alone (read at each call).

    Raises:
        KeyError: ``name`` is not a twin (a programming error; the message lists the twins).
    """
    if name not in TWINS:
        raise KeyError(f"no compiled twin {name!r}; the twins: {', '.join(sorted(TWINS))}")
    if pure_python():
        _MISSING[name] = (
            f"{TWINS[name]} is not loaded ({PURE_PYTHON_VARIABLE} is set); the Python form runs alone"
        )
        return None
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
