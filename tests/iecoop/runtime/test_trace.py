"""Runtime.trace: chosen variables by path, every n cycles, in a ring buffer; CSV, DataFrame and plot."""

from __future__ import annotations

import importlib.util
import io
from pathlib import Path

import pytest

from iecoop import BOOL, INT, REAL, AccessError, Program, T, VAR, VAR_OUTPUT
from iecoop.runtime import DEFAULT_TRACE_SIZE, Runtime, Task, Trace


class Main(Program):
    count: INT = VAR(0)
    lamp: BOOL = VAR_OUTPUT(False)
    speed: REAL = VAR(0.0)

    def body(self) -> None:
        self.count += 1
        self.lamp = not self.lamp
        self.speed = self.count * 0.5


def _runtime() -> tuple[Runtime, Main]:
    main = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)
    return rt, main


def test_rows_hold_cycle_time_and_the_values_after_each_cycle() -> None:
    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count", "MAIN.lamp"])
    rt.run(cycles=3)
    assert isinstance(trace, Trace) and trace.size == DEFAULT_TRACE_SIZE == 10_000
    assert trace.rows == [(1, 0, 1, True), (2, 10, 2, False), (3, 20, 3, True)]
    assert trace.column("MAIN.count") == [1, 2, 3]


def test_the_ring_buffer_keeps_the_last_rows_and_every_n_samples_every_nth_cycle() -> None:
    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count"], every=3, size=4)
    rt.run(cycles=30)
    assert trace.rows == [(18, 170, 18), (21, 200, 21), (24, 230, 24), (27, 260, 27), (30, 290, 30)][1:]
    trace.detach()
    rt.run(cycles=3)
    assert len(trace.rows) == 4 and trace.rows[-1][0] == 30
    trace.clear()
    assert trace.rows == []


def test_csv_has_a_header_of_cycle_time_and_paths(tmp_path: Path) -> None:
    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count", "MAIN.lamp", "MAIN.speed"])
    rt.run(cycles=2)
    expected = "cycle,time_ms,MAIN.count,MAIN.lamp,MAIN.speed\n1,0,1,1,0.5\n2,10,2,0,1.0\n"
    assert trace.to_csv() == expected
    out = io.StringIO()
    trace.to_csv(out)
    trace.to_csv(tmp_path / "trace.csv")
    assert out.getvalue() == (tmp_path / "trace.csv").read_text(encoding="utf-8") == expected


def test_forced_variables_are_marked_per_row() -> None:
    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count", "MAIN.lamp"])
    rt.run(cycles=1)
    rt.force("main.lamp", False)
    rt.run(cycles=2)
    rt.release_all()
    rt.run(cycles=1)
    assert trace.forced == [(), ("MAIN.lamp",), ("MAIN.lamp",), ()]
    assert trace.column("MAIN.lamp") == [True, False, False, True]


@pytest.mark.parametrize(
    ("paths", "every", "size", "error", "words"),
    [
        (["MAIN.nothing"], 1, 10, AccessError, "Main has no member 'nothing'"),
        ("MAIN.count", 1, 10, TypeError, "a list of symbol paths"),
        (["MAIN.count"], 0, 10, ValueError, "every is a number of cycles"),
        (["MAIN.count"], 1, 0, ValueError, "size is a number of rows"),
    ],
)
def test_a_bad_trace_is_refused_when_it_is_made(
    paths: list[str], every: int, size: int, error: type[Exception], words: str
) -> None:
    rt, _ = _runtime()
    with pytest.raises(error, match=words):
        rt.trace(paths, every=every, size=size)
    assert rt.on_cycle_end == []


def test_to_dataframe_needs_pandas_or_says_so() -> None:
    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count"])
    rt.run(cycles=2)
    if importlib.util.find_spec("pandas") is None:
        with pytest.raises(ImportError, match="needs pandas: pip install pandas"):
            trace.to_dataframe()
    else:
        frame = trace.to_dataframe()
        assert list(frame.columns) == ["time_ms", "MAIN.count"]
        assert list(frame.index) == [1, 2]


def test_plot_refuses_a_file_it_cannot_write() -> None:
    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count"])
    with pytest.raises(ValueError, match="must end in .png or .svg"):
        trace.plot("trace.pdf")
    with pytest.raises(ValueError, match="'MAIN.lamp' is not traced"):
        trace.column("MAIN.lamp")


@pytest.mark.skipif(importlib.util.find_spec("matplotlib") is None, reason="matplotlib is not installed")
@pytest.mark.parametrize("suffix", [".png", ".svg"])
def test_plot_draws_one_lane_per_signal_to_png_or_svg(tmp_path: Path, suffix: str) -> None:
    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count", "MAIN.lamp", "MAIN.speed"])
    rt.run(cycles=20)
    target = trace.plot(tmp_path / f"trace{suffix}")
    data = target.read_bytes()
    if suffix == ".png":
        assert data.startswith(b"\x89PNG\r\n\x1a\n")
    else:
        assert b"<svg" in data and b"MAIN.lamp" in data and b"time (ms)" in data


@pytest.mark.skipif(importlib.util.find_spec("matplotlib") is None, reason="matplotlib is not installed")
def test_the_figure_draws_digital_and_integer_signals_as_steps_and_reals_as_lines() -> None:
    from matplotlib import pyplot

    rt, _ = _runtime()
    trace = rt.trace(["MAIN.count", "MAIN.lamp", "MAIN.speed"])
    rt.run(cycles=6)
    figure = trace.figure()
    try:
        count, lamp, speed = figure.axes
        assert speed.lines[0].get_drawstyle() == "default"  # a REAL: a line from sample to sample
        assert count.lines[0].get_drawstyle() == "steps-post"  # an INT holds its value, on whole-number ticks
        assert all(tick == int(tick) for tick in count.get_yticks())
        assert list(count.lines[0].get_ydata()) == [1, 2, 3, 4, 5, 6]
        assert lamp.lines[0].get_drawstyle() == "steps-post"
        assert list(lamp.lines[0].get_ydata()) == [1, 0, 1, 0, 1, 0]
        assert [label.get_text() for label in lamp.get_yticklabels()] == ["FALSE", "TRUE"]
        assert list(lamp.lines[0].get_xdata()) == [0, 10, 20, 30, 40, 50]
        assert speed.get_xlabel() == "time (ms)" and count.get_ylabel() == "MAIN.count"
    finally:
        pyplot.close(figure)


def test_a_trace_streams_every_row_to_a_csv_file_beyond_its_buffer(tmp_path: Path) -> None:
    rt, _ = _runtime()
    target = tmp_path / "long.csv"
    trace = rt.trace(["MAIN.count", "MAIN.lamp"], every=2, size=3, file=target)
    rt.run(cycles=1000)
    trace.detach()
    lines = target.read_text(encoding="utf-8").splitlines()
    assert lines[0] == "cycle,time_ms,MAIN.count,MAIN.lamp"
    assert len(lines) == 1 + 500 and trace.taken == 500
    assert lines[1:3] == ["2,10,2,0", "4,30,4,0"] and lines[-1] == "1000,9990,1000,0"
    assert len(trace.rows) == 3  # the buffer keeps only the last rows; the file has them all
    rt.run(cycles=2)  # detached: the file is closed and takes nothing more
    assert len(target.read_text(encoding="utf-8").splitlines()) == 501


def test_a_trace_streams_to_an_open_text_file_and_leaves_it_open() -> None:
    rt, _ = _runtime()
    out = io.StringIO()
    trace = rt.trace(["MAIN.count"], file=out)
    rt.run(cycles=2)
    trace.close()  # the stream ends; the buffer still records
    rt.run(cycles=1)
    assert out.getvalue() == "cycle,time_ms,MAIN.count\n1,0,1\n2,10,2\n"
    assert [row[0] for row in trace.rows] == [1, 2, 3] and not out.closed
