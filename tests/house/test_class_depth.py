"""The house's limit on inheritance in ``kin/`` and ``dh2urdf/`` (issue 46 item 2): composition.

No project class has more than :data:`DEPTH` project classes in its inheritance chain: itself
and at most one project base. A family of solvers composes its parts (an object it holds,
module-level functions, one module) instead of stacking them as layers of base classes.
Exception classes (an exception family is idiomatic) and ``typing.Protocol`` classes are exempt.

The chains are read from the sources (``ast``), not imported: each base is resolved through the
module's own classes and its imports (relative ones too, followed through a package's
re-exports); a base outside the two packages ends the chain.
"""

from __future__ import annotations

import ast
import builtins
import importlib.util
from dataclasses import dataclass
from pathlib import Path

from support.import_names import absolute_module

#: The packages as installed (their sources in an editable install, site-packages from a wheel).
KIN = Path(importlib.util.find_spec("kin").origin).resolve().parent  # type: ignore[arg-type]
DH2URDF = Path(importlib.util.find_spec("dh2urdf").origin).resolve().parent  # type: ignore[arg-type]

#: The most project classes a chain may hold: the class itself and one project base.
DEPTH = 2


@dataclass(frozen=True)
class ClassInfo:
    """A class of the packages: where it is and the names of its bases as written.

    Attributes:
        module: Dotted name of its module.
        name: Its name.
        bases: Its bases' dotted names as written (``Base``, ``pkg.Base``).
    """

    module: str
    name: str
    bases: tuple[str, ...]


def _dotted(node: ast.expr) -> str | None:
    """``a.b.C`` of a base written as a name or an attribute (a subscript: its value)."""
    if isinstance(node, ast.Subscript):
        return _dotted(node.value)
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        head = _dotted(node.value)
        return None if head is None else f"{head}.{node.attr}"
    return None


def _module_name(path: Path, root: Path) -> str:
    parts = [root.name, *path.relative_to(root).with_suffix("").parts]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


class Index:
    """The classes and imports of every module under ``roots``, and the chains of the classes."""

    def __init__(self, *roots: Path) -> None:
        self.classes: dict[tuple[str, str], ClassInfo] = {}
        #: Per module: local name -> dotted name it stands for (``module.name`` or a module).
        self.names: dict[str, dict[str, str]] = {}
        self.modules: set[str] = set()
        for root in roots:
            for path in sorted(root.rglob("*.py")):
                module = _module_name(path, root)
                self.modules.add(module)
                self._read(module, path.name == "__init__.py", ast.parse(path.read_text("utf-8")))

    def _read(self, module: str, package: bool, tree: ast.Module) -> None:
        table = self.names.setdefault(module, {})
        for node in ast.walk(tree):
            if isinstance(node, ast.ClassDef):
                bases = tuple(d for d in map(_dotted, node.bases) if d is not None)
                self.classes[module, node.name] = ClassInfo(module, node.name, bases)
            elif isinstance(node, ast.ImportFrom):
                source = absolute_module(module, package, node)
                for alias in node.names:
                    table.setdefault(alias.asname or alias.name, f"{source}.{alias.name}")
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.asname:
                        table.setdefault(alias.asname, alias.name)
                    else:
                        head = alias.name.split(".")[0]
                        table.setdefault(head, head)

    def resolve(self, module: str, dotted: str, hops: int = 0) -> tuple[str, str] | str:
        """The project class ``(module, name)`` that ``dotted`` names in ``module``, else the
        name it stands for outside the packages (``typing.Protocol``, ``Exception``)."""
        head, _, rest = dotted.partition(".")
        if not rest and (module, head) in self.classes:
            return module, head
        full = self.names.get(module, {}).get(head, head)
        full = f"{full}.{rest}" if rest else full
        if hops > 20:
            return full
        owner, _, name = full.rpartition(".")
        if full in self.modules or owner not in self.modules:
            return full
        if (owner, name) in self.classes:
            return owner, name
        if name in self.names.get(owner, {}):  # a re-export
            return self.resolve(owner, name, hops + 1)
        return full

    def chain(self, key: tuple[str, str]) -> tuple[list[tuple[str, str]], list[str]]:
        """The project classes of ``key``'s chain (itself first, depth first, once each) and the
        names of the outside bases met on the way."""
        seen: list[tuple[str, str]] = []
        outside: list[str] = []
        stack = [key]
        while stack:
            current = stack.pop(0)
            if current in seen:
                continue
            seen.append(current)
            info = self.classes[current]
            for base in info.bases:
                found = self.resolve(info.module, base)
                if isinstance(found, tuple):
                    stack.append(found)
                else:
                    outside.append(found)
        return seen, outside


def _exempt(outside: list[str]) -> bool:
    """An exception class (a builtin exception among its outside bases) or a Protocol."""
    for name in outside:
        short = name.rpartition(".")[2]
        if short == "Protocol":
            return True
        value = getattr(builtins, short, None)
        if isinstance(value, type) and issubclass(value, BaseException):
            return True
    return False


def deep_classes(*roots: Path) -> list[str]:
    """The complaints: each class (not exempt) whose chain holds more than :data:`DEPTH`
    project classes, with its module and its chain."""
    index = Index(*roots)
    found = []
    for key in sorted(index.classes):
        chain, outside = index.chain(key)
        if len(chain) <= DEPTH or _exempt(outside):
            continue
        names = " -> ".join(f"{module}.{name}" for module, name in chain)
        found.append(
            f"class {key[1]} in {key[0]} has {len(chain)} project classes in its chain "
            f"(limit {DEPTH}): {names}"
        )
    return found


def test_no_class_deeper_than_two_project_classes():
    """No class of kin/ or dh2urdf/ but exceptions and Protocols sits on more than one project
    base (through its whole chain): compose the parts instead."""
    found = deep_classes(KIN, DH2URDF)
    assert found == [], "classes too deep (compose instead):\n" + "\n".join(found)


def test_the_check_sees_a_deep_chain_across_modules(tmp_path):
    """A tiny package: a chain of three through a relative import and a package's re-export is
    found; an exception family and a Protocol family are not; two deep is fine."""
    package = tmp_path / "pkg"
    package.mkdir()
    (package / "__init__.py").write_text("from .a import A\n")
    (package / "a.py").write_text("class A:\n    pass\n\n\nclass Two(A):\n    pass\n")
    (package / "b.py").write_text(
        "from typing import Protocol\n\nfrom pkg import A\n\n\n"
        "class B(A):\n    pass\n\n\n"
        "class P(Protocol):\n    pass\n\n\nclass Q(P, Protocol):\n    pass\n\n\n"
        "class R(Q, Protocol):\n    pass\n\n\n"
        "class Oops(ValueError):\n    pass\n\n\nclass Worse(Oops):\n    pass\n\n\n"
        "class Worst(Worse):\n    pass\n"
    )
    (package / "c.py").write_text("from . import b\n\n\nclass C(b.B):\n    pass\n")
    assert deep_classes(package) == [
        "class C in pkg.c has 3 project classes in its chain (limit 2): "
        "pkg.c.C -> pkg.b.B -> pkg.a.A"
    ]
