"""``--trace VARS --csv FILE --plot FILE`` of ``iecoop run`` and ``iecoop st run``: the table shows a runtime trace."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from iecoop.cli.st import st_run
from iecoop.cli.base import UsageError
from iecoop.cli.trace import TraceTable, run_cycles
from iecoop.runtime import Runtime, Task
from iecoop import INT, VAR, Program, T
from patterns.showcase import main as showcase_main

COUNT = "PROGRAM MAIN\nVAR nCount : INT; bEven : BOOL; tUp : TIME; END_VAR\n" \
        "nCount := nCount + 1;\nbEven := nCount MOD 2 = 0;\ntUp := tUp + T#10MS;\nEND_PROGRAM\n"


def test_st_run_shows_and_writes_the_traced_paths(tmp_path: Path) -> None:
    source = tmp_path / "count.st"
    source.write_text(COUNT)
    csv, plot = tmp_path / "count.csv", tmp_path / "count.svg"
    out, err = io.StringIO(), io.StringIO()
    status = st_run([str(source), "--cycles", "3", "--trace", "MAIN.bEven,MAIN.tUp", "--csv", str(csv),
                     "--plot", str(plot)], out, err)
    assert (status, err.getvalue()) == (0, "")
    assert out.getvalue().splitlines()[1:] == [
        "time ms  cycle  MAIN.bEven  MAIN.tUp",
        "      0      1  FALSE           10ms",
        "     10      2  TRUE            20ms",
        "     20      3  FALSE           30ms",
        f"trace: 3 rows written to {csv}",
        f"trace: plotted to {plot}",
    ]
    assert csv.read_text().splitlines() == ["cycle,time_ms,MAIN.bEven,MAIN.tUp", "1,0,0,10", "2,10,1,20", "3,20,0,30"]
    assert plot.read_text(encoding="utf-8").count("<svg") == 1


@pytest.mark.parametrize(("options", "words"), [
    (["--csv", "x.csv"], "--csv and --plot write what --trace records"),
    (["--trace", "MAIN.nothing"], "--trace: MAIN.nothing: MAIN has no member 'nothing'"),
    (["--trace", "MAIN.nCount", "--plot", "x.gif"], "must end in .png or .svg"),
])
def test_st_run_refuses_wrong_trace_options(tmp_path: Path, options: list[str], words: str) -> None:
    source = tmp_path / "count.st"
    source.write_text(COUNT)
    out, err = io.StringIO(), io.StringIO()
    assert st_run([str(source), "--cycles", "3", *options], out, err) == 2
    assert words in err.getvalue()


def test_iecoop_run_traces_a_catalogue_scenario(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    csv = tmp_path / "state.csv"
    assert showcase_main(["run", "state", "--cycles", "4", "--trace", "PackagingLine.batches,PackagingLine.starved",
                          "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "time ms  cycle  PackagingLine.batches  PackagingLine.starved" in out
    assert csv.read_text().splitlines()[0] == "cycle,time_ms,PackagingLine.batches,PackagingLine.starved"
    assert len(csv.read_text().splitlines()) == 5
    assert showcase_main(["run", "state", "--cycles", "4", "--trace", "MAIN.x"]) == 2
    assert "iecoop run: --trace: MAIN.x: no program or GVL named 'MAIN'" in capsys.readouterr().err


def test_the_table_is_a_view_of_the_runtime_trace() -> None:
    class Counter(Program):
        count: INT = VAR(0)

        def body(self) -> None:
            self.count += 2

    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), Counter())
    table: TraceTable = run_cycles(runtime, [], 3, every=1, paths=["Counter.count"])
    assert table.source is not None
    assert [row[2] for row in table.source.rows] == [2, 4, 6]
    assert [values for _, _, values in table.rows] == [["2"], ["4"], ["6"]]


def test_st_run_writes_every_row_of_a_run_longer_than_the_trace_buffer(tmp_path: Path) -> None:
    source = tmp_path / "count.st"
    source.write_text(COUNT)
    csv = tmp_path / "long.csv"
    out, err = io.StringIO(), io.StringIO()
    assert st_run([str(source), "--cycles", "10005", "--every", "5000", "--trace", "MAIN.nCount",
                   "--csv", str(csv)], out, err) == 0
    lines = csv.read_text().splitlines()
    assert len(lines) == 1 + 10_005 and lines[1] == "1,0,1" and lines[-1] == "10005,100040,10005"
    assert f"trace: 10005 rows written to {csv}" in out.getvalue()


def test_a_serve_streams_its_trace_to_the_csv_file_as_it_runs(tmp_path: Path) -> None:
    import argparse

    from iecoop.cli.serve import trace_for
    from iecoop.cli.trace import write_trace

    class Counter(Program):
        count: INT = VAR(0)

        def body(self) -> None:
            self.count += 1

    runtime = Runtime(store=":memory:")
    runtime.add_task(Task("PlcTask", interval=T("10ms")), Counter())
    csv = tmp_path / "serve.csv"
    args = argparse.Namespace(trace=["Counter.count"], csv=str(csv), plot=None)
    trace = trace_for(runtime, args)
    assert trace is not None and trace.size == 10_000
    runtime.run(cycles=12_000)  # longer than the buffer, as a serve of hours is
    out = io.StringIO()
    write_trace(trace, args, out)
    lines = csv.read_text().splitlines()
    assert len(lines) == 1 + 12_000 and lines[-1] == "12000,119990,12000"
    assert out.getvalue() == f"trace: 12000 rows written to {csv}\n"
    assert runtime.on_cycle_end == []
    bad = argparse.Namespace(trace=["Counter.count"], csv=str(tmp_path / "no" / "such" / "x.csv"), plot=None)
    with pytest.raises(UsageError, match="--csv .*No such file"):
        trace_for(runtime, bad)
