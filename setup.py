"""The compiled twins' build: one optional C extension per entry of ``kin/_native/registry.py``.

Everything else about the package is declared in ``pyproject.toml``; this file only computes what
a TOML table cannot: each twin's source from the module it builds
(``kin.ik.targets._pose_check`` from ``kin/_native/ik/targets/_pose_check.c``), and its ``depends``
(the headers it reaches through ``#include "..."`` lines, so that a header edited rebuilds exactly the twins that include it). The
extensions are optional: without a C compiler the install goes on and the pure-Python modules run
alone (same answers, slower). The registry is read by itself, so the build imports no NumPy and
no ``kin``.
"""

from __future__ import annotations

import re
import runpy
from pathlib import Path

HERE = Path(__file__).resolve().parent
#: A quoted include: ``#include "_twin.h"`` (angle-bracket includes are the system's).
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def headers_reached(source: str, root: Path, include_dir: str) -> list[str]:
    """The project headers a C file includes, directly or through other headers, sorted.

    A quoted name is looked up as the compiler does: beside the including file, then in the
    shared include folder. A name found in neither is left to the compiler to report.

    Args:
        source: The C file, relative to ``root`` (``kin/_native/ik/targets/_pose_check.c``).
        root: The folder holding ``kin/``: the project, or where the package is installed.
        include_dir: The shared headers' folder, relative to ``root``.

    Returns:
        The headers, relative to ``root`` in ``/`` form.
    """
    seen: set[Path] = set()
    stack = [root / source]
    while stack:
        current = stack.pop()
        for name in INCLUDE.findall(current.read_text(encoding="utf-8")):
            for folder in (current.parent, root / include_dir):
                header = folder / name
                if header.is_file():
                    if header not in seen:
                        seen.add(header)
                        stack.append(header)
                    break
    return sorted(header.relative_to(root).as_posix() for header in seen)


def twin_extensions(root: Path = HERE) -> list[dict[str, object]]:
    """Each twin's extension as keyword arguments of ``setuptools.Extension``, by module name.

    Args:
        root: The folder holding ``kin/``: this project (the build), or where the package is
            installed (a test of the wheel, which ships the registry and the C files).
    """
    registry = runpy.run_path(str(root / "kin" / "_native" / "registry.py"))
    source_of, include_dir = registry["source_of"], registry["INCLUDE_DIR"]
    return [
        {
            "name": module,
            "sources": [source_of(module)],
            "depends": headers_reached(source_of(module), root, include_dir),
            "include_dirs": [include_dir],
            "optional": True,
        }
        for module in sorted(registry["TWINS"].values())
    ]


if __name__ == "__main__":
    from setuptools import Extension, setup

    setup(ext_modules=[Extension(**ext) for ext in twin_extensions()])  # type: ignore[arg-type]
