"""The ``iecoop`` command: list the patterns and examples and run them on the cyclic runtime.

::

    iecoop                                   a short tour of every pattern
    iecoop list                              the names, by category
    iecoop run state --cycles 200            one scenario, with its trace table
    iecoop run state --every 10 --profile codesys
    iecoop show state                        the module's documentation

``run`` builds the scenario (the module's ``Program`` on a 10 ms ``PlcTask``
of a ``Runtime(store=":memory:")``, in virtual time), runs it cycle by cycle
and prints the variables that matter: by default only the cycles where one of
them changed, with ``--every K`` every K-th cycle. An unknown name or a bad
option exits with status 2, a PLC fault during the run with status 1.

>>> main(["run", "state", "--cycles", "60"])
state -- State: the PackML unit state machine, one function block per state.
PackagingLine on PlcTask (10 ms), twincat profile, 60 cycles; rows where a traced value changed
time ms  cycle  state      packs  transitions  refused  batches
      0      1  RESETTING      0            1        0        0
    200     21  IDLE           0            2        0        0
    210     22  STARTING       0            3        0        0
    510     52  EXECUTE        0            4        0        0
    590     60  EXECUTE        0            4        0        0
0
"""

from __future__ import annotations

import argparse
import dataclasses
import difflib
import inspect
import os
import re
import sys
from collections.abc import Callable, Sequence
from typing import TextIO

from iecoop import PlcException
from patterns.showcase.catalogue import CATEGORIES, Entry, build, entries, find, normalise, read, show

__all__ = ["Trace", "main", "run_entry", "table"]

#: Runs of at least this many cycles show a progress bar when stderr is a terminal.
PROGRESS_THRESHOLD = 1000
#: The tour's categories (the course examples are listed and run, not toured).
TOUR_CATEGORIES = ("creational", "structural", "behavioral", "solid")
#: Trace rows shown per pattern in the tour (first and last included).
TOUR_ROWS = 20


@dataclasses.dataclass
class Trace:
    """The rows of one run: ``(time ms, cycle, values)``; ``fault`` is set if the PLC stopped."""

    labels: list[str]
    rows: list[tuple[int, int, list[str]]] = dataclasses.field(default_factory=list)
    fault: PlcException | None = None
    cycles_run: int = 0
    where: str = ""


class ProgressBar:
    """A one-line progress bar, redrawn in place on a terminal."""

    def __init__(self, total: int, stream: TextIO, width: int = 30) -> None:
        self.total = total
        self.stream = stream
        self.width = width
        self.shown = -1

    def update(self, done: int) -> None:
        percent = done * 100 // self.total
        if percent == self.shown:
            return
        self.shown = percent
        filled = self.width * done // self.total
        bar = "#" * filled + "-" * (self.width - filled)
        self.stream.write(f"\r[{bar}] {percent:3d}% {done}/{self.total} cycles")
        self.stream.flush()

    def close(self) -> None:
        self.stream.write("\r" + " " * (self.width + 40) + "\r")
        self.stream.flush()


def run_entry(
    entry: Entry,
    cycles: int,
    *,
    every: int | None = None,
    profile: str = "twincat",
    progress: Callable[[int], None] | None = None,
) -> Trace:
    """Build ``entry`` and run it ``cycles`` cycles; keep every ``every``-th row, or the rows that changed.

    The first and the last cycle are always kept.
    """
    trace = Trace([column.label for column in entry.columns])
    try:
        scenario = build(entry, profile)
    except PlcException as exc:
        trace.fault = exc
        return trace
    trace.where = "; ".join(
        f"{', '.join(type(program).__name__ for _, program in task.programs)} on {task.name} ({task.interval} ms)"
        for task in scenario.runtime.tasks
    )
    runtime = scenario.runtime
    watched = [i for i, column in enumerate(entry.columns) if column.watch]
    previous: list[str] | None = None
    for cycle in range(1, cycles + 1):
        start = runtime.time_ms
        try:
            if entry.script is not None:
                entry.script(scenario, cycle)
            runtime.run(cycles=1)
        except PlcException as exc:
            trace.fault = exc
            break
        trace.cycles_run = cycle
        values = [show(read(scenario, column), column.fmt) for column in entry.columns]
        now = [values[i] for i in watched]
        keep = (cycle - 1) % every == 0 if every else now != previous
        if keep or cycle == cycles:
            trace.rows.append((start, cycle, values))
        previous = now
        if progress is not None:
            progress(cycle)
    return trace


_NUMBER = re.compile(r"^[-+]?\d+(\.\d+)?(ms)?$")


def table(trace: Trace, limit: int | None = None) -> list[str]:
    """The trace as aligned text lines; with ``limit``, at most that many rows (the last one kept)."""
    labels = ["time ms", "cycle", *trace.labels]
    rows = [[str(t), str(c), *values] for t, c, values in trace.rows]
    hidden = 0
    if limit is not None and len(rows) > limit:
        hidden = len(rows) - limit
        rows = rows[: limit - 1] + rows[-1:]
    widths = [max([len(label)] + [len(row[i]) for row in rows]) for i, label in enumerate(labels)]
    numeric = [all(_NUMBER.match(row[i]) for row in rows) for i in range(len(labels))]

    def line(cells: Sequence[str]) -> str:
        parts = [c.rjust(w) if n else c.ljust(w) for c, w, n in zip(cells, widths, numeric)]
        return "  ".join(parts).rstrip()

    lines = [line(labels)] + [line(row) for row in rows]
    if hidden:
        lines.insert(len(lines) - 1, f"{'...':>{widths[0]}}  ({hidden} more {'row' if hidden == 1 else 'rows'})")
    return lines


def _fault_text(trace: Trace) -> str:
    assert trace.fault is not None
    where = f"in cycle {trace.cycles_run + 1}" if trace.where else "at start-up"
    return f"PLC fault {where}: {trace.fault.code.name} ({trace.fault})"


def _unknown(name: str, out: TextIO) -> int:
    names = [entry.name for entry in entries()]
    wanted = normalise(name)
    close = difflib.get_close_matches(wanted, names, n=4, cutoff=0.6)
    close += [n for n in names if wanted and wanted in n and n not in close]
    hint = f" Did you mean: {', '.join(close[:5])}?" if close else ""
    out.write(f"iecoop: unknown name {name!r}.{hint} 'iecoop list' shows every name.\n")
    return 2


def _lookup(name: str, err: TextIO) -> Entry | None:
    try:
        return find(name)
    except KeyError:
        _unknown(name, err)
        return None


def _cmd_list(out: TextIO) -> int:
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


def _cmd_show(name: str, out: TextIO, err: TextIO) -> int:
    entry = _lookup(name, err)
    if entry is None:
        return 2
    try:
        module = entry.load()
    except Exception as exc:
        err.write(f"iecoop: {entry.name}: cannot import {entry.module}: {type(exc).__name__}: {exc}\n")
        return 1
    out.write(f"{entry.name} ({entry.module})\n\n{inspect.getdoc(module) or '(no documentation)'}\n")
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
    bar = ProgressBar(cycles, err) if cycles >= PROGRESS_THRESHOLD and err.isatty() else None
    try:
        trace = run_entry(entry, cycles, every=args.every, profile=args.profile, progress=bar.update if bar else None)
    finally:
        if bar is not None:
            bar.close()
    rows = f"a row every {args.every} cycles" if args.every else "rows where a traced value changed"
    out.write(f"{entry.name} -- {entry.heading()}\n")
    if trace.where:
        out.write(f"{trace.where}, {args.profile} profile, {cycles} cycles; {rows}\n")
        for text in table(trace):
            out.write(text + "\n")
    if trace.fault is not None:
        err.write(f"iecoop: {entry.name}: {_fault_text(trace)}\n")
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


def _cmd_tour(out: TextIO) -> int:
    toured = [entry for entry in entries() if entry.category in TOUR_CATEGORIES]
    out.write(
        f"iecoop tour: {len(toured)} patterns and principles, each a PLC program on a 10 ms task in virtual time.\n"
        "Rows show the cycles where a traced variable changed. 'iecoop list' names them all;\n"
        "'iecoop run NAME' runs one in full, 'iecoop show NAME' explains it.\n"
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
        try:
            trace = run_entry(entry, entry.tour_cycles)
        except Exception as exc:  # a module being edited: report it and go on with the others
            out.write(f"  not run: {type(exc).__name__}: {exc}\n")
            status = 1
            continue
        for text in table(trace, limit=TOUR_ROWS):
            out.write(f"  {text}\n")
        if trace.fault is not None:
            out.write(f"  {_fault_text(trace)}\n")
            status = 1
    return status


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="iecoop",
        description="The GoF patterns, SOLID principles and course examples of iecoop, run on the cyclic PLC "
        "runtime. Without a command: a short tour of every pattern.",
    )
    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.add_parser("tour", help="a short run of every pattern (the default)")
    commands.add_parser("list", help="the names of the patterns, principles and examples, by category")
    show_cmd = commands.add_parser("show", help="the documentation of one pattern or example")
    show_cmd.add_argument("name", help="a name from 'iecoop list'")
    run = commands.add_parser("run", help="run one pattern or example and print its trace table")
    run.add_argument("name", help="a name from 'iecoop list', e.g. state")
    run.add_argument("--cycles", type=_positive, metavar="N", help="cycles of 10 ms to run (default: the entry's)")
    run.add_argument("--every", type=_positive, metavar="K", help="print every K-th cycle (default: the changes)")
    run.add_argument("--profile", choices=("twincat", "codesys"), default="twincat", help="the PLC profile")
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``iecoop`` command; returns the exit status."""
    out, err = sys.stdout, sys.stderr
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # --help, or a bad option (argparse has printed why)
        return exc.code if isinstance(exc.code, int) else 0
    try:
        if args.command == "list":
            return _cmd_list(out)
        if args.command == "show":
            return _cmd_show(args.name, out, err)
        if args.command == "run":
            return _cmd_run(args, out, err)
        return _cmd_tour(out)
    except KeyboardInterrupt:
        err.write("\niecoop: interrupted\n")
        return 130
    except BrokenPipeError:  # the reader went away (iecoop | head): stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
