"""``iecoop st2py`` and ``iecoop st run``: output, files written, and the exit status of each failure."""

from __future__ import annotations

import io
import pathlib
from collections.abc import Callable
from typing import TextIO

import pytest

from iecoop.cli import main
from iecoop.cli.st import st2py, st_run

TWINCAT = pathlib.Path(__file__).parents[1] / "st" / "data" / "twincat"


def call(command: Callable[[list[str], TextIO, TextIO], int], *argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    status = command(list(argv), out, err)
    return status, out.getvalue(), err.getvalue()


def test_st_run_prints_the_trace_of_a_twincat_project() -> None:
    status, out, err = call(st_run, str(TWINCAT), "--cycles", "9", "--every", "1")
    assert (status, err) == (0, "")
    lines = out.splitlines()
    assert lines[0].startswith("MAIN on PlcTask (10 ms), twincat profile, 9 cycles")
    assert lines[1].split()[:4] == ["time", "ms", "cycle", "rLevel"]
    assert lines[5].split()[:3] == ["30", "4", "50.00"]  # full at the 4th cycle
    assert len(lines) == 2 + 9


def test_st_run_fault_exits_1(tmp_path: pathlib.Path) -> None:
    source = tmp_path / "div.st"
    source.write_text("PROGRAM MAIN\nVAR a : INT := 1; b : INT; END_VAR\na := a / b;\nEND_PROGRAM\n")
    status, out, err = call(st_run, str(source), "--cycles", "2")
    assert status == 1 and f"PLC fault in cycle 1 at {source}:3 (MAIN): RTSEXCPT_DIVIDEBYZERO" in err


RUNAWAY = "PROGRAM MAIN\nVAR x : INT; END_VAR\nx := x + 1;\nWHILE x > 1 DO x := 5; END_WHILE\nEND_PROGRAM\n"


def test_st_run_stops_a_cycle_that_never_ends_as_a_watchdog_fault(tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch) -> None:
    source = tmp_path / "loop.st"
    source.write_text(RUNAWAY)
    status, out, err = call(st_run, str(source), "--cycles", "3", "--watchdog", "50ms")
    assert status == 1 and f"PLC fault in cycle 2 at {source}:4 (MAIN): RTSEXCPT_WATCHDOG" in err and "watchdog 50 ms" in err
    monkeypatch.setattr("iecoop.cli.st.DEFAULT_WATCHDOG", "40ms")  # the default, made short for the test
    status, out, err = call(st_run, str(source), "--cycles", "3")
    assert status == 1 and "RTSEXCPT_WATCHDOG" in err and "watchdog 40 ms" in err


def test_st_run_watchdog_takes_a_time_or_0(tmp_path: pathlib.Path) -> None:
    source = tmp_path / "count.st"
    source.write_text("PROGRAM MAIN\nVAR x : INT; END_VAR\nx := x + 1;\nEND_PROGRAM\n")
    assert call(st_run, str(source), "--cycles", "2", "--watchdog", "0")[0] == 0
    with pytest.raises(SystemExit):
        call(st_run, str(source), "--watchdog", "soon")


def test_st_run_bad_source_and_unknown_program_exit_2(tmp_path: pathlib.Path) -> None:
    source = tmp_path / "bad.st"
    source.write_text("PROGRAM MAIN\nVAR x : FB_Nowhere; END_VAR\nEND_PROGRAM\n")
    status, _, err = call(st_run, str(source))
    assert status == 2 and "unknown type 'FB_Nowhere'" in err
    status, _, err = call(st_run, str(TWINCAT), "--program", "PLC_PRG")
    assert status == 2 and "no PROGRAM PLC_PRG" in err


def test_st2py_prints_or_writes(tmp_path: pathlib.Path) -> None:
    status, out, _ = call(st2py, str(TWINCAT))
    assert status == 0 and "class FB_Tank(FunctionBlock, I_Tank):" in out
    status, out, _ = call(st2py, str(TWINCAT), "-o", str(tmp_path))
    assert status == 0 and (tmp_path / "twincat.py").read_text().count("class ") == 6
    status, _, err = call(st2py, str(tmp_path / "missing.st"))
    assert status == 2 and "does not exist" in err


def test_st2py_and_st_run_are_commands_of_iecoop(capsys: pytest.CaptureFixture[str]) -> None:
    folder = TWINCAT
    assert main(["st", "run", str(folder), "--cycles", "2"]) == 0
    out = capsys.readouterr().out
    assert "MAIN on PlcTask" in out and out.count("\n") >= 4
    assert main(["st2py", str(folder)]) == 0
    assert "class MAIN(Program):" in capsys.readouterr().out
    assert main(["st", "run", str(folder), "--program", "NOPE"]) == 2
    assert "declares no PROGRAM NOPE" in capsys.readouterr().err


PROJECTS = pathlib.Path(__file__).parents[1] / "st" / "data" / "projects"


def test_st_run_streams_rows_above_a_progress_line_on_a_terminal(monkeypatch: pytest.MonkeyPatch) -> None:
    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    from iecoop.cli import trace

    monkeypatch.setattr(trace, "FLUSH_EVERY", 0.0)  # draw at every cycle
    out = Terminal()
    argv = [str(PROJECTS / "FillStation"), "--set", "GVL_IO.bStartButton=TRUE@100ms", "--trace", "MAIN.eState", "--cycles", "1200"]
    assert st_run(argv, out, io.StringIO()) == 0
    text = out.getvalue()
    assert text.startswith("MAIN on PlcTask (5 ms), twincat profile, 1200 cycles; rows where a traced value changed\n")
    assert "\r[" in text and "100% 1200/1200 cycles" in text and text.endswith("\r")  # the bar, wiped at the end
    # the first row after the start button shows up once its cycle ran, after the bar of the cycles before it
    before_filling = text[: text.index("FILLING")]
    assert "20/1200 cycles" in before_filling and "22/1200" not in before_filling


def test_st_run_into_a_pipe_writes_the_rows_alone() -> None:
    status, out, err = call(st_run, str(PROJECTS / "FillStation"), "--cycles", "1500", "--trace", "MAIN.eState")
    assert (status, err) == (0, "")
    assert "\r" not in out and out.splitlines()[-1].split()[:2] == ["7495", "1500"]


def test_an_exported_project_runs_on_its_task_and_strings_stay_on_their_row(tmp_path: pathlib.Path) -> None:
    # PackLine's MAIN holds an unbound REFERENCE TO (refGoal): picking the default columns does not read it
    assert main(["export", str(PROJECTS / "PackLine"), "-o", str(tmp_path / "out")]) == 0
    assert (tmp_path / "out" / "PlcTask.TcTTO").read_bytes() == (PROJECTS / "PackLine" / "PlcTask.TcTTO").read_bytes()
    assert '<None Include="PlcTask.TcTTO">' in (tmp_path / "out" / "PackLine.plcproj").read_text()
    status, out, err = call(st_run, str(tmp_path / "out"), "--cycles", "8", "--trace", "MAIN.sText")
    assert (status, err) == (0, "")
    lines = out.splitlines()
    assert lines[0].startswith("MAIN on PlcTask (2 ms)")  # <CycleTime>2000</CycleTime>
    assert lines[3].split() == ["10", "6", "zero", "pack$N"]  # 'pack$N' holds a line break: shown as ST writes it
    status, out, _ = call(st_run, str(PROJECTS / "PackLine"), "--cycles", "2")
    assert status == 0 and out.splitlines()[1].split()[:3] == ["time", "ms", "cycle"]


def _task_file(folder: pathlib.Path, name: str, cycle_us: int, priority: int, *calls: str) -> None:
    pou_calls = "".join(f"    <PouCall>\n      <Name>{call}</Name>\n    </PouCall>\n" for call in calls)
    (folder / f"{name}.TcTTO").write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n<TcPlcObject Version="1.1.0.1" ProductVersion="3.1.4024.12">\n'
        f'  <Task Name="{name}" Id="{{00000000-0000-0000-0000-00000000000{priority % 10}}}">\n'
        f"    <CycleTime>{cycle_us}</CycleTime>\n    <Priority>{priority}</Priority>\n{pou_calls}  </Task>\n</TcPlcObject>\n"
    )


def _two_programs(folder: pathlib.Path) -> pathlib.Path:
    folder.mkdir()
    (folder / "lines.st").write_text(
        "PROGRAM PRG_Fast\nVAR nCount : INT; END_VAR\nnCount := nCount + 1;\nEND_PROGRAM\n"
        "PROGRAM PRG_Slow\nVAR nCount : INT; END_VAR\nnCount := nCount + 10;\nEND_PROGRAM\n"
    )
    return folder


def test_st_run_runs_the_programs_each_task_file_calls_on_its_own_task(tmp_path: pathlib.Path) -> None:
    project = _two_programs(tmp_path / "cell")
    _task_file(project, "FastTask", 2000, 10, "PRG_Fast")
    _task_file(project, "SlowTask", 10000, 20, "prg_slow")  # ST names: case aside
    status, out, err = call(st_run, str(project), "--duration", "20ms", "--every", "1",
                            "--trace", "PRG_Fast.nCount,PRG_Slow.nCount")
    assert (status, err) == (0, "")
    lines = out.splitlines()
    assert lines[0].startswith("PRG_Fast on FastTask (2 ms); PRG_Slow on SlowTask (10 ms), twincat profile, 10 cycles")
    # every 2 ms the fast program counts one, every 10 ms the slow one ten: at 0 and 10 ms
    assert [line.split() for line in lines[2:]] == [
        [str(2 * n), str(n + 1), str(n + 1), str(10 if n < 5 else 20)] for n in range(10)
    ]
    # --program runs one alone, on the task that calls it
    status, out, _ = call(st_run, str(project), "--program", "PRG_Slow", "--cycles", "3", "--every", "1")
    assert status == 0 and out.splitlines()[0].startswith("PRG_Slow on SlowTask (10 ms)")
    assert [line.split()[-1] for line in out.splitlines()[2:]] == ["10", "20", "30"]


def test_st_run_without_task_calls_runs_main_or_the_one_program(tmp_path: pathlib.Path) -> None:
    alone = tmp_path / "alone"
    alone.mkdir()
    (alone / "p.st").write_text("PROGRAM P_Only\nVAR n : INT; END_VAR\nn := n + 2;\nEND_PROGRAM\n")
    _task_file(alone, "PlcTask", 5000, 20)  # a task that calls nothing: its cycle time still counts
    status, out, _ = call(st_run, str(alone), "--cycles", "2", "--every", "1")
    assert status == 0 and out.splitlines()[0].startswith("P_Only on PlcTask (5 ms)")
    assert [line.split() for line in out.splitlines()[2:]] == [["0", "1", "2"], ["5", "2", "4"]]
    status, _, err = call(st_run, str(_two_programs(tmp_path / "two")))
    assert status == 2 and "declares no PROGRAM MAIN; its PROGRAMs: PRG_Fast, PRG_Slow (choose one with --program)" in err


def test_st_run_of_a_task_file_calling_an_absent_program_names_the_file_and_task(tmp_path: pathlib.Path) -> None:
    project = _two_programs(tmp_path / "cell")
    _task_file(project, "PlcTask", 10000, 20, "PRG_Fast", "PRG_Gone")
    status, out, err = call(st_run, str(project))
    assert (status, out) == (2, "")
    assert f"{project / 'PlcTask.TcTTO'}: task PlcTask calls PRG_Gone, which the project declares no PROGRAM of" in err
