"""The trace a run prints: cycles run in virtual time, the values that matter, as an aligned table.

:func:`run_cycles` runs a runtime cycle by cycle and samples its
:class:`Probe` s after each cycle into a :class:`TraceTable`; given symbol
paths instead, the table is a view of the runtime's own
:class:`iecoop.runtime.Trace` of them (``TraceTable.source``), which
``--csv`` and ``--plot`` write. :func:`table` and :class:`RowWriter` print
the rows (all at once, or streamed as the cycles run); :class:`Progress` is
the line a long run redraws on a terminal. Cycles are counted from 1, in the
rows and in a fault report.

>>> from iecoop import INT, VAR, Program, T
>>> from iecoop.runtime import Runtime, Task
>>> class Counter(Program):
...     count: INT = VAR(0)
...     def body(self) -> None:
...         self.count += 1
>>> runtime = Runtime(store=":memory:")
>>> counter = Counter()
>>> runtime.add_task(Task("PlcTask", interval=T("10ms"), priority=20), counter)
>>> trace = run_cycles(runtime, [Probe("count", lambda: show(counter.count))], 3, every=1)
>>> print("\\n".join(table(trace)))
time ms  cycle  count
      0      1      1
     10      2      2
     20      3      3
"""

from __future__ import annotations

import argparse
import dataclasses
import enum
import operator
import pathlib
import re
import time
from collections.abc import Callable, Sequence
from typing import Any, TextIO

from iecoop import TYPE_CLASS, FunctionBlock, PlcException, Program, var_info
from iecoop.cli.base import UsageError
from iecoop.exceptions import AccessError
from iecoop.memory.typeinfo import ElementaryInfo
from iecoop.metadata import Kind, kind_of, st_name
from iecoop.runtime import Runtime, Trace
from iecoop.sections import Section
from iecoop.uml import class_diagram

__all__ = [
    "FLUSH_EVERY",
    "add_trace_arguments",
    "check_trace_options",
    "write_trace",
    "PROGRESS_THRESHOLD",
    "Probe",
    "Progress",
    "Row",
    "RowWriter",
    "TIME_CLASSES",
    "TraceTable",
    "elementary_variables",
    "fault_text",
    "run_cycles",
    "show",
    "st_path",
    "table",
    "tasks_text",
    "variable_probes",
]

#: Runs of at least this many cycles show a progress line on a terminal.
PROGRESS_THRESHOLD = 1000
#: Seconds between two flushes of streamed rows (and two redraws of the progress line).
FLUSH_EVERY = 0.1

#: One trace row: (time in ms at the cycle's start, cycle counted from 1, the values as text).
Row = tuple[int, int, list[str]]


@dataclasses.dataclass
class TraceTable:
    """The rows of one run as the command prints them; ``fault`` is set if the PLC stopped, ``fault_cycle``
    counts from 1 like the rows; ``source`` is the runtime trace the table shows, when it shows one."""

    labels: list[str]
    rows: list[Row] = dataclasses.field(default_factory=list)
    fault: PlcException | None = None
    fault_cycle: int = 0
    fault_message: str = ""
    cycles_run: int = 0
    where: str = ""
    tick_ms: int = 0
    #: Per label, the widest text its probe can give (0: not known before the run).
    widths: list[int] = dataclasses.field(default_factory=list)
    #: The runtime trace whose values the rows show (``--trace``), or None.
    source: Trace | None = None


@dataclasses.dataclass(frozen=True)
class Probe:
    """One traced value: its column label and a function giving its current text.

    ``watch=False`` marks a value that moves every cycle (a temperature): it
    is shown, but its changes alone do not make a row.
    """

    label: str
    read: Callable[[], str]
    watch: bool = True
    #: The widest text the value can take, where its type bounds it (an enumeration's longest name).
    width: int = 0


def widest(value: object) -> int:
    """The widest text :func:`show` gives for a value of ``value``'s type: an enumeration's longest name, FALSE."""
    if isinstance(value, bool):
        return len("FALSE")
    if isinstance(value, enum.Enum):
        return max(len(member.name) for member in type(value))
    return 0


def show(value: object, fmt: str | Callable[[Any], str] = "") -> str:
    """A value as the trace prints it: ``TRUE`` / ``FALSE``, enum names, REALs to two decimals."""
    if callable(fmt):
        return fmt(value)
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, enum.Enum):
        return st_name(type(value), value.name) if kind_of(type(value)) is Kind.ENUM else value.name
    if isinstance(value, float):
        return format(value, fmt or ".2f")
    if fmt:
        return format(value, fmt)
    return str(value)


def tasks_text(runtime: Runtime) -> str:
    """The runtime's tasks as a trace's header names them: ``Main on PlcTask (10 ms)``."""
    return "; ".join(
        f"{', '.join(st_name(type(program)) for _, program in task.programs)} on {task.name} ({task.interval} ms)"
        for task in runtime.tasks
    )


def run_cycles(
    runtime: Runtime,
    probes: Sequence[Probe],
    cycles: int,
    *,
    every: int | None = None,
    before_cycle: Callable[[int], None] | None = None,
    progress: Callable[[int], None] | None = None,
    on_start: Callable[[TraceTable], None] | None = None,
    on_row: Callable[[Row], None] | None = None,
    paths: Sequence[str] = (),
) -> TraceTable:
    """Run ``cycles`` cycles; keep every ``every``-th row, or the rows where a watched probe changed.

    The first and the last cycle are always kept. ``before_cycle`` is called
    with the number of the cycle about to run (a scenario's scripted
    events); ``on_start`` once, before the first cycle; with ``on_row`` each
    row is handed over as its cycle ends instead of being kept in
    ``trace.rows``, so a run of any length streams in constant memory.
    With symbol ``paths`` (``--trace``), the runtime traces them every cycle
    (``trace.source``) and the table shows them instead of ``probes``;
    UsageError names a path that is no variable.
    """
    source: Trace | None = None
    if paths:
        try:
            # A bounded run: the buffer holds every row of it, so --csv writes them all.
            source = runtime.trace(list(paths), size=max(1, cycles))
            probes = [_symbol_probe(runtime, path) for path in source.paths]
        except AccessError as exc:
            raise UsageError(f"--trace: {exc}") from None
    trace = TraceTable([probe.label for probe in probes], where=tasks_text(runtime), widths=[probe.width for probe in probes],
                       source=source)
    trace.tick_ms = min((task.interval for task in runtime.tasks), default=0)
    if on_start is not None:
        on_start(trace)
    emit = on_row if on_row is not None else trace.rows.append
    watched = [i for i, probe in enumerate(probes) if probe.watch]
    previous: list[str] | None = None
    for cycle in range(1, cycles + 1):
        start = runtime.time_ms
        try:
            if before_cycle is not None:
                before_cycle(cycle)
            runtime.run(cycles=1)
        except PlcException as exc:
            trace.fault, trace.fault_cycle = exc, cycle
            # The runtime's text repeats the task and cycle the report names: keep only the cause.
            trace.fault_message = runtime.fault.exception.message if runtime.fault is not None else exc.message
            break
        trace.cycles_run = cycle
        values = [probe.read() for probe in probes]
        now = [values[i] for i in watched]
        keep = (cycle - 1) % every == 0 if every else now != previous
        if keep or cycle == cycles:
            emit((start, cycle, values))
        previous = now
        if progress is not None:
            progress(cycle)
    return trace


def _symbol_probe(runtime: Runtime, path: str) -> Probe:
    """The table column of a traced symbol path: the value the runtime trace records after the same cycle."""
    symbol = runtime.symbol(path)
    info = symbol.info
    if isinstance(info, ElementaryInfo) and info.record.kind == "time":
        unit = info.record.unit
        return Probe(path, lambda: f"{int(symbol.load())}{unit}")
    return Probe(path, lambda: show(symbol.load()), width=widest(symbol.load()))


def add_trace_arguments(parser: argparse.ArgumentParser) -> None:
    """``--trace VARS --csv FILE --plot FILE``: record symbol paths every cycle, then write them."""
    parser.add_argument("--trace", metavar="VARS", type=lambda text: [p.strip() for p in text.split(",") if p.strip()],
                        help="symbol paths to record every cycle, comma-separated (MAIN.nCount,GVL_IO.bStart)")
    parser.add_argument("--csv", metavar="FILE", help="write the traced values to FILE as CSV")
    parser.add_argument("--plot", metavar="FILE", help="draw the traced values to FILE (.png or .svg) at the end")


def check_trace_options(args: argparse.Namespace) -> None:
    """UsageError for ``--csv`` / ``--plot`` without ``--trace``, or a plot file of another kind."""
    if not args.trace and (args.csv or args.plot):
        raise UsageError("--csv and --plot write what --trace records: name the variables with --trace")
    if args.plot and pathlib.Path(args.plot).suffix.lower() not in (".png", ".svg"):
        raise UsageError(f"--plot {args.plot}: the file must end in .png or .svg")


def write_trace(source: Trace | None, args: argparse.Namespace, out: TextIO) -> None:
    """Write ``--csv`` / ``--plot`` of the runtime trace ``source`` and say where; UsageError if it cannot be."""
    if source is None:
        return
    try:
        source.detach()  # a trace streamed to --csv (a serve) is closed here, with every row
        if args.csv:
            if source.file is None:
                source.to_csv(args.csv)
            out.write(f"trace: {source.taken} rows written to {args.csv}\n")
        if args.plot:
            source.plot(args.plot)
            out.write(f"trace: plotted to {args.plot}\n")
    except (OSError, ImportError) as exc:
        raise UsageError(f"the trace cannot be written: {exc}") from None


def fault_text(trace: TraceTable) -> str:
    """``PLC fault in cycle 3 at FB_Calc.TcPOU:23 (FB_Calc.Divide): RTSEXCPT_DIVIDEBYZERO (...)``.

    ``at start-up`` before the first cycle; the ST location when the fault arose in loaded ST.
    """
    assert trace.fault is not None
    where = f"in cycle {trace.fault_cycle}" if trace.fault_cycle else "at start-up"
    if trace.fault.location is not None:
        where += f" at {trace.fault.location}"
    cause = f" ({trace.fault_message})" if trace.fault_message else ""
    return f"PLC fault {where}: {trace.fault.code.name}{cause}"


# ---------------------------------------------------------------------------
# The table
# ---------------------------------------------------------------------------

_NUMBER = re.compile(r"^[-+]?\d+(\.\d+)?(ms)?$")


def _cells(row: Row) -> list[str]:
    start, cycle, values = row
    return [str(start), str(cycle), *values]


def _line(cells: Sequence[str], widths: Sequence[int], numeric: Sequence[bool]) -> str:
    parts = [c.rjust(w) if n else c.ljust(w) for c, w, n in zip(cells, widths, numeric)]
    return "  ".join(parts).rstrip()


def table(trace: TraceTable, limit: int | None = None) -> list[str]:
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
        widths: Sequence[int] = (), progress: Progress | None = None, clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.labels = ["time ms", "cycle", *labels]
        self.out = out
        self.progress = progress
        self.clock = clock
        self.flushed_at = clock()
        # A value whose type bounds its text (an enumeration) gets its widest text from the start,
        # so that a later, longer name does not shift the rows after it.
        known = [0, 0, *widths, *[0] * (len(labels) - len(widths))]
        self.widths = [max(len(label), width) for label, width in zip(self.labels, known)]
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


# ---------------------------------------------------------------------------
# What to trace when nothing says
# ---------------------------------------------------------------------------

_NOT_ELEMENTARY = {
    TYPE_CLASS.TYPE_POINTER,
    TYPE_CLASS.TYPE_REFERENCE,
    TYPE_CLASS.TYPE_ARRAY,
    TYPE_CLASS.TYPE_USERDEF,
    TYPE_CLASS.TYPE_INTERFACE,
    TYPE_CLASS.TYPE_PARAMS,
    TYPE_CLASS.TYPE_NONE,
    TYPE_CLASS.TYPE_ANY,
}


def _declared(instance: Any, base: type, sections: Sequence[str]) -> list[tuple[str, TYPE_CLASS]]:
    """``(name, type class)`` of the variables ``instance`` declares in ``sections``, in order."""
    own = [c for c in reversed(type(instance).__mro__) if isinstance(c, type) and issubclass(c, base) and c is not base]
    found: list[tuple[str, TYPE_CLASS]] = []
    for box in class_diagram(*own, related=False).classes:
        for field in box.fields:
            if field.section in sections and not field.static and field.name not in dict(found):
                try:
                    found.append((field.name, var_info(instance, field.name).TypeClass))
                except Exception:
                    continue
    return found


def elementary_variables(cls: type[Program], limit: int = 5) -> list[tuple[str, TYPE_CLASS]]:
    """The first ``limit`` elementary variables of ``cls`` as ``(dotted path, type class)``.

    VAR_OUTPUT, VAR, then the nested blocks' outputs; VAR_INPUT only when
    nothing else is found.
    """
    sample = cls()
    direct = _declared(sample, Program, (Section.VAR_OUTPUT, Section.VAR))
    chosen = [(name, kind) for name, kind in direct if kind not in _NOT_ELEMENTARY]
    for name, kind in direct:
        block = getattr(sample, name, None)
        if kind == TYPE_CLASS.TYPE_USERDEF and kind_of(type(block)) is Kind.FUNCTION_BLOCK:
            outputs = _declared(block, FunctionBlock, (Section.VAR_OUTPUT,))
            chosen += [(f"{name}.{inner}", k) for inner, k in outputs if k not in _NOT_ELEMENTARY]
    if not chosen:
        chosen = [(n, k) for n, k in _declared(sample, Program, (Section.VAR_INPUT,)) if k not in _NOT_ELEMENTARY]
    return chosen[:limit]


def st_path(instance: Any, path: str) -> str:
    """The dotted Python ``path`` of a variable of ``instance`` in ST names: ``gate.in_`` is ``gate.in``."""
    names = []
    for name in path.split("."):
        names.append(st_name(type(instance), name))
        instance = getattr(instance, name)
    return ".".join(names)


#: The type classes whose values the trace shows as ``250ms``.
TIME_CLASSES = (TYPE_CLASS.TYPE_TIME, TYPE_CLASS.TYPE_LTIME)


def variable_probes(program: Program, limit: int = 5) -> list[Probe]:
    """Probes of the first ``limit`` elementary variables of ``program`` (see :func:`elementary_variables`)."""

    def probe(path: str, kind: TYPE_CLASS) -> Probe:
        get = operator.attrgetter(path)
        label = st_path(program, path)
        if kind in TIME_CLASSES:
            return Probe(label, lambda: f"{int(get(program))}ms")
        return Probe(label, lambda: show(get(program)), width=widest(get(program)))

    return [probe(path, kind) for path, kind in elementary_variables(type(program), limit)]
