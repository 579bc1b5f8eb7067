"""The house's limits on ``kin/`` and ``dh2urdf/`` (issue 34 item 4, issue 46 item 4): small
modules, small classes, no import circle, and ``dh2urdf`` never imports ``kin``.

No module over :data:`MODULE_LINES` lines (one that says it is one algorithm, up to
:data:`ALGORITHM_LINES`) and no class over :data:`CLASS_LINES` (Python sources; the C files and
the compiled modules aside), and no circle in the graph of the two packages'
imports of themselves and each other: every import counts, the function-local and
``TYPE_CHECKING`` ones too, and a name taken from a package (``from kin import RobotModel``)
counts as an import of the module that defines it. ``dh2urdf`` is the lower layer: none of its
modules imports ``kin``.

What still breaks a limit today is listed below with today's size: a ratchet. The test fails when
a listed one grows, or when a new one appears; a listed one brought within the limit may leave the
list.
"""

from __future__ import annotations

import ast
import importlib.util
from collections.abc import Iterator
from pathlib import Path

import pytest
from support.import_names import absolute_module

#: The packages as installed (their sources in an editable install, site-packages from a wheel).
KIN = Path(importlib.util.find_spec("kin").origin).resolve().parent  # type: ignore[arg-type]
DH2URDF = Path(importlib.util.find_spec("dh2urdf").origin).resolve().parent  # type: ignore[arg-type]
PACKAGES = (KIN, DH2URDF)

#: The limits [lines].
MODULE_LINES = 400
CLASS_LINES = 250

#: A module may be longer when it is one algorithm and says so: a line of its docstring starts
#: with this phrase, then says which algorithm (issue 46 item 4: one concept per module, not a
#: line count). Up to :data:`ALGORITHM_LINES`; past that even one algorithm has parts to name.
ONE_ALGORITHM = "One algorithm:"
ALGORITHM_LINES = 800

#: Modules over :data:`MODULE_LINES` (path under ``kin/``, or ``dh2urdf/...``: lines; dh2urdf's
#: since 2026-12-02). Each is to be split by concept (the house style: one concept per module).
MODULES_OVER: dict[str, int] = {}

#: Classes over :data:`CLASS_LINES` on 2026-11-27 (``path::class``: lines): pipelines to be
#: composed of small stages over a frozen context, as ``NumericIK`` now is.
CLASSES_OVER: dict[str, int] = {}

#: Import circles on 2026-11-27 (the modules of each strongly connected part of the graph).
CIRCLES_KNOWN: tuple[frozenset[str], ...] = ()


def _sources() -> Iterator[tuple[str, Path]]:
    """``(name, path)`` of every Python module of both packages: its path under ``kin/`` (the
    names the ratchet has always used), or ``dh2urdf/`` and its path under that."""
    for path in sorted(KIN.rglob("*.py")):
        yield path.relative_to(KIN).as_posix(), path
    for path in sorted(DH2URDF.rglob("*.py")):
        yield f"dh2urdf/{path.relative_to(DH2URDF).as_posix()}", path


def _module_name(relative: str, top: str = "kin") -> str:
    """The dotted name of a module by its path under the package ``top`` (a package: its own)."""
    parts = [top, *relative.removesuffix(".py").split("/")]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _lines(path: Path) -> int:
    return len(path.read_text(encoding="utf-8").splitlines())


def _classes(path: Path) -> Iterator[tuple[str, int]]:
    """``(name, lines)`` of every class of a module, nested ones too (decorators aside)."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ClassDef):
            assert node.end_lineno is not None
            yield node.name, node.end_lineno - node.lineno + 1


def _over(sizes: dict[str, int], limit: int, known: dict[str, int], what: str) -> list[str]:
    """The complaints: a size over ``limit`` not in ``known``, or above its known size."""
    found = []
    for name, size in sorted(sizes.items()):
        if size <= limit:
            continue
        if name not in known:
            found.append(f"{what} {name} has {size} lines (limit {limit}): split it")
        elif size > known[name]:
            found.append(f"{what} {name} grew to {size} lines (was {known[name]}, limit {limit})")
    return found


def _one_algorithm(path: Path) -> bool:
    """Whether the module's docstring declares it one algorithm (:data:`ONE_ALGORITHM`)."""
    docstring = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
    return any(line.strip().startswith(ONE_ALGORITHM) for line in docstring.splitlines())


def _module_complaints(sources: list[tuple[str, Path]]) -> list[str]:
    """:func:`_over` of the modules, a declared algorithm's against :data:`ALGORITHM_LINES`."""
    declared = {name for name, path in sources if _one_algorithm(path)}
    plain = {name: _lines(path) for name, path in sources if name not in declared}
    long = {name: _lines(path) for name, path in sources if name in declared}
    return _over(plain, MODULE_LINES, MODULES_OVER, "module") + _over(
        long, ALGORITHM_LINES, {}, "module (one algorithm)"
    )


def test_no_module_over_the_limit():
    """No module of kin/ or dh2urdf/ over 400 lines but the listed ones, none of those grown,
    and the ones declared one algorithm within 800."""
    assert _module_complaints(list(_sources())) == []


def test_a_declared_algorithm_may_be_long_and_no_longer(tmp_path):
    """The declaration is read from the docstring: 600 lines pass with it, not without it;
    900 lines fail even with it."""
    declared = tmp_path / "declared.py"
    plain = tmp_path / "plain.py"
    huge = tmp_path / "huge.py"
    header = '"""A solver.\n\nOne algorithm: the elimination of Raghavan and Roth.\n"""\n'
    declared.write_text(header + "x = 1\n" * 600)
    plain.write_text('"""A solver."""\n' + "x = 1\n" * 600)
    huge.write_text(header + "x = 1\n" * 900)
    assert _module_complaints([("declared.py", declared)]) == []
    assert _module_complaints([("plain.py", plain)]) == [
        "module plain.py has 601 lines (limit 400): split it"
    ]
    assert _module_complaints([("huge.py", huge)]) == [
        "module (one algorithm) huge.py has 904 lines (limit 800): split it"
    ]


def test_no_class_over_the_limit():
    """No class of kin/ or dh2urdf/ over 250 lines but the listed ones, none of those grown."""
    sizes = {
        f"{relative}::{name}": lines
        for relative, path in _sources()
        for name, lines in _classes(path)
    }
    assert _over(sizes, CLASS_LINES, CLASSES_OVER, "class") == []


def test_the_ratchet_sees_a_module_that_grows():
    """The checks themselves: a listed module grown, a new one and a class over the limit."""
    known = {"a.py": 500}
    assert _over({"a.py": 500, "b.py": 400}, 400, known, "module") == []
    assert _over({"a.py": 501}, 400, known, "module") == [
        "module a.py grew to 501 lines (was 500, limit 400)"
    ]
    assert _over({"b.py": 401}, 400, known, "module") == [
        "module b.py has 401 lines (limit 400): split it"
    ]


def import_graph(*roots: Path) -> dict[str, set[str]]:
    """Each module of the packages under ``roots`` (kin's and dh2urdf's when none is given) and
    the modules of those packages it imports.

    Every import statement counts, wherever it stands (module level, a function, a
    ``TYPE_CHECKING`` block). ``from pkg import name`` is an import of ``pkg.name`` when that is
    a module, else of the module ``pkg``'s ``__init__`` takes ``name`` from (followed through
    re-exports), else of ``pkg`` itself.
    """
    tops = {root.name for root in roots or PACKAGES}
    trees: dict[str, ast.Module] = {}
    packages: set[str] = set()
    for root in roots or PACKAGES:
        for path in sorted(root.rglob("*.py")):
            name = _module_name(path.relative_to(root).as_posix(), root.name)
            trees[name] = ast.parse(path.read_text(encoding="utf-8"))
            if path.name == "__init__.py":
                packages.add(name)
    exported: dict[str, dict[str, tuple[str, str]]] = {}
    for package in packages:
        table = exported[package] = {}
        # a lazy package (names loaded on first use) states its sources under TYPE_CHECKING
        body = [
            inner
            for node in trees[package].body
            for inner in (node.body if isinstance(node, ast.If) else [node])
        ]
        for node in body:
            if isinstance(node, ast.ImportFrom):
                source = absolute_module(package, True, node)
                for alias in node.names:
                    table[alias.asname or alias.name] = (source, alias.name)

    def defining(package: str, name: str, hops: int = 0) -> str | None:
        if f"{package}.{name}" in trees:
            return f"{package}.{name}"
        if package in exported and name in exported[package] and hops < 20:
            source, original = exported[package][name]
            if source in packages:
                return defining(source, original, hops + 1)
            if source in trees:
                return source
        return package if package in trees else None

    graph: dict[str, set[str]] = {module: set() for module in trees}
    for module, tree in trees.items():
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                graph[module].update(alias.name for alias in node.names if alias.name in trees)
            elif isinstance(node, ast.ImportFrom):
                source = absolute_module(module, module in packages, node)
                if source.split(".")[0] not in tops:
                    continue
                for alias in node.names:
                    found = defining(source, alias.name)
                    if found is not None and found != module:
                        graph[module].add(found)
    return graph


def circles(graph: dict[str, set[str]]) -> list[frozenset[str]]:
    """The strongly connected parts of ``graph`` of more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[frozenset[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, edges = work[-1]
            step = next(edges, None)
            if step is not None:
                if step not in index:
                    index[step] = low[step] = len(index)
                    stack.append(step)
                    on_stack.add(step)
                    work.append((step, iter(sorted(graph.get(step, ())))))
                elif step in on_stack:
                    low[node] = min(low[node], index[step])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                part = set()
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    part.add(member)
                    if member == node:
                        break
                if len(part) > 1:
                    found.append(frozenset(part))
    return found


@pytest.fixture(scope="module")
def kin_graph() -> dict[str, set[str]]:
    """The import graph of kin/ and dh2urdf/ together (read once)."""
    return import_graph()


def test_dh2urdf_never_imports_kin(kin_graph):
    """dh2urdf is the lower layer: no module of it imports kin (kin composes the two)."""
    upward = {
        module: sorted(found for found in imported if found.split(".")[0] == "kin")
        for module, imported in kin_graph.items()
        if module.split(".")[0] == "dh2urdf"
    }
    assert {module: found for module, found in upward.items() if found} == {}


def test_no_import_circle_but_the_known_ones(kin_graph):
    """No circle in the imports of kin/ and dh2urdf/ but the listed ones, none of those grown."""
    new = [
        sorted(part)
        for part in circles(kin_graph)
        if not any(part <= known for known in CIRCLES_KNOWN)
    ]
    assert new == [], f"import circles: {new}"
    stale = [sorted(known) for known in CIRCLES_KNOWN if not known <= kin_graph.keys()]
    assert stale == [], f"listed circles name modules that no longer exist: {stale}"


def test_the_graph_sees_a_circle_behind_a_function_local_import(tmp_path):
    """A tiny package: a circle closed by a function-local import through a re-export is found,
    and a package whose __init__ re-exports its modules is no circle by itself."""
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("from .a import A\nfrom .sub.c import C\n")
    (package / "a.py").write_text("from .b import B\n\nclass A:\n    pass\n")
    (package / "b.py").write_text("def f():\n    from pkg import A\n\nclass B:\n    pass\n")
    (package / "sub" / "__init__.py").write_text("")
    (package / "sub" / "c.py").write_text("from ..a import A\n\nclass C:\n    pass\n")
    graph = import_graph(package)
    assert graph["pkg.b"] == {"pkg.a"} and graph["pkg.sub.c"] == {"pkg.a"}
    assert circles(graph) == [frozenset({"pkg.a", "pkg.b"})]
    (package / "b.py").write_text("class B:\n    pass\n")
    assert circles(import_graph(package)) == []


def test_the_graph_sees_an_import_across_packages(tmp_path):
    """Two tiny packages: an import of the other package is an arrow, a function-local one too,
    and the two arrows close a circle across the packages."""
    for package in ("low", "high"):
        (tmp_path / package).mkdir()
        (tmp_path / package / "__init__.py").write_text("")
    (tmp_path / "low" / "a.py").write_text("def f():\n    from high.b import B\n")
    (tmp_path / "high" / "b.py").write_text("from low import a\n\nclass B:\n    pass\n")
    graph = import_graph(tmp_path / "low", tmp_path / "high")
    assert graph["low.a"] == {"high.b"} and graph["high.b"] == {"low.a"}
    assert circles(graph) == [frozenset({"low.a", "high.b"})]
