"""Helpers that the test modules share (issue 46 item 5): references built apart from kin, arm
tables, command-line and process helpers. A test module imports them as ``support.<module>``;
no test module imports another.

``tests/`` is on ``sys.path`` while pytest runs: the default ``prepend`` import mode puts the
folder of ``tests/conftest.py`` there (no ``__init__.py`` above it), so ``support`` is found from a
test module in any subfolder. A child process that imports a support module puts :data:`TESTS`
on its own path.
"""

from __future__ import annotations

from pathlib import Path

#: The tests folder (``tests/``), whatever subfolder a test module sits in.
TESTS = Path(__file__).resolve().parents[1]
#: The repository (or the copy of it without the packages' sources that CI tests the wheel from).
ROOT = TESTS.parent
#: The tests' data files (``tests/data``).
DATA = TESTS / "data"
