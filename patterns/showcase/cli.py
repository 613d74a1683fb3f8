"""The ``iecoop`` command: list the patterns and examples and run them on the cyclic runtime.

::

    iecoop                                   a short tour of every pattern
    iecoop list                              the names, by category
    iecoop run state --cycles 200            one scenario, with its trace table
    iecoop run state --every 10 --profile codesys
    iecoop show state                        the module's documentation and file

``run`` builds the scenario (the module's ``Program`` on a 10 ms ``PlcTask``
of a ``Runtime(store=":memory:")``, in virtual time), runs it cycle by cycle
and prints the variables that matter as the cycles run: by default only the
cycles where one of them changed, with ``--every K`` every K-th cycle. On a
terminal a progress line follows the rows; into a pipe the rows alone are
written, and a reader that stops early (``iecoop run state | head``) ends
the run quietly. Cycles are counted from 1 everywhere, in the table and in a
fault report. An unknown name or a bad option exits with status 2, a PLC
fault during the run with status 1.

>>> main(["run", "state", "--cycles", "60"])
state -- State: the PackML unit state machine, one function block per state.
  expected: refused (part of the scenario: Start is pressed again while the unit is already in EXECUTE)
PackagingLine on PlcTask (10 ms), twincat profile, 60 cycles; rows where a traced value changed
time ms  cycle  state      packs  transitions  refused  batches
      0      1  RESETTING      0            1        0        0
    200     21  IDLE           0            2        0        0
    210     22  STARTING       0            3        0        0
    510     52  EXECUTE        0            4        0        0
    590     60  EXECUTE        0            4        0        0
0

The subcommands are one table, :data:`COMMANDS`: the showcase's own
(``tour``, ``list``, ``show``, ``run``) and those of :mod:`iecoop.cli`
(``st2py``, ``st``, ``export``, ``serve``), which take the catalogue's
names through :data:`~patterns.showcase.catalogue.NAMES`. A new one is a
:class:`~iecoop.cli.Command` added there, with its arguments and the
function it runs.
"""

from __future__ import annotations

import argparse
import functools
import inspect
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import TextIO

from iecoop import PlcException
from iecoop.cli import Command, commands
from iecoop.cli import main as iecoop_main
from iecoop.cli.base import positive, usage_errors
from iecoop.cli.export import module_of
from iecoop.cli.trace import (
    Probe, Progress, Row, RowWriter, TraceTable, add_trace_arguments, check_trace_options,
    fault_text, run_cycles, run_streamed, table, widest, write_trace,
)
from iecoop.st.export import StExportError, dump
from patterns.showcase.catalogue import CATEGORIES, NAMES, Entry, build, entries, find, read, show, unknown_name
from patterns.showcase.text import render_rst
from patterns.showcase.entry import Column, Scenario

__all__ = [
    "COMMANDS", "Command", "Progress", "RowWriter", "SHOW_SECTIONS", "TOUR_CATEGORIES", "TraceTable", "main", "run_entry",
    "st_text", "table",
]

#: The tour's categories (the course examples are listed and run, not toured).
TOUR_CATEGORIES = ("creational", "structural", "behavioral", "solid")
#: TraceTable rows shown per pattern in the tour (first and last included).
TOUR_ROWS = 20


def _width(scenario: Scenario, column: Column) -> int:
    """The widest text a column's type allows (an enumeration's longest name), read once before the run.

    A value that cannot be read yet (a pointer the first cycle sets) leaves the column to grow as it goes.
    """
    if column.fmt:
        return 0
    try:
        return widest(read(scenario, column))
    except PlcException:
        return 0


def run_entry(
    entry: Entry,
    cycles: int,
    *,
    every: int | None = None,
    profile: str = "twincat",
    progress: Callable[[int], None] | None = None,
    on_start: Callable[[TraceTable], None] | None = None,
    on_row: Callable[[Row], None] | None = None,
    paths: Sequence[str] = (),
) -> TraceTable:
    """Build ``entry`` and run it ``cycles`` cycles; keep every ``every``-th row, or the rows that changed.

    With symbol ``paths`` the table shows them, recorded by a runtime trace
    (``trace.source``), instead of the entry's columns.

    The first and the last cycle are always kept. ``on_start`` is called once
    the scenario is built (``trace.where`` names its tasks); with ``on_row``
    each row is handed over as its cycle ends instead of being kept in
    ``trace.rows``, so a run of any length streams in constant memory.
    """
    try:
        scenario = build(entry, profile)
    except PlcException as exc:
        return TraceTable([column.label for column in entry.columns], fault=exc, fault_message=exc.message)
    probes = [
        Probe(column.label, functools.partial(lambda column: show(read(scenario, column), column.fmt), column),
              column.watch, _width(scenario, column))
        for column in entry.columns
    ]
    script = entry.script
    return run_cycles(
        scenario.runtime, probes, cycles, every=every, progress=progress, on_start=on_start, on_row=on_row, paths=paths,
        before_cycle=None if script is None else lambda cycle: script(scenario, cycle),
    )


def st_text(entry_name: str, *, lenient: bool = False, report: list[str] | None = None) -> str:
    """The generated ST of an entry (what ``iecoop show NAME --st`` prints): strict, as ``iecoop export`` is,
    unless ``lenient`` (then a statement with no ST form is an ST comment, listed in ``report``).

    >>> "FUNCTION_BLOCK TemperatureTransmitter IMPLEMENTS ISubject" in st_text("observer")
    True
    """
    return dump(module_of(entry_name, NAMES), lenient=lenient, report=report)


def _expected(entry: Entry) -> list[str]:
    return [f"expected: {what} (part of the scenario: {why})" for what, why in entry.expected]


def _lookup(name: str, err: TextIO) -> Entry | None:
    try:
        return find(name)
    except KeyError:
        err.write(unknown_name(name, "iecoop"))
        return None


# ---------------------------------------------------------------------------
# The subcommands
# ---------------------------------------------------------------------------


def _cmd_list(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    known = entries()
    width = max(len(entry.name) for entry in known)
    groups = [(heading, [e for e in known if e.category == category]) for category, heading in CATEGORIES.items()]
    for number, (heading, group) in enumerate((h, g) for h, g in groups if g):
        if number:
            out.write("\n")
        out.write(f"{heading}\n")
        for entry in group:
            note = f"  [{entry.problem}]" if entry.problem else ""
            out.write(f"  {entry.name:<{width}}  {entry.heading()}{note}\n")
    return 0


def _documentation(entry: Entry, module: ModuleType) -> str | None:
    doc = module.__doc__
    return render_rst(inspect.cleandoc(doc)) if doc else "(no documentation)"


def _python_file(entry: Entry, module: ModuleType) -> str | None:
    path = getattr(module, "__file__", None)
    return f"Python: {Path(path).resolve()}" if path else None


#: What ``iecoop show`` prints for a module, in order: each function gives a block of text or None.
#: ``show --st`` then adds the module as Structured Text.
SHOW_SECTIONS: list[Callable[[Entry, ModuleType], str | None]] = [_python_file, _documentation]


def _cmd_show(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    entry = _lookup(args.name, err)
    if entry is None:
        return 2
    try:
        module = entry.load()
    except Exception as exc:
        err.write(f"iecoop: {entry.name}: cannot import {entry.module}: {type(exc).__name__}: {exc}\n")
        return 1
    blocks = [f"{entry.name} ({entry.module})"]
    blocks += [text for section in SHOW_SECTIONS if (text := section(entry, module)) is not None]
    if args.st:
        comments: list[str] = []
        try:
            text = st_text(entry.name, lenient=args.lenient, report=comments)
        except StExportError as exc:
            err.write(f"iecoop show: {entry.name}: {exc} (--lenient writes it as an ST comment)\n")
            return 1
        err.writelines(f"iecoop show: written as a comment: {line}\n" for line in comments)
        blocks.append("Structured Text (generated by iecoop.st.export; 'iecoop export' writes TwinCAT files):\n\n" + text)
    out.write("\n\n".join(blocks) + "\n")
    return 0


def _cmd_run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    entry = _lookup(args.name, err)
    if entry is None:
        return 2
    if entry.problem:
        err.write(f"iecoop: {entry.name} cannot run: {entry.problem}\n")
        return 2
    if entry.demo:
        return _run_demo(entry, out, err)
    cycles = args.cycles if args.cycles is not None else entry.cycles
    check_trace_options(args)
    out.write(f"{entry.name} -- {entry.heading()}\n")
    for note in _expected(entry):
        out.write(f"  {note}\n")
    what = "rows where a traced value changed"
    if args.every:
        what = "a row every cycle" if args.every == 1 else f"a row every {args.every} cycles"
    trace = run_streamed(
        functools.partial(run_entry, entry, cycles, every=args.every, profile=args.profile, paths=args.trace or ()),
        cycles, out, err, lambda started: f"{started.where}, {args.profile} profile, {cycles} cycles; {what}", f"iecoop: {entry.name}",
    )
    if trace is None:
        return 130
    write_trace(trace.source, args, out)
    if trace.fault is not None:
        err.write(f"iecoop: {entry.name}: {fault_text(trace)}\n")
        return 1
    return 0


def _run_demo(entry: Entry, out: TextIO, err: TextIO) -> int:
    out.write(f"{entry.name} -- {entry.heading()}\n(the module has no Program: running its main())\n")
    try:
        entry.load().main()
    except PlcException as exc:
        err.write(f"iecoop: {entry.name}: PLC fault: {exc.code.name} ({exc})\n")
        return 1
    return 0


def _cmd_tour(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    toured = [entry for entry in entries() if entry.category in TOUR_CATEGORIES]
    out.write(
        f"iecoop tour: {len(toured)} patterns and principles, each a PLC program on a 10 ms task in virtual time.\n"
        "Rows show the cycles where a traced variable changed; 'expected' marks the faults a scenario\n"
        "provokes on purpose. 'iecoop list' names them all; 'iecoop run NAME' runs one in full,\n"
        "'iecoop show NAME' explains it.\n"
    )
    status = 0
    category = ""
    for entry in toured:
        if entry.category != category:
            category = entry.category
            out.write(f"\n{CATEGORIES[category]}\n{'=' * len(CATEGORIES[category])}\n")
        out.write(f"\n{entry.name} -- {entry.heading()}\n")
        if entry.problem or entry.demo:
            out.write(f"  not run: {entry.problem or 'no Program to trace'}\n")
            status = 1 if entry.problem else status
            continue
        for note in _expected(entry):
            out.write(f"  {note}\n")
        try:
            trace = run_entry(entry, entry.tour_cycles)
        except Exception as exc:  # a module being edited: report it and go on with the others
            out.write(f"  not run: {type(exc).__name__}: {exc}\n")
            status = 1
            continue
        for text in table(trace, limit=TOUR_ROWS):
            out.write(f"  {text}\n")
        if trace.fault is not None:
            out.write(f"  {fault_text(trace)}\n")
            status = 1
        out.flush()
    return status


def _name_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("name", help="a name from 'iecoop list', e.g. state")


def _show_arguments(parser: argparse.ArgumentParser) -> None:
    _name_argument(parser)
    parser.add_argument("--st", action="store_true", help="also print the pattern as Structured Text")
    parser.add_argument("--lenient", action="store_true",
                        help="with --st: write a statement with no ST form as an ST comment (listed on stderr)")


def _run_arguments(parser: argparse.ArgumentParser) -> None:
    _name_argument(parser)
    parser.add_argument("--cycles", type=positive, metavar="N", help="cycles of 10 ms to run (default: the entry's)")
    parser.add_argument("--every", type=positive, metavar="K", help="print every K-th cycle (default: the changes)")
    parser.add_argument("--profile", choices=("twincat", "codesys"), default="twincat", help="the PLC profile")
    add_trace_arguments(parser)


def _no_arguments(parser: argparse.ArgumentParser) -> None:
    pass


#: The subcommands, in the order ``--help`` lists them; ``tour`` runs when none is given.
COMMANDS: dict[str, Command] = {
    "tour": Command("a short run of every pattern (the default)", _no_arguments, _cmd_tour),
    "list": Command("the names of the patterns, principles and examples, by category", _no_arguments, _cmd_list),
    "show": Command("the documentation of one pattern or example, and where its file is", _show_arguments, _cmd_show),
    "run": Command("run one pattern or example, printing its trace rows as the cycles run", _run_arguments,
                   usage_errors("iecoop run")(_cmd_run)),
    **commands(NAMES),
}
DEFAULT_COMMAND = "tour"
DESCRIPTION = (
    "The GoF patterns, SOLID principles and course examples of iecoop, run on the cyclic PLC "
    "runtime. Without a command: a short tour of every pattern."
)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``iecoop`` command; returns the exit status."""
    return iecoop_main(argv, table=COMMANDS, default=DEFAULT_COMMAND, description=DESCRIPTION)
