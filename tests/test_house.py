"""House rules that keep the code readable: functions on one screen, no import circles.

Both are read from the source with ``ast`` (nothing is imported or run):

- a function (or method) outside ``tests/`` and ``benchmarks/`` is at most ``HARD_LIMIT``
  lines long from its ``def`` to its last line, docstring included, and at most
  ``MAX_OVER_SOFT`` functions are longer than ``SOFT_LIMIT``; ``ALLOWED_LONG`` lists the
  functions still waiting to be split, each with its reason, and shrinks as they are;
- the modules of the five packages import each other without a cycle: the graph counts every
  ``import``/``from ... import`` (at module level or inside a function) and every
  ``importlib.import_module("...")`` with a literal name, which static tools miss.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

REPO = Path(__file__).resolve().parent.parent
PACKAGES = ("dem", "limit", "fem_check", "validation", "paper_figures")
HARD_LIMIT = 100  # lines, def to last line
SOFT_LIMIT = 80
MAX_OVER_SOFT = 5

_WAITING = {}
ALLOWED_LONG = {tuple(key.split("::")): reason for reason, keys in _WAITING.items() for key in keys}
"""(path, function) longer than ``SOFT_LIMIT`` that wait for their split, with the reason."""


# -- function length ------------------------------------------------------------------------
def function_lengths(tree: ast.AST) -> Iterator[tuple[str, int]]:
    """(qualified name, lines from ``def`` to the last line) of every function in ``tree``,
    nested ones and methods included (``Class.method``, ``outer.inner``)."""

    def walk(node: ast.AST, prefix: str) -> Iterator[tuple[str, int]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                yield prefix + child.name, child.end_lineno - child.lineno + 1
                yield from walk(child, f"{prefix}{child.name}.")
            elif isinstance(child, ast.ClassDef):
                yield from walk(child, f"{prefix}{child.name}.")
            else:
                yield from walk(child, prefix)

    yield from walk(tree, "")


def _source_files() -> Iterator[Path]:
    for package in PACKAGES:
        yield from sorted((REPO / package).rglob("*.py"))


def _long_functions(limit: int) -> dict[tuple[str, str], int]:
    out = {}
    for path in _source_files():
        rel = path.relative_to(REPO).as_posix()
        for name, length in function_lengths(ast.parse(path.read_text(), str(path))):
            if length > limit:
                out[(rel, name)] = length
    return out


def test_function_lengths_are_measured_from_def_to_last_line():
    """A synthetic module: a 101-line function with a nested 3-line one, and a method."""
    body = "\n".join(f"    x{i} = {i}" for i in range(96))
    source = (
        f"def outer():\n    def inner():\n        return 1\n\n{body}\n    return inner\n\n\n"
        "class A:\n    def m(self):\n        return 2\n"
    )
    lengths = dict(function_lengths(ast.parse(source)))
    assert lengths == {"outer": 101, "outer.inner": 2, "A.m": 2}


def test_no_function_is_longer_than_the_hard_limit():
    too_long = {key: n for key, n in _long_functions(HARD_LIMIT).items() if key not in ALLOWED_LONG}
    assert not too_long, f"split these (over {HARD_LIMIT} lines): {too_long}"


def test_few_functions_are_longer_than_the_soft_limit():
    over = {key: n for key, n in _long_functions(SOFT_LIMIT).items() if key not in ALLOWED_LONG}
    assert len(over) <= MAX_OVER_SOFT, (
        f"{len(over)} functions over {SOFT_LIMIT} lines (at most {MAX_OVER_SOFT}): {over}"
    )


def test_the_allow_list_names_only_long_functions():
    """An entry whose function was split (or renamed) leaves the list."""
    long = _long_functions(SOFT_LIMIT)
    stale = [key for key in ALLOWED_LONG if key not in long]
    assert not stale, f"remove from ALLOWED_LONG in tests/test_house.py: {stale}"


# -- import cycles --------------------------------------------------------------------------
def module_name(path: Path, root: Path) -> str:
    """Dotted module name of a source file below ``root`` (a package's ``__init__`` is the
    package)."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imported_names(tree: ast.AST, module: str, is_package: bool) -> Iterator[str]:
    """Every name ``module`` imports: ``import a.b``, ``from a import b`` (as ``a.b``; relative
    ones resolved), and ``importlib.import_module("a.b")`` with a literal name."""
    base = module.split(".") if is_package else module.split(".")[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            origin = node.module or ""
            if node.level:
                anchor = base[: len(base) - node.level + 1]
                origin = ".".join([*anchor, origin] if origin else anchor)
            # a.b when b is a module, else a (the longest prefix that is one)
            yield from (f"{origin}.{alias.name}" for alias in node.names)
        elif (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute | ast.Name)
            and (node.func.attr if isinstance(node.func, ast.Attribute) else node.func.id)
            == "import_module"
            and node.args
            and isinstance(node.args[0], ast.Constant)
            and isinstance(node.args[0].value, str)
        ):
            yield node.args[0].value


def import_graph(root: Path, packages: tuple[str, ...]) -> dict[str, set[str]]:
    """Module -> the modules of ``packages`` it imports (a name that is not a module counts
    for its longest prefix that is)."""
    files = {
        module_name(p, root): p
        for package in packages
        for p in sorted((root / package).rglob("*.py"))
    }
    graph = {}
    for module, path in files.items():
        targets = set()
        tree = ast.parse(path.read_text(), str(path))
        for name in imported_names(tree, module, path.name == "__init__.py"):
            parts = name.split(".")
            while parts and ".".join(parts) not in files:
                parts.pop()
            if parts and ".".join(parts) != module:
                targets.add(".".join(parts))
        graph[module] = targets
    return graph


def import_cycles(graph: dict[str, set[str]]) -> list[set[str]]:
    """The strongly connected components of more than one module."""
    names = sorted(graph)
    index = {m: i for i, m in enumerate(names)}
    rows = [index[m] for m in names for _ in graph[m]]
    cols = [index[t] for m in names for t in sorted(graph[m])]
    adjacency = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(names),) * 2)
    _, label = connected_components(adjacency, directed=True, connection="strong")
    groups: dict[int, set[str]] = {}
    for m, lab in zip(names, label, strict=True):
        groups.setdefault(int(lab), set()).add(m)
    return [g for g in groups.values() if len(g) > 1]


def test_import_cycles_are_found_through_relative_and_importlib_imports(tmp_path):
    """A synthetic package: a -> b by a relative import, b -> a by importlib inside a
    function, c -> a only: one cycle {a, b}."""
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from . import b\n")
    (pkg / "b.py").write_text(
        "import importlib\n\ndef f():\n    importlib.import_module('pkg.a')\n"
    )
    (pkg / "c.py").write_text("from pkg.a import something\n")
    graph = import_graph(tmp_path, ("pkg",))
    assert graph["pkg.a"] == {"pkg.b"} and graph["pkg.c"] == {"pkg.a"}
    assert import_cycles(graph) == [{"pkg.a", "pkg.b"}]


def test_no_import_cycles():
    cycles = [sorted(c) for c in import_cycles(import_graph(REPO, PACKAGES))]
    assert not cycles, f"import cycles: {cycles}"
