"""A trace of chosen variables, cycle by cycle: TwinCAT's Scope / CODESYS trace, in a ring buffer.

``rt.trace(paths, every=1, size=10_000)`` samples the variables at the end
of every ``every``-th base tick (an ``on_cycle_end`` hook, so the values are
the cycle's results, forces applied). The buffer keeps the last ``size``
rows (``DEFAULT_TRACE_SIZE``); older ones are dropped. A row is
``(cycle, time_ms, value, ...)``: the cycle counted from 1, the time of the
cycle's start in ms, then one value per path. ``trace.forced`` holds, per
row, the paths that were forced when it was taken. For a run longer than
the buffer, ``file=`` streams every row to a CSV file as it is taken
(``detach()`` or ``close()`` ends it), so nothing is dropped and memory
stays bounded.

>>> from iecoop import BOOL, INT, VAR, Program, T
>>> from iecoop.runtime import Runtime, Task
>>> class Main(Program):
...     count: INT = VAR(0)
...     def body(self) -> None:
...         self.count += 1
>>> rt = Runtime(store=":memory:")
>>> rt.add_task(Task("PlcTask", interval=T("10ms")), Main())
>>> trace = rt.trace(["MAIN.count"], every=2, size=2)
>>> rt.run(cycles=6)
>>> trace.rows
[(4, 30, 4), (6, 50, 6)]
>>> print(trace.to_csv(), end="")
cycle,time_ms,MAIN.count
4,30,4
6,50,6
"""

from __future__ import annotations

import collections
import csv
import importlib
import io
import os
import threading
import typing
from pathlib import Path
from typing import Any

from iecoop.runtime.online import OnlineTable, Symbol

__all__ = ["DEFAULT_TRACE_SIZE", "Trace"]

#: Rows a trace keeps unless told otherwise (at 10 ms a cycle, the last 100 s).
DEFAULT_TRACE_SIZE = 10_000

#: One trace row: cycle (from 1), time of the cycle's start in ms, then the values.
Row = tuple[Any, ...]


class Trace:
    """Chosen variables recorded every ``every`` cycles into a ring buffer of ``size`` rows.

    Made by ``Runtime.trace``; safe to read from another thread while the
    runtime runs in the background.
    """

    def __init__(self, paths: typing.Sequence[str], resolve: typing.Callable[[str], Symbol], *,
                 stamp: typing.Callable[[], tuple[int, int]], online: OnlineTable,
                 hooks: list[typing.Callable[[], None]], every: int = 1, size: int = DEFAULT_TRACE_SIZE,
                 file: str | os.PathLike[str] | typing.TextIO | None = None) -> None:
        """``resolve`` finds a path's variable, ``stamp`` gives ``(cycle, time_ms)`` of the cycle that just ran,
        ``online`` says which variables are forced, and ``hooks`` is the list of end-of-cycle hooks it leaves.
        ``file`` (a path or an open text file) receives every row as CSV as it is taken."""
        if isinstance(paths, str):
            raise TypeError(f"Runtime.trace(): paths is a list of symbol paths, got the string {paths!r}")
        if not isinstance(every, int) or every < 1:
            raise ValueError(f"Runtime.trace(): every is a number of cycles >= 1, got {every!r}")
        if not isinstance(size, int) or size < 1:
            raise ValueError(f"Runtime.trace(): size is a number of rows >= 1, got {size!r}")
        self.paths: tuple[str, ...] = tuple(paths)
        self.every = every
        self.size = size
        self._stamp = stamp
        self._online = online
        self._hooks = hooks
        # Resolved once: a wrong path is refused here, and sampling is one load per path.
        self._symbols = [resolve(path) for path in self.paths]
        self._rows: collections.deque[Row] = collections.deque(maxlen=size)
        self._forced: collections.deque[tuple[str, ...]] = collections.deque(maxlen=size)
        self._lock = threading.Lock()
        #: Rows taken since the trace was made (the buffer keeps the last ``size`` of them).
        self.taken = 0
        self.file: str | os.PathLike[str] | typing.TextIO | None = file
        self._stream: typing.TextIO | None = None
        self._owned = False
        self._writer: Any = None
        if file is not None:
            if isinstance(file, (str, os.PathLike)):
                # Line buffering would cost a system call a cycle; the file is flushed when the trace ends.
                self._stream, self._owned = open(file, "w", encoding="utf-8", newline=""), True
            else:
                self._stream = file
            self._writer = csv.writer(self._stream, lineterminator="\n")
            self._writer.writerow(self.header)

    def __repr__(self) -> str:
        return f"<Trace {', '.join(self.paths)}: {len(self._rows)} rows>"

    def _sample(self) -> None:
        cycle, time_ms = self._stamp()
        if cycle % self.every:
            return
        row = (cycle, time_ms, *[symbol.load() for symbol in self._symbols])
        online = self._online
        forced = tuple(path for path, symbol in zip(self.paths, self._symbols) if online.is_forced(symbol)) \
            if online.forced_now else ()
        with self._lock:
            self._rows.append(row)
            self._forced.append(forced)
            self.taken += 1
            if self._writer is not None:
                self._writer.writerow([_plain(value) for value in row])

    def detach(self) -> None:
        """Stop recording (the rows stay); a streamed file is flushed and, if the trace opened it, closed."""
        hooks = self._hooks
        if self._sample in hooks:
            hooks.remove(self._sample)
        self.close()

    def close(self) -> None:
        """End the stream to ``file`` (the recording into the buffer goes on until ``detach``)."""
        with self._lock:
            stream, self._stream, self._writer = self._stream, None, None
        if stream is not None:
            if self._owned:
                stream.close()
            else:
                stream.flush()

    def clear(self) -> None:
        """Drop the rows recorded so far."""
        with self._lock:
            self._rows.clear()
            self._forced.clear()

    @property
    def header(self) -> list[str]:
        """The column names: ``cycle``, ``time_ms``, then the paths."""
        return ["cycle", "time_ms", *self.paths]

    @property
    def rows(self) -> list[Row]:
        """The rows kept, oldest first: ``(cycle, time_ms, value, ...)``."""
        with self._lock:
            return list(self._rows)

    @property
    def forced(self) -> list[tuple[str, ...]]:
        """Per row, the traced paths that were forced when it was taken."""
        with self._lock:
            return list(self._forced)

    def column(self, path: str) -> list[Any]:
        """The values of one traced path, oldest first."""
        index = self._index(path)
        return [row[index] for row in self.rows]

    def _index(self, path: str) -> int:
        try:
            return 2 + self.paths.index(path)
        except ValueError:
            raise ValueError(f"{path!r} is not traced (traced: {', '.join(self.paths)})") from None

    def to_csv(self, target: str | os.PathLike[str] | typing.TextIO | None = None) -> str:
        """The rows as CSV (header ``cycle,time_ms,<paths>``), written to ``target`` if given; BOOLs as 0 / 1."""
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(self.header)
        writer.writerows([_plain(value) for value in row] for row in self.rows)
        text = buffer.getvalue()
        if isinstance(target, (str, os.PathLike)):
            Path(target).write_text(text, encoding="utf-8")
        elif target is not None:
            target.write(text)
        return text

    def to_dataframe(self) -> Any:
        """The rows as a pandas DataFrame indexed by cycle (pandas must be installed)."""
        try:
            pandas = importlib.import_module("pandas")
        except ImportError:
            raise ImportError("Trace.to_dataframe() needs pandas: pip install pandas") from None
        frame = pandas.DataFrame(self.rows, columns=self.header)
        return frame.set_index("cycle")

    def plot(self, target: str | os.PathLike[str], paths: typing.Sequence[str] | None = None) -> Path:
        """Draw the traced signals to ``target`` (``.png`` or ``.svg``): one lane each, BOOLs and integers as steps.

        Needs matplotlib (``pip install iecoop[plot]``).
        """
        target = Path(target)
        if target.suffix.lower() not in (".png", ".svg"):
            raise ValueError(f"Trace.plot(): {target.name} must end in .png or .svg")
        figure = self.figure(paths)
        from matplotlib import pyplot

        try:
            figure.savefig(target)
        finally:
            pyplot.close(figure)
        return target

    def figure(self, paths: typing.Sequence[str] | None = None) -> Any:
        """The matplotlib ``Figure`` ``plot`` draws, a scope's view: one lane per signal, BOOLs and integers as steps.

        For a notebook or more drawing on it; ``pyplot.close(figure)`` frees it.
        """
        try:
            import matplotlib
        except ImportError:
            raise ImportError("Trace.plot() needs matplotlib: pip install iecoop[plot]") from None
        matplotlib.use("Agg")  # a file, never a window: works without a display
        from matplotlib import pyplot
        from matplotlib.ticker import MaxNLocator

        chosen = list(self.paths if paths is None else paths)
        indices = [self._index(path) for path in chosen]
        rows = self.rows
        times = [row[1] for row in rows]
        figure, axes = pyplot.subplots(len(chosen), 1, sharex=True, squeeze=False,
                                       figsize=(8, 1.2 + 1.3 * len(chosen)))
        try:
            for lane, path, index in zip(axes[:, 0], chosen, indices):
                # BOOLs and enumeration values as their numbers
                values = [int(row[index]) if isinstance(row[index], int) else row[index] for row in rows]
                first = rows[0][index] if rows else None
                if isinstance(first, int):
                    # A digital or integer signal holds its value until the next sample, as a scope draws it.
                    lane.step(times, values, where="post")
                    if isinstance(first, bool):
                        lane.set_yticks([0, 1], ["FALSE", "TRUE"])
                        lane.set_ylim(-0.2, 1.2)
                    else:
                        lane.yaxis.set_major_locator(MaxNLocator(integer=True))
                else:
                    lane.plot(times, values)
                lane.set_ylabel(path, rotation=0, ha="right", va="center")
                lane.grid(True, alpha=0.3)
            axes[-1, 0].set_xlabel("time (ms)")
            figure.tight_layout()
        except BaseException:
            pyplot.close(figure)
            raise
        return figure


def _plain(value: Any) -> Any:
    """A value as a number or text for a CSV or a plot: BOOL as 0 / 1, an enum member as its name."""
    if isinstance(value, bool):
        return int(value)
    name = getattr(value, "name", None)
    return name if isinstance(name, str) else value
