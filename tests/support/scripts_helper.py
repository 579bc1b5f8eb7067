"""Import the command-line scripts as modules so tests can call their ``main(argv)``."""

import importlib.util
import sys
from collections.abc import Callable
from types import ModuleType

from support import ROOT

SCRIPTS = ROOT / "scripts"


def load_script(name: str) -> ModuleType:
    """The module of ``scripts/<name>.py``."""
    key = f"_script_{name}"
    if key in sys.modules:
        return sys.modules[key]
    spec = importlib.util.spec_from_file_location(key, SCRIPTS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[key] = module
    spec.loader.exec_module(module)
    return module


def exit_code(main: Callable[[list[str]], int], argv: list[str]) -> int:
    """Exit code of ``main(argv)``, whether it returns it or argparse raises SystemExit."""
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)
