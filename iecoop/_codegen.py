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

import itertools
import linecache
import types
from typing import Any

__all__ = ["compile_source", "compiled", "script_number"]

_numbers = itertools.count(1)


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
