"""Every pattern, SOLID module and course example, exported as ST, loaded back and run against its Python original.

For each catalogue entry the module is exported (TwinCAT files, and the
plain ST files), loaded with ``st.load``, and its names are bound to the
loaded classes (:func:`iecoop.testing.round_trip.round_trip`); then its
``main()`` and its showcase trace run again and must print exactly what the
Python original printed. A module that cannot round-trip yet is an expected
failure with its reason: the statements the writer leaves out (computed from
the writer's own report) or the first difference (kept by hand in
:data:`KNOWN`). Both are strict, so a module that starts to pass fails the
run until it leaves the list.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import io
import os
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from iecoop.runtime import Runtime
from iecoop.st.write.units import units
from iecoop.st.write.model import collect
from iecoop.st.export import StExportError
from iecoop.testing.round_trip import FORMATS, load_back, rebound
from patterns.showcase import catalogue
from patterns.showcase.catalogue import Entry
from patterns.showcase.cli import run_entry, table
from patterns.showcase.entry import plc_task

ENTRIES = catalogue.entries()
ROOT = Path(__file__).resolve().parents[3]
CATALOGUE_MODULES = sorted({entry.module for entry in catalogue.entries()})

#: Modules that export fully but do not yet run the same once loaded: module -> the first difference
#: (none at present; a module that starts to differ is listed here with its first difference).
KNOWN: dict[str, str] = {}


def exported_modules(entry: Entry) -> list[ModuleType]:
    """The modules whose classes the entry runs: its own, and for a chapter package its solutions'."""
    names = [entry.module] + [m for m in CATALOGUE_MODULES if m.startswith(entry.module + ".")]
    modules = [importlib.import_module(name) for name in names]
    return [module for module in modules if collect(module)]


def untranslated(entry: Entry) -> list[str]:
    """The writer's report of the statements it cannot write as ST, for the entry's modules."""
    found: list[str] = []
    for module in exported_modules(entry):
        _units, left_out = units(collect(module), lenient=True)
        found += [str(item).replace(f"{ROOT}{os.sep}", "") for item in left_out]
    return found


def _param(entry: Entry, fmt: str) -> Any:
    left_out = untranslated(entry)
    marks = []
    if left_out:
        reason = f"{len(left_out)} statement(s) with no ST form yet, the first: {left_out[0]}"
        marks.append(pytest.mark.xfail(strict=True, raises=StExportError, reason=reason))
    elif entry.module in KNOWN:
        marks.append(pytest.mark.xfail(strict=True, reason=KNOWN[entry.module]))
    return pytest.param(entry, fmt, id=f"{entry.name}-{fmt}", marks=marks)


# ---------------------------------------------------------------------------
# What a run shows: main()'s output, the trace table
# ---------------------------------------------------------------------------


def captured(function: Callable[[], object]) -> list[str]:
    """What ``function()`` prints and returns, or the exception it ends with, as lines."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        try:
            result = function()
        except Exception as exc:
            ending = f"raised {type(exc).__name__}: {exc}"
        else:
            ending = f"returned {result!r}"
    return out.getvalue().splitlines() + [ending]


def program_names(entry: Entry) -> list[str]:
    """The names of the programs the entry builds (read from the Python classes, before any rebinding)."""
    if entry.program is not None:
        return [entry.program if isinstance(entry.program, str) else entry.program.__name__]
    return [cls.__name__ for cls in catalogue.program_classes(entry.load())]


class Recorder:
    """Builds the entry's programs by name, from whatever the module holds now, and keeps them."""

    def __init__(self, entry: Entry, names: list[str]) -> None:
        self.builder = entry.builder
        self.names = names
        self.programs: list[Any] = []

    def __call__(self, module: ModuleType, runtime: Runtime) -> Sequence[Any]:
        if self.builder is not None:
            self.programs = list(self.builder(module, runtime))
        else:
            self.programs = [getattr(module, name)() for name in self.names]
            runtime.add_task(plc_task(), *self.programs)
        return self.programs


def traced(entry: Entry, names: list[str]) -> tuple[list[str], list[Any]]:
    """The entry's trace table over its cycles (with the fault, if any) and the programs it ran."""
    recorder = Recorder(entry, names)
    trace = run_entry(dataclasses.replace(entry, builder=recorder, program=None), entry.cycles)
    fault = [] if trace.fault is None else [f"fault in cycle {trace.fault_cycle}: {trace.fault.code.name} {trace.fault_message}"]
    return table(trace) + fault, recorder.programs


def first_difference(python: list[str], loaded: list[str]) -> str:
    for number, (want, got) in enumerate(zip(python, loaded), 1):
        if want != got:
            return f"line {number}: Python {want!r}, ST {got!r}"
    return f"Python has {len(python)} lines, ST {len(loaded)}"


# ---------------------------------------------------------------------------
# The round trip
# ---------------------------------------------------------------------------


#: The catalogue goes through the TwinCAT files, what a PLC project imports. The plain-text form goes
#: through the same reader once the files are unpacked; it is checked on the course chapters, where
#: every construct of the language appears, so the whole run stays within the time CI allows.
def _formats(entry: Entry) -> tuple[str, ...]:
    return FORMATS if entry.module.startswith("iecoop_examples.") else ("twincat",)


@pytest.mark.slow  # blark reads every exported file (about a second a module)
@pytest.mark.parametrize(("entry", "fmt"), [_param(entry, fmt) for entry in ENTRIES for fmt in _formats(entry)])
def test_catalogue_round_trip(entry: Entry, fmt: str) -> None:
    assert entry.runnable, entry.problem
    modules = exported_modules(entry)
    loaded = [load_back(module, fmt) for module in modules]
    module = entry.load()
    main = getattr(module, "main", None)
    names = [] if entry.demo else program_names(entry)
    python_main = captured(main) if main is not None else []
    python_trace = traced(entry, names)[0] if not entry.demo else []
    with contextlib.ExitStack() as stack:
        for original, back in zip(modules, loaded):
            stack.enter_context(rebound(original, back))
        if main is not None:
            st_main = captured(module.main)
            assert st_main == python_main, first_difference(python_main, st_main)
        if not entry.demo:
            st_trace, programs = traced(entry, names)
            assert programs and all(type(p).__module__ in {m.__name__ for m in loaded} for p in programs)
            assert st_trace == python_trace, first_difference(python_trace, st_trace)
