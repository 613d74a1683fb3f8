"""``iecoop serve --ads --modbus --trace``: the servers of a served ST program, and Ctrl+C ending them cleanly."""

from __future__ import annotations

import io
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from iecoop.cli.serve import located_in, serve

pyads = pytest.importorskip("pyads")
pytest.importorskip("pymodbus")
from pymodbus.client import ModbusTcpClient  # noqa: E402

TIMEOUT = 60.0  # seconds: the bound of the served process's start and stop

PLANT = """\
PROGRAM MAIN
VAR_INPUT
    bStart AT %IX0.0 : BOOL;
END_VAR
VAR
    bPump AT %QX0.0 : BOOL;
    nLevel AT %QW0 : INT;
    nCount : INT;
    bSpare AT %I* : BOOL;
END_VAR
nCount := nCount + 1;
bPump := bStart;
IF bPump THEN nLevel := nLevel + 1; END_IF
END_PROGRAM
"""


@pytest.fixture
def plant(tmp_path: Path) -> Path:
    source = tmp_path / "plant.st"
    source.write_text(PLANT)
    return source


def test_located_variables_come_from_the_st_declarations(plant: Path) -> None:
    assert located_in(str(plant), "MAIN") == {"MAIN.bStart": "%IX0.0", "MAIN.bPump": "%QX0.0", "MAIN.nLevel": "%QW0"}
    assert located_in(str(plant), "OTHER") == {}


@pytest.mark.parametrize(("options", "words"), [
    (["--csv", "x.csv"], "--csv and --plot write what --trace records"),
    (["--trace", "MAIN.nothing"], "--trace: MAIN.nothing"),
    (["--trace", "MAIN.nCount", "--plot", "x.pdf"], "must end in .png or .svg"),
])
def test_trace_options_are_checked_before_serving(plant: Path, options: list[str], words: str) -> None:
    out, err = io.StringIO(), io.StringIO()
    assert serve([str(plant), "--ads", "0", *options], out, err) == 2
    assert words in err.getvalue() and "ADS server" not in out.getvalue()


def test_modbus_needs_located_variables(tmp_path: Path) -> None:
    source = tmp_path / "bare.st"
    source.write_text("PROGRAM MAIN\nVAR n : INT; END_VAR\nn := n + 1;\nEND_PROGRAM\n")
    out, err = io.StringIO(), io.StringIO()
    assert serve([str(source), "--modbus", "0", "--duration", "10ms"], out, err) == 2
    assert "declares no located variable" in err.getvalue()


def test_ads_and_modbus_for_a_duration_with_a_trace(plant: Path, tmp_path: Path) -> None:
    out, err = io.StringIO(), io.StringIO()
    csv = tmp_path / "run.csv"
    status = serve([str(plant), "--ads", "0", "--modbus", "0", "--duration", "50ms", "--trace", "MAIN.nCount",
                    "--csv", str(csv)], out, err)
    assert (status, err.getvalue()) == (0, "")
    text = out.getvalue()
    assert re.search(r"ADS server at 127\.0\.0\.1:\d+, AMS Net ID 127\.0\.0\.1\.1\.1, AMS port 851", text)
    assert "%IX0.0 MAIN.bStart (discrete_inputs 0), %QX0.0 MAIN.bPump (coils 0), %QW0 MAIN.nLevel " \
           "(holding_registers 0)" in text
    assert "OPC UA" not in text  # only the servers named
    assert csv.read_text().splitlines()[:3] == ["cycle,time_ms,MAIN.nCount", "1,0,1", "2,10,2"]
    assert text.splitlines()[-1] == "iecoop serve: stopped after 50 ms of PLC time"


def _line(process: subprocess.Popen[str], pattern: str) -> re.Match[str]:
    assert process.stdout is not None
    seen = []
    for line in process.stdout:
        seen.append(line)
        found = re.search(pattern, line)
        if found:
            return found
    raise AssertionError(f"no line matched {pattern!r}: {''.join(seen)}")


@pytest.mark.slow  # seconds each: once, in the slow gate
@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process is a POSIX signal")
def test_ctrl_c_stops_every_server_cleanly(plant: Path, tmp_path: Path) -> None:
    plot = tmp_path / "run.png"
    process = subprocess.Popen(
        [sys.executable, "-m", "iecoop.cli", "serve", str(plant), "--ads", "0", "--modbus", "0",
         "--opcua", "opc.tcp://127.0.0.1:0", "--trace", "MAIN.nLevel,MAIN.bPump", "--plot", str(plot)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    try:
        ads_port = int(_line(process, r"ADS server at 127\.0\.0\.1:(\d+)")[1])
        modbus_port = int(_line(process, r"Modbus TCP server at 127\.0\.0\.1:(\d+)")[1])
        _line(process, "running in real time until Ctrl")
        client: Any = ModbusTcpClient("127.0.0.1", port=modbus_port, timeout=10)
        assert client.connect()
        plc = pyads.Connection("127.0.0.1.1.1", 851, f"127.0.0.1:{ads_port}")
        plc.open()
        try:
            plc.write_by_name("MAIN.bStart", True)  # over ADS: the pump runs ...
            deadline = time.monotonic() + TIMEOUT
            while not client.read_coils(0, count=1).bits[0]:  # ... and Modbus sees %QX0.0
                assert time.monotonic() < deadline, "the pump coil never came on"
                time.sleep(0.01)
            assert client.read_discrete_inputs(0, count=1).bits[0] is True
        finally:
            plc.close()
            client.close()
        process.send_signal(signal.SIGINT)
        stdout, stderr = process.communicate(timeout=TIMEOUT)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    assert process.returncode == 0, stdout + stderr
    assert "stopped after" in stdout and f"trace: plotted to {plot}" in stdout
    assert plot.stat().st_size > 0


def test_online_opens_the_online_write_and_force_to_ads_and_opc_ua_clients(plant: Path) -> None:
    pytest.importorskip("asyncua")
    out, err = io.StringIO(), io.StringIO()
    status = serve([str(plant), "--ads", "0", "--opcua", "opc.tcp://127.0.0.1:0", "--online", "--duration", "20ms"],
                   out, err)
    assert (status, err.getvalue()) == (0, "")
    assert re.search(r"ADS server at 127\.0\.0\.1:\d+, .*AMS port 851, online write and force", out.getvalue())
    assert "writable: every variable but the CONSTANTs; forced with the methods Online.Force / Release" \
        in out.getvalue()
    out = io.StringIO()
    assert serve([str(plant), "--ads", "0", "--duration", "20ms"], out, err) == 0
    assert "online write" not in out.getvalue()


def test_modbus_map_codesys_lets_a_plant_simulator_write_the_inputs(
        plant: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out, err = io.StringIO(), io.StringIO()
    status = serve([str(plant), "--modbus", "0", "--modbus-map", "codesys", "--duration", "20ms"], out, err)
    assert (status, err.getvalue()) == (0, "")
    assert "%IX0.0 MAIN.bStart (coils 0), %QX0.0 MAIN.bPump (discrete_inputs 0), %QW0 MAIN.nLevel " \
           "(input_registers 0)" in out.getvalue()
    out = io.StringIO()
    assert serve([str(plant), "--modbus", "0", "--modbus-map", "wago"], out, err) == 2
    assert "invalid choice: 'wago'" in capsys.readouterr().err


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_serve_for_a_duration_shows_its_progress_on_a_terminal(plant: Path) -> None:
    out, err = _Terminal(), io.StringIO()
    assert serve([str(plant), "--ads", "0", "--duration", "300ms"], out, err) == 0
    text = out.getvalue()
    assert "\r[" + "#" * 30 + "] 100% 30/30 cycles" in text  # the runtime's progress callback, drawn
    assert text.endswith("iecoop serve: stopped after 300 ms of PLC time\n")
    piped = io.StringIO()
    assert serve([str(plant), "--ads", "0", "--duration", "50ms"], piped, err) == 0
    assert "cycles," not in piped.getvalue() and "\r" not in piped.getvalue()
