"""The module structure of iecoop: no import cycle, and the outer packages use only public names.

The import graph is read from the source with ``ast``: every ``import`` of a
module, at module level and inside functions (an import deferred into a
function still ties the two modules together), except those under
``if TYPE_CHECKING:``, which never run.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator, Mapping
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent.parent
PACKAGE = ROOT / "iecoop"

#: Packages above the runtime that use only the public API below them (and the process-wide switch,
#: and the one compiler of generated Python, so its scripts are numbered and registered in one place).
OUTER = ("iecoop.opcua", "iecoop.uml", "iecoop.stdlib", "iecoop.testing", "iecoop.st", "iecoop.runtime", "iecoop.libraries")
ALLOWED_PRIVATE = frozenset({"iecoop._config", "iecoop._codegen"})


def _modules(package: Path = PACKAGE) -> dict[str, Path]:
    found = {}
    for path in package.rglob("*.py"):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


MODULES = _modules()


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _imports(module: str, path: Path, modules: Mapping[str, Path] = MODULES) -> Iterator[tuple[str, list[str]]]:
    """``(imported module, names imported from it)`` for each import that runs."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]

    def visit(nodes: list[ast.stmt]) -> Iterator[tuple[str, list[str]]]:
        for node in nodes:
            if isinstance(node, ast.If) and _is_type_checking(node):
                yield from visit(node.orelse)
            elif isinstance(node, ast.Import):
                yield from ((alias.name, []) for alias in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    parent = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join([*parent, *([node.module] if node.module else [])])
                for alias in node.names:
                    # ``from iecoop import _config`` imports the module iecoop._config
                    full = f"{base}.{alias.name}"
                    yield (full, []) if full in modules else (base, [alias.name])
            else:
                for field in ("body", "orelse", "finalbody", "handlers"):
                    inner = getattr(node, field, None)
                    if isinstance(inner, list):
                        yield from visit(inner)

    yield from visit(ast.parse(path.read_text(encoding="utf-8")).body)


def import_graph(modules: Mapping[str, Path] = MODULES) -> dict[str, set[str]]:
    """Module -> the modules of ``modules`` it imports (by default iecoop's)."""
    return {
        module: {target for target, _ in _imports(module, path, modules) if target in modules and target != module}
        for module, path in modules.items()
    }


def find_cycle(graph: Mapping[str, set[str]]) -> list[str] | None:
    """One import cycle as a path ``[a, b, ..., a]``, or None when the graph is acyclic."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for target in sorted(graph.get(node, ())):
            if state.get(target) == 1:
                return path[path.index(target):] + [target]
            if target not in state and (cycle := visit(target)) is not None:
                return cycle
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state and (cycle := visit(node)) is not None:
            return cycle
    return None


def test_the_cycle_finder_finds_a_cycle() -> None:
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None


def test_the_graph_reads_every_module_and_deferred_imports() -> None:
    graph = import_graph()
    assert {"iecoop.pou", "iecoop.memory._handles", "iecoop.stdlib.timers", "iecoop.uml.svg"} <= set(graph)
    assert "iecoop.gvl" in graph["iecoop.pou"]  # VAR_EXTERNAL finds its global variable list
    assert "iecoop._config" in graph["iecoop.pou"]  # ``from iecoop import _config`` is the module


def test_no_import_cycle_inside_iecoop() -> None:
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle or [])


def _private(dotted: str) -> bool:
    return any(part.startswith("_") for part in dotted.split("."))


@pytest.mark.parametrize("outer", OUTER)
def test_the_outer_packages_import_no_private_name_of_another_package(outer: str) -> None:
    found = []
    for module, path in MODULES.items():
        if module != outer and not module.startswith(outer + "."):
            continue
        for target, names in _imports(module, path):
            if not target.startswith("iecoop") or target == outer or target.startswith(outer + "."):
                continue
            private = [target] if _private(target) and target not in ALLOWED_PRIVATE else []
            private += [f"{target}.{name}" for name in names if name.startswith("_") and name != "_config"]
            found += [f"{module} imports {name}" for name in private]
    assert not found, "\n".join(sorted(set(found)))


def test_the_public_memory_names_live_in_public_modules() -> None:
    """A reader finds a type in the module named after it, not in the private engine."""
    import iecoop.memory

    homes = {name: getattr(iecoop.memory, name).__module__ for name in iecoop.memory.__all__}
    assert not {name: home for name, home in homes.items() if _private(home)}
    # REFERENCE_TO is an Annotated alias, whose __module__ is typing's from CPython 3.12 on: ask its module instead
    from iecoop.memory import references

    assert iecoop.memory.REFERENCE_TO is references.REFERENCE_TO and "REFERENCE_TO" in references.__all__
    assert homes["NullInterface"] == "iecoop.memory.interface_references"
    assert homes["Alias"] == "iecoop.memory.aliases"
