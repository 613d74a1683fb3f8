"""A module's showcase declaration: how ``iecoop run`` builds, drives and traces its scenario.

Each pattern, SOLID principle and course example ends with one
``SHOWCASE = Showcase(...)`` next to its ``main()``: the variables the trace
shows (:class:`Column`), what happens to the inputs during the run (the
*script*) and the faults the scenario provokes on purpose. This module is
small and imports no command-line code, so a pattern module may import it;
the catalogue (:mod:`patterns.showcase.catalogue`) imports the pattern
modules and collects their declarations, never the other way round.

A column reads the traced program instance through a function of it:

>>> from iecoop import INT, VAR, Program
>>> class Counter(Program):
...     count: INT = VAR(0)
...     def body(self) -> None:
...         self.count += 1
>>> column = Column("count", lambda p: p.count)
>>> column.source(Counter())
0

A script is called before each cycle; ``steps`` makes one from events, and
``press`` gives the events of a button held for some cycles:

>>> press("start", 2, hold=3)
[(2, 'start', True), (5, 'start', False)]
"""

from __future__ import annotations

import dataclasses
import functools
import re
from collections.abc import Callable, Sequence
from types import ModuleType
from typing import Any

from iecoop import T
from iecoop.runtime import Runtime, Task

__all__ = [
    "Builder",
    "Column",
    "Getter",
    "Scenario",
    "Script",
    "Showcase",
    "chain",
    "flag",
    "hex_word",
    "ms",
    "plc_task",
    "press",
    "resolve",
    "steps",
    "write",
]


@dataclasses.dataclass
class Scenario:
    """A built scenario: the runtime and its program instances (the first one is traced).

    ``sim`` holds the state of a script's plant simulation (a tank level).
    """

    runtime: Runtime
    programs: list[Any]
    module: ModuleType
    sim: dict[str, float] = dataclasses.field(default_factory=dict)

    @property
    def program(self) -> Any:
        """The traced program instance."""
        return self.programs[0]


#: Reads one traced value from a program instance.
Getter = Callable[[Any], object]
#: Called before each cycle with the scenario and the number (from 1) of the cycle about to run.
Script = Callable[[Scenario, int], None]
#: Builds the programs of a scenario on a runtime (adding its tasks) and returns them.
Builder = Callable[[ModuleType, Runtime], Sequence[Any]]


@dataclasses.dataclass(frozen=True)
class Column:
    """One traced variable: a function of the program instance (``lambda p: p.unit.state``) or a dotted path.

    ``of`` picks the program instance among the scenario's programs (0: the
    traced one). ``fmt`` is a format spec (``".1f"``) or a function giving
    the text; ``watch=False`` marks a value that moves every cycle (a
    temperature, a position): it is shown, but its changes alone do not make
    a trace row.
    """

    label: str
    source: str | Getter
    fmt: str | Callable[[Any], str] = ""
    watch: bool = True
    of: int = 0


@dataclasses.dataclass(frozen=True, kw_only=True)
class Showcase:
    """What a module declares as ``SHOWCASE`` for the catalogue.

    ``program`` is the ``Program`` class to trace, or its name (default:
    every concrete ``Program`` of the module, on one ``PlcTask``); ``builder`` builds the
    programs and tasks itself; ``setup`` runs once on the built scenario;
    ``demo`` marks a module without a ``Program``, whose ``main()`` is run
    instead of a trace. ``use_when`` is one line on when the pattern pays off
    on a PLC; ``expected`` lists the deliberate faults as ``(what the trace
    shows, why)``.
    """

    columns: tuple[Column, ...] = ()
    program: type | str | None = None
    script: Script | None = None
    setup: Callable[[Scenario], None] | None = None
    builder: Builder | None = None
    cycles: int = 100
    tour_cycles: int = 30
    title: str = ""
    demo: bool = False
    use_when: str = ""
    expected: tuple[tuple[str, str], ...] = ()


# ---------------------------------------------------------------------------
# Reading and writing variables by path
# ---------------------------------------------------------------------------

_STEP = re.compile(r"([A-Za-z_]\w*)((?:\[-?\d+\])*)$")


@functools.lru_cache(maxsize=None)
def _parse(path: str) -> tuple[tuple[str, tuple[int, ...]], ...]:
    steps = []
    for part in path.split("."):
        match = _STEP.match(part)
        if match is None:
            raise ValueError(f"bad variable path {path!r}: {part!r}")
        indices = tuple(int(i) for i in re.findall(r"-?\d+", match.group(2)))
        steps.append((match.group(1), indices))
    return tuple(steps)


def _walk(root: Any, steps: Sequence[tuple[str, tuple[int, ...]]]) -> Any:
    value = root
    for name, indices in steps:
        value = getattr(value, name)
        for index in indices:
            value = value[index]
    return value


def resolve(root: Any, path: str) -> Any:
    """The value at ``path`` below ``root``: ``resolve(line, "unit.execute.packs")``, ``"drives[1].running"``."""
    return _walk(root, _parse(path))


def write(root: Any, path: str, value: object) -> None:
    """Write ``value`` at ``path`` below ``root`` (only inputs may be written from outside a block)."""
    steps = _parse(path)
    name, indices = steps[-1]
    holder = _walk(root, steps[:-1])
    if indices:
        target = getattr(holder, name)
        for index in indices[:-1]:
            target = target[index]
        target[indices[-1]] = value
    else:
        setattr(holder, name, value)


# ---------------------------------------------------------------------------
# Formats
# ---------------------------------------------------------------------------


def ms(value: Any) -> str:
    """A TIME value as ``250ms``."""
    return f"{int(value)}ms"


def hex_word(value: Any) -> str:
    """A WORD as ST writes it: ``16#00FF``."""
    return f"16#{int(value):04X}"


def flag(value: Any) -> str:
    """A BOOL as a lamp: ``ON`` or ``-``."""
    return "ON" if value else "-"


# ---------------------------------------------------------------------------
# Scripts
# ---------------------------------------------------------------------------


def steps(*events: tuple[int, str, object]) -> Script:
    """A script writing ``value`` to ``path`` before cycle ``n``, for each ``(n, path, value)``."""
    plan: dict[int, list[tuple[str, object]]] = {}
    for cycle, path, value in events:
        plan.setdefault(cycle, []).append((path, value))

    def script(scenario: Scenario, cycle: int) -> None:
        for path, value in plan.get(cycle, ()):
            write(scenario.program, path, value)

    return script


def press(path: str, *cycles: int, hold: int = 1) -> list[tuple[int, str, object]]:
    """Events pressing the button at ``path`` at each of ``cycles``, held for ``hold`` cycles."""
    events: list[tuple[int, str, object]] = []
    for cycle in cycles:
        events += [(cycle, path, True), (cycle + hold, path, False)]
    return events


def chain(*scripts: Script) -> Script:
    """One script running ``scripts`` in order."""

    def script(scenario: Scenario, cycle: int) -> None:
        for each in scripts:
            each(scenario, cycle)

    return script


def plc_task() -> Task:
    """The showcase's cyclic task: ``PlcTask``, 10 ms, priority 20."""
    return Task("PlcTask", interval=T("10ms"), priority=20)
