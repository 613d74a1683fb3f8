"""The showcase catalogue: every pattern, SOLID principle and course example, ready to run.

The catalogue only collects. Each module declares its own scenario as
``SHOWCASE = Showcase(...)`` next to its ``main()`` (see
:mod:`patterns.showcase.entry`): how to build it on a runtime (its
``Program`` on a 10 ms ``PlcTask``), what to do to its inputs during the
run (the *script*) and which variables the trace shows. :func:`entries`
walks the packages, imports each module and turns its declaration into an
:class:`Entry`; a module without one gets a generic entry: its ``Program``
and its first elementary outputs.

>>> state = find("state")
>>> state.category, state.module
('behavioral', 'patterns.behavioral.state')
>>> scenario = build(state)
>>> scenario.runtime.run(cycles=1)
>>> [column.label for column in state.columns]
['state', 'packs', 'transitions', 'refused', 'batches']
>>> [show(read(scenario, column)) for column in state.columns]
['RESETTING', '0', '1', '0', '0']
"""

from __future__ import annotations

import difflib
import dataclasses
import importlib
import inspect
import pkgutil
import re
from collections.abc import Callable, Iterator, Sequence
from types import ModuleType
from typing import Any

from iecoop import Program
from iecoop.cli import Names, Served, UsageError
from iecoop.cli.trace import TIME_CLASSES, elementary_variables, show
from iecoop.runtime import Runtime
from patterns.showcase.entry import (
    Column,
    Scenario,
    Showcase,
    ms,
    plc_task,
    press,
    resolve,
    steps,
    write,
)

__all__ = [
    "CATEGORIES",
    "Column",
    "NAMES",
    "Entry",
    "Scenario",
    "Showcase",
    "build",
    "entries",
    "find",
    "plc_task",
    "unknown_name",
    "press",
    "read",
    "show",
    "steps",
    "write",
]

#: Category key -> heading, in catalogue order.
CATEGORIES: dict[str, str] = {
    "creational": "Creational patterns",
    "structural": "Structural patterns",
    "behavioral": "Behavioral patterns",
    "solid": "SOLID principles",
    "examples": "Course examples",
}

#: The packages searched for modules, by category.
_PACKAGES: dict[str, str] = {
    "creational": "patterns.creational",
    "structural": "patterns.structural",
    "behavioral": "patterns.behavioral",
    "solid": "patterns.solid",
    "examples": "iecoop_examples",
}

#: Categories listed in an order of their own rather than by module name: S, O, L, I, D.
_ORDER: dict[str, tuple[str, ...]] = {"solid": ("srp", "ocp", "lsp", "isp", "dip")}

#: Entries for modules outside the searched packages (a test's own program), listed first in their category.
ENTRIES: tuple[Entry, ...] = ()


@dataclasses.dataclass(frozen=True)
class Entry(Showcase):
    """One module of the catalogue and how to run it: its name, category and module, and its :class:`Showcase`.

    ``generic`` marks an entry made by discovery rather than declared by
    its module; ``demo`` one whose module has no ``Program`` but a
    ``main()``, which ``iecoop run`` calls instead of tracing; ``problem``
    says why an entry cannot run (its module does not import, or has
    nothing to run).
    """

    name: str
    category: str
    module: str
    generic: bool = False
    problem: str = ""

    @property
    def runnable(self) -> bool:
        """False when the module cannot be imported or has no ``Program`` to run."""
        return not self.problem

    def load(self) -> ModuleType:
        """Import the entry's module."""
        return importlib.import_module(self.module)

    def heading(self) -> str:
        """The title: the first line of the module docstring unless the entry sets one."""
        if self.title:
            return self.title
        try:
            doc = inspect.getdoc(self.load()) or ""
        except Exception as exc:  # a module being edited may not import
            return f"(cannot import: {type(exc).__name__})"
        first = doc.strip().splitlines()[0] if doc.strip() else self.module
        return first.replace("``", "")


def read(scenario: Scenario, column: Column) -> object:
    """The current value of ``column`` in ``scenario``."""
    program = scenario.programs[column.of]
    if isinstance(column.source, str):
        return resolve(program, column.source)
    return column.source(program)


# ---------------------------------------------------------------------------
# Building
# ---------------------------------------------------------------------------


def program_classes(module: ModuleType) -> list[type[Program]]:
    """The concrete ``Program`` subclasses defined in ``module``, in definition order."""
    found: list[tuple[int, type[Program]]] = []
    for value in vars(module).values():
        if (
            isinstance(value, type)
            and issubclass(value, Program)
            and value is not Program
            and value.__module__ == module.__name__
            and not value.__iec__.abstract
        ):
            try:
                line = inspect.getsourcelines(value)[1]
            except (OSError, TypeError):
                line = 0
            found.append((line, value))
    return [cls for _, cls in sorted(found, key=lambda item: item[0])]


def build(entry: Entry, profile: str = "twincat") -> Scenario:
    """Instantiate the entry's programs on a fresh ``Runtime(store=":memory:")`` and run its setup."""
    if entry.problem or entry.demo:
        raise LookupError(f"{entry.name}: {entry.problem or 'no Program to build: run its main()'}")
    module = entry.load()
    runtime = Runtime(store=":memory:", profile=profile)
    if entry.builder is not None:
        programs = list(entry.builder(module, runtime))
    else:
        if entry.program is not None:
            program = getattr(module, entry.program) if isinstance(entry.program, str) else entry.program
            classes: list[type[Program]] = [program]
        else:
            classes = program_classes(module)
        programs = [cls() for cls in classes]
        runtime.add_task(plc_task(), *programs)
    scenario = Scenario(runtime, programs, module)
    if entry.setup is not None:
        entry.setup(scenario)
    return scenario


def generic_columns(cls: type[Program], limit: int = 5) -> tuple[Column, ...]:
    """The first ``limit`` elementary variables of ``cls``: VAR_OUTPUT, VAR, then the nested blocks' outputs.

    VAR_INPUT is used only when nothing else is found.
    """
    return tuple(Column(name, name, ms if kind in TIME_CLASSES else "") for name, kind in elementary_variables(cls, limit))


# ---------------------------------------------------------------------------
# Discovery
# ---------------------------------------------------------------------------


def _import_package(package: str) -> ModuleType | None:
    """Import ``package``, or None when it is not installed."""
    try:
        return importlib.import_module(package)
    except ImportError:
        return None


def _modules(package: str) -> Iterator[str]:
    root = _import_package(package)
    if root is None:
        return
    for info in pkgutil.walk_packages(root.__path__, prefix=f"{package}.", onerror=lambda name: None):
        leaf = info.name.rsplit(".", 1)[-1]
        if leaf.startswith(("_", "test")):
            continue
        yield info.name


def _no_arguments(function: Callable[..., object]) -> bool:
    try:
        parameters = inspect.signature(function).parameters.values()
    except (TypeError, ValueError):
        return False
    return all(p.default is not p.empty or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in parameters)


def _generic_entry(name: str, category: str, module_name: str) -> Entry | None:
    try:
        module = importlib.import_module(module_name)
    except Exception as exc:
        return Entry(name, category, module_name, generic=True, problem=f"cannot import: {type(exc).__name__}: {exc}")
    classes = program_classes(module)
    if not classes:
        main = getattr(module, "main", None)
        if callable(main) and _no_arguments(main):
            return Entry(name, category, module_name, generic=True, demo=True)
        if getattr(module, "__path__", None) is not None:
            return None  # a package of examples, not an example
        return Entry(name, category, module_name, generic=True, problem="no Program and no main() to run")
    try:
        columns = generic_columns(classes[0])
    except Exception as exc:
        return Entry(name, category, module_name, generic=True, problem=f"cannot build: {type(exc).__name__}: {exc}")
    return Entry(name, category, module_name, columns=columns, generic=True)


def _declared_entry(name: str, category: str, module_name: str, showcase: Showcase) -> Entry:
    """The entry of a module's ``SHOWCASE`` declaration."""
    fields = {field.name: getattr(showcase, field.name) for field in dataclasses.fields(showcase)}
    return Entry(name, category, module_name, **fields)


def _collect(name: str, category: str, module_name: str) -> Entry | None:
    """The entry of a module: its own declaration, or a generic one (None for a package of examples)."""
    try:
        module = importlib.import_module(module_name)
    except Exception as exc:
        return Entry(name, category, module_name, generic=True, problem=f"cannot import: {type(exc).__name__}: {exc}")
    declared = getattr(module, "SHOWCASE", None)
    if isinstance(declared, Showcase):
        return _declared_entry(name, category, module_name, declared)
    return _generic_entry(name, category, module_name)


def _ordered(category: str, modules: list[str]) -> list[str]:
    order = _ORDER.get(category, ())
    leaf = {m: m.rsplit(".", 1)[-1] for m in modules}
    return sorted(modules, key=lambda m: order.index(leaf[m]) if leaf[m] in order else len(order))


def _short_names(category: str, modules: Sequence[str]) -> dict[str, str]:
    """Module -> short name: ``factory_method`` -> ``factory-method``; ``iecoop_examples.ch09_x`` -> ``ch09``."""
    base = {m: m.rsplit(".", 1)[-1].replace("_", "-").lower() for m in modules}
    if category == "examples":
        prefixes = {m: re.match(r"(ch\d+)", name) for m, name in base.items()}
        counts: dict[str, int] = {}
        for match in prefixes.values():
            if match:
                counts[match.group(1)] = counts.get(match.group(1), 0) + 1
        for m, match in prefixes.items():
            if match and counts[match.group(1)] == 1:
                base[m] = match.group(1)
    clashes = {n for n in base.values() if list(base.values()).count(n) > 1}
    for m, name in base.items():
        if name in clashes:
            base[m] = m.split(".", 1)[-1].replace(".", "-").replace("_", "-").lower()
    return base


def _found() -> Iterator[tuple[str, str, str]]:
    """``(category, module, name)`` of every module in the packages, in catalogue order, without importing it."""
    known = {entry.module for entry in ENTRIES}
    taken = {entry.name for entry in ENTRIES}
    for category, package in _PACKAGES.items():
        found = _ordered(category, [m for m in _modules(package) if m not in known])
        for module_name, name in _short_names(category, found).items():
            if name in taken:
                name = f"{category}-{name}"
            taken.add(name)
            yield category, module_name, name


def entries() -> list[Entry]:
    """Every entry, by category: those of :data:`ENTRIES`, then every module found (examples by chapter)."""
    found = list(_found())
    result: list[Entry] = []
    for category in _PACKAGES:
        group = [entry for entry in ENTRIES if entry.category == category]
        for where, module_name, name in found:
            entry = _collect(name, category, module_name) if where == category else None
            if entry is not None:
                group.append(entry)
        if category == "examples":
            group.sort(key=lambda entry: entry.module)  # chapter order
        result += group
    return result


def names() -> list[str]:
    """The short names of every entry."""
    return [entry.name for entry in entries()]


def normalise(name: str) -> str:
    """``Factory_Method`` -> ``factory-method``."""
    return name.strip().lower().replace("_", "-")


def unknown_name(name: str, command: str) -> str:
    """The message for a name no entry has, with the closest names: ``iecoop: unknown name 'stat'. Did you mean ...``."""
    names = [entry.name for entry in entries()]
    wanted = normalise(name)
    close = difflib.get_close_matches(wanted, names, n=4, cutoff=0.6)
    close += [n for n in names if wanted and wanted in n and n not in close]
    hint = f" Did you mean: {', '.join(close[:5])}?" if close else ""
    return f"{command}: unknown name {name!r}.{hint} 'iecoop list' shows every name.\n"


def find(name: str) -> Entry:
    """The entry called ``name`` (case and ``_`` / ``-`` do not matter); KeyError if there is none."""
    wanted = normalise(name)
    for entry in ENTRIES:
        if entry.name == wanted or entry.module == name:
            return entry
    # Only the module asked for is imported: 'iecoop run NAME' does not load the whole catalogue.
    for category, module_name, short in _found():
        if short == wanted or module_name == name:
            collected = _collect(short, category, module_name)
            if collected is not None:
                return collected
    raise KeyError(name)


# ---------------------------------------------------------------------------
# The catalogue's names in the iecoop command (export NAME, serve NAME)
# ---------------------------------------------------------------------------


def _module(name: str) -> ModuleType | None:
    try:
        return find(name).load()
    except KeyError:
        return None


def _scenario(name: str, profile: str) -> Served | None:
    try:
        entry = find(name)
    except KeyError:
        return None
    if entry.problem or entry.demo:
        raise UsageError(f"{entry.name} cannot be served: {entry.problem or 'it has no Program'}")
    scenario = build(entry, profile)
    script = entry.script
    return Served(entry.name, f"{entry.name} -- {entry.heading()}", scenario.runtime,
                  None if script is None else lambda cycle: script(scenario, cycle))


#: The catalogue as the names ``iecoop export`` and ``iecoop serve`` accept.
NAMES = Names("catalogue entry", _module, _scenario, unknown_name)
