"""The module a ``from ... import`` reads: the house tests' import graph and class chains."""

from __future__ import annotations

import ast


def absolute_module(module: str, package: bool, node: ast.ImportFrom) -> str:
    """The dotted name a ``from ... import`` in ``module`` reads (relative ones resolved).

    ``package``: ``module`` is a package (its ``__init__``), the level counted from it.
    """
    if node.level == 0:
        return node.module or ""
    base = module.split(".") if package else module.split(".")[:-1]
    base = base[: len(base) - node.level + 1]
    return ".".join([*base, *([node.module] if node.module else [])])
