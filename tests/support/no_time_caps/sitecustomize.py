"""Python's start-up hook for a test's child process: the library's default time caps infinite.

A test that runs a command as a child process (``python -m kin ...``) puts this folder first on
``PYTHONPATH``; Python then imports this module at start-up. It patches nothing yet: it only
watches imports, and when one of the modules of :data:`support.time_caps.DEFAULT_CAPS` has run,
it sets that module's cap to infinity, as tests/conftest.py does in the test process. So a
command's verdict in a test does not depend on the machine's load either.
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # tests/, for support.time_caps
from support.time_caps import DEFAULT_CAPS  # noqa: E402

sys.path.pop(0)

_CAPS = dict(DEFAULT_CAPS)


class _Lifted(importlib.abc.Loader):
    """Runs the real loader, then sets the module's cap to infinity."""

    def __init__(self, loader: importlib.abc.Loader, name: str) -> None:
        self.loader = loader
        self.name = name

    def create_module(self, spec):  # type: ignore[no-untyped-def]
        return self.loader.create_module(spec)

    def exec_module(self, module) -> None:  # type: ignore[no-untyped-def]
        self.loader.exec_module(module)
        setattr(module, _CAPS[self.name], math.inf)


class _Finder(importlib.abc.MetaPathFinder):
    """Finds the listed modules through the normal path finder and wraps their loaders."""

    def find_spec(self, name, path=None, target=None):  # type: ignore[no-untyped-def]
        if name not in _CAPS:
            return None
        spec = importlib.machinery.PathFinder.find_spec(name, path, target)
        if spec is not None and spec.loader is not None:
            spec.loader = _Lifted(spec.loader, name)
        return spec


sys.meta_path.insert(0, _Finder())
