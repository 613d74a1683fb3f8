"""The command's place in the layers: iecoop never imports the showcase, and no import cycle runs through it.

The import graph is read from the source with ``ast`` (function-level imports
included), as in :mod:`tests.iecoop.test_imports`.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

from tests.iecoop.test_imports import MODULES, ROOT, _imports, _modules, find_cycle, import_graph


def _patterns_imports() -> list[str]:
    """``module imports target`` for every import of ``patterns`` from iecoop, by statement or by name."""
    found = [
        f"{module} imports {target}"
        for module, path in MODULES.items()
        for target, _ in _imports(module, path)
        if target == "patterns" or target.startswith("patterns.")
    ]
    for module, path in MODULES.items():  # importlib.import_module("patterns.x") is an import too
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value.startswith("patterns."):
                found.append(f"{module} names {node.value!r}")
    return found


def test_iecoop_never_imports_patterns() -> None:
    assert "iecoop.cli.app" in MODULES and "iecoop.cli.trace" in MODULES
    assert _patterns_imports() == []


def test_the_finder_sees_an_import_of_patterns_inside_a_function(tmp_path: Path) -> None:
    graph = import_graph()
    assert {"iecoop.cli.base", "iecoop.cli.st", "iecoop.cli.export", "iecoop.cli.serve"} <= graph["iecoop.cli.app"]
    source = tmp_path / "deferred.py"
    source.write_text("def f() -> None:\n    if True:\n        from patterns.showcase.cli import run_entry\n")
    assert list(_imports("iecoop.cli.deferred", source)) == [("patterns.showcase.cli", ["run_entry"])]


def test_no_import_cycle_in_iecoop_the_patterns_and_the_examples() -> None:
    modules = {**MODULES, **_modules(ROOT / "patterns"), **_modules(ROOT / "iecoop_examples")}
    graph = import_graph(modules)
    assert "patterns.showcase.catalogue" in graph["patterns.showcase.cli"]
    assert not any(target.startswith("patterns") for target in graph["iecoop.cli.st"])
    cycle = find_cycle(graph)
    assert cycle is None, "import cycle: " + " -> ".join(cycle or [])


def test_the_command_runs_without_the_showcase() -> None:
    code = (
        "import sys; sys.modules['patterns'] = None\n"  # any import of patterns fails
        "from iecoop.cli import main\n"
        "status = main(['--help'])\n"
        "print(status, sorted(m for m in sys.modules if m.startswith('patterns')))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "0 ['patterns']"
    assert "st2py" in done.stdout and "tour" not in done.stdout
