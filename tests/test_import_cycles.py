"""No import cycles among the modules of ``src/workcell``.

Every ``import`` and ``from ... import`` statement of every module counts, wherever it
stands: at module level, inside a function (a lazy import still ties the two modules: the
one cannot be understood, moved or tested without the other), and under
``if TYPE_CHECKING:`` (the type checker follows it). An import names one module: ``from
workcell.a import b`` names ``workcell.a.b`` when that is a module, else ``workcell.a``
(its ``__init__``). The packages above a module named are not counted as imported: they
run first, but a package's ``__init__`` only hands names on, and a circle through one
shows where that ``__init__`` itself imports.
"""

from __future__ import annotations

import ast
from pathlib import Path

import workcell

ROOT = Path(workcell.__file__).parent
PACKAGE = "workcell"


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules() -> dict[str, Path]:
    return {module_name(path): path for path in sorted(ROOT.rglob("*.py"))}


def imported(name: str, path: Path, known: set[str]) -> set[str]:
    """The modules of the package that the module ``name`` (at ``path``) imports."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            for alias in node.names:
                full = f"{base}.{alias.name}"
                out.add(full if full in known else base)
    return {m for m in out if m in known and m != name}


def import_graph() -> dict[str, set[str]]:
    found = modules()
    known = set(found)
    return {name: imported(name, path, known) for name, path in found.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One circle (``a -> b -> ... -> a``) per strongly connected group of modules
    (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups: list[list[str]] = []
    for start in sorted(graph):
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                group = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == node:
                        break
                if len(group) > 1:
                    groups.append(sorted(group))
    return [circle(graph, group) for group in groups]


def circle(graph: dict[str, set[str]], group: list[str]) -> list[str]:
    """A shortest path from the group's first module back to itself, inside the group."""
    members = set(group)
    start = group[0]
    paths = {start: [start]}
    frontier = [start]
    while frontier:
        nxt = []
        for node in frontier:
            for child in sorted(graph[node] & members):
                if child == start:
                    return [*paths[node], start]
                if child not in paths:
                    paths[child] = [*paths[node], child]
                    nxt.append(child)
        frontier = nxt
    raise AssertionError(f"{group} is not strongly connected")


def test_no_module_of_the_package_imports_itself_in_a_circle() -> None:
    found = cycles(import_graph())
    assert found == [], "import cycles:\n" + "\n".join(" -> ".join(c) for c in found)


def test_the_walk_sees_imports_at_every_level(tmp_path: Path) -> None:
    graph = {
        "workcell.a": {"workcell.b"},
        "workcell.b": {"workcell.c"},
        "workcell.c": {"workcell.a"},
        "workcell.d": {"workcell.a"},
    }
    assert cycles(graph) == [["workcell.a", "workcell.b", "workcell.c", "workcell.a"]]
    module = tmp_path / "m.py"
    module.write_text(
        "from typing import TYPE_CHECKING\n"
        "import workcell.x\n"
        "if TYPE_CHECKING:\n    from workcell.y import Thing\n"
        "def f():\n    from workcell import z\n    from . import w\n"
    )
    known = {"workcell.x", "workcell.y", "workcell.z", "workcell.w", "workcell"}
    assert imported("workcell.m", module, known) == {
        "workcell.x",
        "workcell.y",
        "workcell.z",
        "workcell.w",
    }
