"""The library's default wall-clock caps, lifted in tests (tests/conftest.py, child processes).

A search is bounded by its work; its cap [s] only stops it early on a slow machine, and then the
answer says ``timeout``. Left in place, a test's verdict would depend on the machine's load (a
busy CI run: not_found became timeout), so tests run with these caps infinite unless marked
``default_cap`` (the tests of the cap itself, on a ticking clock). A child process gets the same
through :data:`CHILD_PATH` on its ``PYTHONPATH`` (:func:`child_environment`).
tests/house/test_time_caps.py checks that the list is whole.
"""

from __future__ import annotations

import os
from pathlib import Path

#: (module, name) of each default cap.
DEFAULT_CAPS = (
    ("kin.ik.numeric.solver", "DEFAULT_TIMEOUT"),
    ("kin.ik.partial.settings", "DEFAULT_TIMEOUT"),
    ("kin.ik.partial_pose", "DEFAULT_TIMEOUT"),
    ("kin.ik.collision.collision_aware", "DEFAULT_TIMEOUT"),
    ("kin.mimic.solver", "DEFAULT_TIMEOUT"),
    ("kin.reach.map", "NUMERIC_CAP"),
)

#: The folder whose sitecustomize.py lifts the caps in a child process.
CHILD_PATH = Path(__file__).resolve().parent / "no_time_caps"


def child_environment(env: dict[str, str] | None = None) -> dict[str, str]:
    """``env`` (default: this process's) with :data:`CHILD_PATH` first on ``PYTHONPATH``."""
    out = dict(os.environ if env is None else env)
    out["PYTHONPATH"] = os.pathsep.join(p for p in (str(CHILD_PATH), out.get("PYTHONPATH")) if p)
    return out
