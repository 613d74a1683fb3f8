"""The showcase: every pattern, SOLID principle and course example, runnable as the ``iecoop`` command.

- :mod:`patterns.showcase.entry`: ``Showcase`` and ``Column``, the declaration each module
  makes next to its ``main()`` (small, no command-line code: pattern modules import it).
- :mod:`patterns.showcase.catalogue`: finds the modules and collects their declarations as entries,
  and offers their names to ``iecoop export`` and ``iecoop serve`` (``NAMES``).
- :mod:`patterns.showcase.cli`: the ``iecoop`` command: the showcase's ``tour``, ``list``, ``show``
  and ``run``, composed with the subcommands of :mod:`iecoop.cli` (``st2py``, ``st``, ``export``,
  ``serve``).
- :mod:`patterns.showcase.serve` and :mod:`patterns.showcase.text`: ``iecoop serve NAME``, and the
  docstrings rendered for a terminal.

The command's names (``main``, ``run_entry``, ...) are found here too, imported on first use, so
that importing a pattern module (which imports ``entry``) does not import the command.
"""

from __future__ import annotations

import importlib
from typing import Any

#: The names of :mod:`patterns.showcase.cli` that this package hands out.
_CLI = frozenset(
    ["COMMANDS", "Command", "Progress", "RowWriter", "SHOW_SECTIONS", "TOUR_CATEGORIES", "TraceTable", "main", "run_entry",
     "table"]
)


def __getattr__(name: str) -> Any:
    """``patterns.showcase.main`` and the other names of the command, from :mod:`patterns.showcase.cli`."""
    if name in _CLI:
        return getattr(importlib.import_module("patterns.showcase.cli"), name)
    raise AttributeError(f"module 'patterns.showcase' has no attribute {name!r}")
