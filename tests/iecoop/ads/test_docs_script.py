"""The scripts of docs/commissioning.md run, as a reader pastes them, against the page's tank.st served here.

The pyads script talks ADS to it, the plant simulator Modbus with
``--modbus-map codesys``; each runs in a process of its own, as a reader
runs it, against servers started as ``iecoop serve`` starts them.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from iecoop.ads import AdsServer
from iecoop.cli.serve import located_in
from iecoop.cli.st import load_program, plc_task
from iecoop.runtime import Runtime

pytest.importorskip("pyads")

PAGE = Path(__file__).resolve().parents[3] / "docs" / "commissioning.md"


def tank(tmp_path: Path) -> Runtime:
    """A runtime running the page's ``tank.st`` as ``iecoop serve`` does: its PROGRAM MAIN on a 10 ms PlcTask."""
    source = tmp_path / "tank.st"
    source.write_text(script("tank.st", "text"), encoding="utf-8")
    runtime = Runtime(store=":memory:")
    runtime.add_task(plc_task(), load_program(str(source), "MAIN", "twincat"))
    return runtime


def script(caption: str, language: str = "python") -> str:
    text = PAGE.read_text(encoding="utf-8")
    found = re.search(r"^```\{code-block\} " + language + r"\n:caption: " + re.escape(caption) + r"\n\n(.*?)^```$",
                      text, re.M | re.S)
    assert found is not None, f"no block {caption} in {PAGE.name}"
    return found[1]


def test_the_pyads_script_of_the_page(tmp_path: Path) -> None:
    code = script("tank_hmi.py")
    assert '"127.0.0.1")' in code  # the address of a server on the AMS router's port, 48898
    rt = tank(tmp_path)
    with AdsServer(rt, port=0) as server, rt.running():
        path = tmp_path / "tank_hmi.py"
        # The one change: the free port this test's server took instead of 48898.
        path.write_text(code.replace('"127.0.0.1")', f'"127.0.0.1:{server.port}")'), encoding="utf-8")
        done = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "iecoop 3.1.4024, state (5, 0)"
    # the programs first, then every GVL of the process (other test modules' too)
    assert lines[1].startswith("{'MAIN.fLevel': 'REAL', 'MAIN.bValve': 'BOOL'")
    assert lines[2] == "{'MAIN.fLevel': 50.0, 'MAIN.bValve': False}"
    assert lines[3] == "valve open, level 30.0"


def test_the_plant_simulator_of_the_page_over_modbus(tmp_path: Path) -> None:
    pytest.importorskip("pymodbus")
    from iecoop.modbus import CODESYS_DEVICE_TABLES, ModbusServer

    code = script("tank_plant.py")
    assert "port=5020" in code
    rt = tank(tmp_path)
    located = located_in(str(tmp_path / "tank.st"), "MAIN")
    assert located == {"MAIN.fLevel": "%ID0", "MAIN.bValve": "%QX0.0"}
    trace = rt.trace(["MAIN.fLevel", "MAIN.bValve"], file=tmp_path / "tank.csv")
    with ModbusServer(rt, port=0, located=located, tables=CODESYS_DEVICE_TABLES) as server, rt.running():
        path = tmp_path / "tank_plant.py"
        path.write_text(code.replace("port=5020", f"port={server.port}"), encoding="utf-8")
        done = subprocess.run([sys.executable, str(path)], capture_output=True, text=True, timeout=600)
    trace.detach()
    assert done.returncode == 0, done.stdout + done.stderr
    found = re.fullmatch(r"the valve opened at (\d+) % and closed at (\d+) %\n", done.stdout)
    assert found is not None, done.stdout
    assert int(found[1]) < 40 < 60 < int(found[2])
    valve = [line.split(",")[3] for line in (tmp_path / "tank.csv").read_text().splitlines()[1:]]
    assert "1" in valve and valve[0] == "0"  # the PLC saw the simulator's levels and opened the valve
