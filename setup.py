"""The compiled twins' build: one optional C extension per entry of ``kin/_native/registry.py``.

Everything else about the package is declared in ``pyproject.toml``; this file only computes what
a TOML table cannot: each twin's source from the module it builds (``kin.ik._pose_check`` from
``kin/_native/ik/_pose_check.c``), and its ``depends`` (the headers it reaches through
``#include "..."`` lines, so that a header edited rebuilds exactly the twins that include it). The
extensions are optional: without a C compiler the install goes on and the pure-Python modules run
alone (same answers, slower). The registry is read by itself, so the build imports no NumPy and
no ``kin``.
"""

from __future__ import annotations

import re
import runpy
from pathlib import Path

HERE = Path(__file__).resolve().parent
REGISTRY = runpy.run_path(str(HERE / "kin" / "_native" / "registry.py"))
#: A quoted include: ``#include "_twin.h"`` (angle-bracket includes are the system's).
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def headers_reached(source: str) -> list[str]:
    """The project headers a C file includes, directly or through other headers, sorted.

    A quoted name is looked up as the compiler does: beside the including file, then in the
    shared include folder. A name found in neither is left to the compiler to report.

    Args:
        source: The C file, relative to the project (``kin/_native/ik/_pose_check.c``).

    Returns:
        The headers, relative to the project in ``/`` form.
    """
    include_dir = HERE / REGISTRY["INCLUDE_DIR"]
    seen: set[Path] = set()
    stack = [HERE / source]
    while stack:
        current = stack.pop()
        for name in INCLUDE.findall(current.read_text(encoding="utf-8")):
            for folder in (current.parent, include_dir):
                header = folder / name
                if header.is_file():
                    if header not in seen:
                        seen.add(header)
                        stack.append(header)
                    break
    return sorted(header.relative_to(HERE).as_posix() for header in seen)


def twin_extensions() -> list[dict[str, object]]:
    """Each twin's extension as keyword arguments of ``setuptools.Extension``, by module name."""
    source_of = REGISTRY["source_of"]
    return [
        {
            "name": module,
            "sources": [source_of(module)],
            "depends": headers_reached(source_of(module)),
            "include_dirs": [REGISTRY["INCLUDE_DIR"]],
            "optional": True,
        }
        for module in sorted(REGISTRY["TWINS"].values())
    ]


if __name__ == "__main__":
    from setuptools import Extension, setup

    setup(ext_modules=[Extension(**ext) for ext in twin_extensions()])  # type: ignore[arg-type]
