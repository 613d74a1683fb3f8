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

The subcommands are one table, :data:`COMMANDS`: a new one is a
:class:`Command` added there, with its arguments and the function it runs.
"""

from __future__ import annotations

import argparse
import dataclasses
import inspect
import os
import re
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import TextIO

from iecoop import PlcException
from patterns.showcase.catalogue import CATEGORIES, Entry, build, entries, find, read, show, unknown_name
from patterns.showcase.text import render_rst
from patterns.showcase import export_cli, serve, st_cli

__all__ = ["COMMANDS", "Command", "Progress", "RowWriter", "SHOW_SECTIONS", "Trace", "main", "run_entry", "table"]

#: Runs of at least this many cycles show a progress line on a terminal.
PROGRESS_THRESHOLD = 1000
#: The tour's categories (the course examples are listed and run, not toured).
TOUR_CATEGORIES = ("creational", "structural", "behavioral", "solid")
#: Trace rows shown per pattern in the tour (first and last included).
TOUR_ROWS = 20
#: Seconds between two flushes of streamed rows (and two redraws of the progress line).
FLUSH_EVERY = 0.1

#: One trace row: (time in ms at the cycle's start, cycle counted from 1, the values as text).
Row = tuple[int, int, list[str]]


@dataclasses.dataclass
class Trace:
    """The rows of one run; ``fault`` is set if the PLC stopped, ``fault_cycle`` counts from 1 like the rows."""

    labels: list[str]
    rows: list[Row] = dataclasses.field(default_factory=list)
    fault: PlcException | None = None
    fault_cycle: int = 0
    fault_message: str = ""
    cycles_run: int = 0
    where: str = ""
    tick_ms: int = 0


class Progress:
    """A one-line progress report redrawn in place on a terminal, at most every :data:`FLUSH_EVERY` s."""

    def __init__(self, total: int, stream: TextIO, width: int = 30, clock: Callable[[], float] = time.monotonic):
        self.total = total
        self.stream = stream
        self.width = width
        self.clock = clock
        self.started = clock()
        self.drawn_at = -FLUSH_EVERY
        self.done = 0
        self.shown = ""

    def update(self, done: int) -> None:
        self.done = done
        now = self.clock()
        if now - self.drawn_at >= FLUSH_EVERY or done == self.total:
            self.drawn_at = now
            self.draw()

    def draw(self) -> None:
        filled = self.width * self.done // self.total
        bar = "#" * filled + "-" * (self.width - filled)
        seconds = self.clock() - self.started
        text = f"[{bar}] {self.done * 100 // self.total:3d}% {self.done}/{self.total} cycles, {seconds:.0f} s"
        self.stream.write("\r" + text.ljust(len(self.shown)))
        self.stream.flush()
        self.shown = text

    def clear(self) -> None:
        """Wipe the line (before a row is written to the same terminal, and at the end)."""
        if self.shown:
            self.stream.write("\r" + " " * len(self.shown) + "\r")
            self.shown = ""


_NUMBER = re.compile(r"^[-+]?\d+(\.\d+)?(ms)?$")


def _cells(row: Row) -> list[str]:
    start, cycle, values = row
    return [str(start), str(cycle), *values]


def _line(cells: Sequence[str], widths: Sequence[int], numeric: Sequence[bool]) -> str:
    parts = [c.rjust(w) if n else c.ljust(w) for c, w, n in zip(cells, widths, numeric)]
    return "  ".join(parts).rstrip()


def table(trace: Trace, limit: int | None = None) -> list[str]:
    """The trace as aligned text lines; with ``limit``, at most that many rows (the last one kept)."""
    labels = ["time ms", "cycle", *trace.labels]
    rows = [_cells(row) for row in trace.rows]
    hidden = 0
    if limit is not None and len(rows) > limit:
        hidden = len(rows) - limit
        rows = rows[: limit - 1] + rows[-1:]
    widths = [max([len(label)] + [len(row[i]) for row in rows]) for i, label in enumerate(labels)]
    numeric = [all(_NUMBER.match(row[i]) for row in rows) for i in range(len(labels))]
    lines = [_line(labels, widths, numeric)] + [_line(row, widths, numeric) for row in rows]
    if hidden:
        lines.insert(len(lines) - 1, f"{'...':>{widths[0]}}  ({hidden} more {'row' if hidden == 1 else 'rows'})")
    return lines


class RowWriter:
    """Writes a trace table row by row, as the cycles run.

    The widths come from the labels and the first row (the time and cycle
    columns from the largest values the run can reach); a later, wider value
    widens its column from that row on. A column is right-aligned when its
    first value is a number. Rows are flushed at most every
    :data:`FLUSH_EVERY` seconds and at the end, so a pipe reader sees them as
    they come; a ``progress`` line on the same terminal is wiped before each
    row and redrawn after it.
    """

    def __init__(
        self, labels: Sequence[str], out: TextIO, *, last_time: int = 0, last_cycle: int = 0,
        progress: Progress | None = None, clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.labels = ["time ms", "cycle", *labels]
        self.out = out
        self.progress = progress
        self.clock = clock
        self.flushed_at = clock()
        self.widths = [len(label) for label in self.labels]
        self.widths[0] = max(self.widths[0], len(str(last_time)))
        self.widths[1] = max(self.widths[1], len(str(last_cycle)))
        self.numeric: list[bool] = []

    def row(self, row: Row) -> None:
        cells = _cells(row)
        if not self.numeric:
            self.numeric = [bool(_NUMBER.match(cell)) for cell in cells]
            self.widths = [max(w, len(cell)) for w, cell in zip(self.widths, cells)]
            self._write(_line(self.labels, self.widths, self.numeric))
        self.widths = [max(w, len(cell)) for w, cell in zip(self.widths, cells)]
        self._write(_line(cells, self.widths, self.numeric))
        now = self.clock()
        if now - self.flushed_at >= FLUSH_EVERY:
            self.flushed_at = now
            self.out.flush()

    def _write(self, line: str) -> None:
        shared = self.progress is not None and self.progress.stream is self.out and self.progress.shown
        if shared:
            assert self.progress is not None
            self.progress.clear()
        self.out.write(line + "\n")
        if shared:
            assert self.progress is not None
            self.progress.draw()

    def close(self) -> None:
        if self.progress is not None:
            self.progress.clear()
        self.out.flush()


def run_entry(
    entry: Entry,
    cycles: int,
    *,
    every: int | None = None,
    profile: str = "twincat",
    progress: Callable[[int], None] | None = None,
    on_start: Callable[[Trace], None] | None = None,
    on_row: Callable[[Row], None] | None = None,
) -> Trace:
    """Build ``entry`` and run it ``cycles`` cycles; keep every ``every``-th row, or the rows that changed.

    The first and the last cycle are always kept. ``on_start`` is called once
    the scenario is built (``trace.where`` names its tasks); with ``on_row``
    each row is handed over as its cycle ends instead of being kept in
    ``trace.rows``, so a run of any length streams in constant memory.
    """
    trace = Trace([column.label for column in entry.columns])
    try:
        scenario = build(entry, profile)
    except PlcException as exc:
        trace.fault, trace.fault_message = exc, exc.message
        return trace
    trace.where = "; ".join(
        f"{', '.join(type(program).__name__ for _, program in task.programs)} on {task.name} ({task.interval} ms)"
        for task in scenario.runtime.tasks
    )
    trace.tick_ms = min((task.interval for task in scenario.runtime.tasks), default=0)
    if on_start is not None:
        on_start(trace)
    emit = on_row if on_row is not None else trace.rows.append
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
            trace.fault, trace.fault_cycle = exc, cycle
            # The runtime's own text numbers the cycle from 0 (its CycleCount): keep only the cause.
            trace.fault_message = runtime.fault.exception.message if runtime.fault is not None else exc.message
            break
        trace.cycles_run = cycle
        values = [show(read(scenario, column), column.fmt) for column in entry.columns]
        now = [values[i] for i in watched]
        keep = (cycle - 1) % every == 0 if every else now != previous
        if keep or cycle == cycles:
            emit((start, cycle, values))
        previous = now
        if progress is not None:
            progress(cycle)
    return trace


def _fault_text(trace: Trace) -> str:
    assert trace.fault is not None
    where = f"in cycle {trace.fault_cycle}" if trace.fault_cycle else "at start-up"
    cause = f" ({trace.fault_message})" if trace.fault_message else ""
    return f"PLC fault {where}: {trace.fault.code.name}{cause}"


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
        blocks.append("Structured Text (generated by iecoop.st.export; 'iecoop export' writes TwinCAT files):\n\n"
                      + export_cli.st_text(entry.name))
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
    out.write(f"{entry.name} -- {entry.heading()}\n")
    for note in _expected(entry):
        out.write(f"  {note}\n")
    # On a terminal the progress line follows the rows on stdout; into a pipe it goes to stderr if that
    # is a terminal, and otherwise nowhere: the reader gets the rows alone.
    screen = out if out.isatty() else err if err.isatty() else None
    progress = Progress(cycles, screen) if screen is not None and cycles >= PROGRESS_THRESHOLD else None
    rows: list[RowWriter] = []

    def start(trace: Trace) -> None:
        what = "rows where a traced value changed"
        if args.every:
            what = "a row every cycle" if args.every == 1 else f"a row every {args.every} cycles"
        out.write(f"{trace.where}, {args.profile} profile, {cycles} cycles; {what}\n")
        rows.append(RowWriter(trace.labels, out, last_time=(cycles - 1) * trace.tick_ms, last_cycle=cycles,
                              progress=progress))

    trace: Trace | None = None
    try:
        trace = run_entry(
            entry, cycles, every=args.every, profile=args.profile, on_start=start,
            on_row=lambda row: rows[0].row(row), progress=progress.update if progress is not None else None,
        )
    except KeyboardInterrupt:
        if rows:
            rows[0].close()
        done = progress.done if progress is not None else 0
        err.write(f"\niecoop: {entry.name}: interrupted{f' after cycle {done}' if done else ''}\n")
        return 130
    finally:
        if rows:
            rows[0].close()
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
            out.write(f"  {_fault_text(trace)}\n")
            status = 1
        out.flush()
    return status


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _name_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("name", help="a name from 'iecoop list', e.g. state")


def _show_arguments(parser: argparse.ArgumentParser) -> None:
    _name_argument(parser)
    parser.add_argument("--st", action="store_true", help="also print the pattern as Structured Text")


def _run_arguments(parser: argparse.ArgumentParser) -> None:
    _name_argument(parser)
    parser.add_argument("--cycles", type=_positive, metavar="N", help="cycles of 10 ms to run (default: the entry's)")
    parser.add_argument("--every", type=_positive, metavar="K", help="print every K-th cycle (default: the changes)")
    parser.add_argument("--profile", choices=("twincat", "codesys"), default="twincat", help="the PLC profile")


def _no_arguments(parser: argparse.ArgumentParser) -> None:
    pass


@dataclasses.dataclass(frozen=True)
class Command:
    """One subcommand: its help line, the function adding its arguments, and the function running it."""

    help: str
    arguments: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace, TextIO, TextIO], int]


#: The subcommands, in the order ``--help`` lists them; ``tour`` runs when none is given.
COMMANDS: dict[str, Command] = {
    "tour": Command("a short run of every pattern (the default)", _no_arguments, _cmd_tour),
    "list": Command("the names of the patterns, principles and examples, by category", _no_arguments, _cmd_list),
    "show": Command("the documentation of one pattern or example, and where its file is", _show_arguments, _cmd_show),
    "run": Command("run one pattern or example, printing its trace rows as the cycles run", _run_arguments, _cmd_run),
    "serve": Command(serve.HELP, serve.add_arguments, serve.run),
    "st2py": Command(st_cli.ST2PY_HELP, st_cli.add_st2py_arguments, st_cli.st2py_command),
    "st": Command(st_cli.ST_HELP, st_cli.add_st_arguments, st_cli.st_command),
    "export": Command(export_cli.EXPORT_HELP, export_cli.add_export_arguments, export_cli.export_run),
}
DEFAULT_COMMAND = "tour"


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="iecoop",
        description="The GoF patterns, SOLID principles and course examples of iecoop, run on the cyclic PLC "
        "runtime. Without a command: a short tour of every pattern.",
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, command in COMMANDS.items():
        command.arguments(subparsers.add_parser(name, help=command.help))
    return parser


def _quiet_stdout() -> None:
    """Point stdout at the null device, so that the interpreter's last flush at exit cannot fail again.

    This is the handling the Python documentation gives for SIGPIPE / BrokenPipeError (``signal`` module).
    """
    try:
        descriptor = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # not a real file (a test's capture): nothing to redirect
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, descriptor)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``iecoop`` command; returns the exit status."""
    out, err = sys.stdout, sys.stderr
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # --help, or a bad option (argparse has printed why)
        return exc.code if isinstance(exc.code, int) else 0
    command = COMMANDS[args.command or DEFAULT_COMMAND]
    try:
        status = command.run(args, out, err)
        out.flush()  # inside the try: a reader that went away shows up here at the latest
        return status
    except KeyboardInterrupt:
        err.write("\niecoop: interrupted\n")
        return 130
    except BrokenPipeError:  # the reader stopped early (iecoop list | head -1): that is not an error
        _quiet_stdout()
        return 0
