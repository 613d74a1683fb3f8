"""``iecoop serve FILE_OR_FOLDER``: an ST PROGRAM in real time behind the OPC UA server."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from iecoop.cli.serve import serve

pytest.importorskip("asyncua")


def test_serve_runs_an_st_program_for_its_duration(tmp_path: Path) -> None:
    source = tmp_path / "plant.st"
    source.write_text("PROGRAM MAIN\nVAR_INPUT nSetpoint : INT; END_VAR\nVAR nCount : INT; END_VAR\n"
                      "nCount := nCount + 1;\nEND_PROGRAM\n")
    out, err = io.StringIO(), io.StringIO()
    status = serve([str(source), "--endpoint", "opc.tcp://127.0.0.1:0", "--duration", "100ms"], out, err)
    assert (status, err.getvalue()) == (0, "")
    lines = out.getvalue().splitlines()
    assert lines[0] == f"iecoop serve: MAIN of {source} on PlcTask (10 ms)"
    assert lines[1].startswith("OPC UA server at opc.tcp://127.0.0.1:")
    assert "PlcTask.MAIN.nSetpoint" in lines[2]
    assert lines[-1] == "iecoop serve: stopped after 100 ms of PLC time"


def test_serve_without_a_catalogue_takes_paths_only(capsys: pytest.CaptureFixture[str]) -> None:
    assert serve(["state"]) == 2
    assert capsys.readouterr().err == "iecoop serve: ST source 'state' does not exist\n"


def test_serve_takes_the_task_of_the_project(tmp_path: Path) -> None:
    project = Path(__file__).parents[1] / "st" / "data" / "projects" / "FillStation"
    out, err = io.StringIO(), io.StringIO()
    status = serve([str(project), "--endpoint", "opc.tcp://127.0.0.1:0", "--duration", "20ms"], out, err)
    assert status == 0, err.getvalue()
    lines = out.getvalue().splitlines()
    assert lines[0] == f"iecoop serve: MAIN of {project} on PlcTask (5 ms)"  # <CycleTime>5000</CycleTime>
    assert lines[-1] == "iecoop serve: stopped after 20 ms of PLC time"


def test_serve_runs_the_programs_the_task_files_call(tmp_path: Path) -> None:
    (tmp_path / "line.st").write_text("PROGRAM PRG_Line\nVAR_INPUT nSpeed : INT; END_VAR\nVAR nCount : INT; END_VAR\n"
                                      "nCount := nCount + nSpeed;\nEND_PROGRAM\n")
    (tmp_path / "LineTask.TcTTO").write_text(
        '<?xml version="1.0" encoding="utf-8"?>\n<TcPlcObject Version="1.1.0.1">\n  <Task Name="LineTask">\n'
        "    <CycleTime>4000</CycleTime>\n    <Priority>5</Priority>\n"
        "    <PouCall>\n      <Name>PRG_Line</Name>\n    </PouCall>\n  </Task>\n</TcPlcObject>\n"
    )
    out, err = io.StringIO(), io.StringIO()
    status = serve([str(tmp_path), "--endpoint", "opc.tcp://127.0.0.1:0", "--duration", "20ms"], out, err)
    assert status == 0, err.getvalue()
    lines = out.getvalue().splitlines()
    assert lines[0] == f"iecoop serve: PRG_Line of {tmp_path} on LineTask (4 ms)"
    assert "LineTask.PRG_Line.nSpeed" in lines[2]  # the program's input, writable on its task
