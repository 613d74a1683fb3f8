"""Python that iecoop generates, compiled once and registered so tracebacks show its lines.

The class builder (``__call__`` of each FB), the parameter wrappers and the ST
reader all generate Python text. Each script gets a unique file name, its text goes
into ``linecache`` (so a traceback through generated code prints the real line,
as for a file), and it is compiled and run once; nothing of this runs on a call.

>>> namespace = compile_source("def twice(x):\\n    return 2 * x\\n", "example", {})
>>> namespace["twice"](21), namespace["twice"].__code__.co_filename.startswith("<iecoop generated example #")
(42, True)
"""

from __future__ import annotations

import ast
import itertools
import linecache
import types
import weakref
from typing import Any

__all__ = ["compile_source", "compiled", "definition", "python_source", "register_definition", "script_number"]

_numbers = itertools.count(1)
#: Code compiled under another file's name (ST source maps), by identity: the code (weakly), its ``def`` node and
#: the Python module text it is from. Not by value: two loads of one file make equal code objects.
_definitions: dict[int, tuple[weakref.ref[types.CodeType], ast.AST, str]] = {}


def script_number() -> int:
    """A number no other generated script has, to keep file and module names apart."""
    return next(_numbers)


def compiled(source: str, filename: str) -> types.CodeType:
    """``source`` compiled under ``filename``, its lines registered in ``linecache`` first."""
    linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
    return compile(source, filename, "exec")


def compile_source(source: str, name_hint: str, namespace: dict[str, Any]) -> dict[str, Any]:
    """Run ``source`` in ``namespace`` as the script ``<iecoop generated name_hint #n>``; ``namespace`` is returned."""
    exec(compiled(source, f"<iecoop generated {name_hint} #{script_number()}>"), namespace)  # noqa: S102 - iecoop's own generated code
    return namespace


def register_definition(code: types.CodeType, node: ast.AST, module_text: str) -> None:
    """Record the ``def`` node of ``code``, whose file (an ST file) does not hold its Python source."""
    key = id(code)

    def forget(ref: weakref.ref[types.CodeType]) -> None:
        if _definitions.get(key, (None,))[0] is ref:
            del _definitions[key]

    _definitions[key] = (weakref.ref(code, forget), node, module_text)


def definition(code: types.CodeType | None) -> tuple[ast.AST, str] | None:
    """The ``def`` node and module text recorded for ``code`` (loaded ST), or None: read the source file then."""
    entry = _definitions.get(id(code)) if isinstance(code, types.CodeType) else None
    if entry is None or entry[0]() is not code:
        return None
    return entry[1], entry[2]


def python_source(func: Any) -> str:
    """The Python source of ``func``: as generated for loaded ST (its file holds ST), else ``inspect.getsource``."""
    import inspect

    registered = definition(getattr(inspect.unwrap(func), "__code__", None))
    text = getattr(registered[0], "iecoop_python", None) if registered is not None else None
    return text if isinstance(text, str) else inspect.getsource(func)
