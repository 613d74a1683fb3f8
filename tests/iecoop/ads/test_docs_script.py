"""The pyads script of docs/commissioning.md runs, as a reader pastes it, against a server started here."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from iecoop import BOOL, REAL, VAR_INPUT, VAR_OUTPUT, Program, T
from iecoop.ads import AdsServer
from iecoop.runtime import Runtime, Task

pytest.importorskip("pyads")

PAGE = Path(__file__).resolve().parents[3] / "docs" / "commissioning.md"


class TankMain(Program, st_name="MAIN"):
    fLevel: REAL = VAR_INPUT(50.0)
    bValve: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        if self.fLevel < 40.0:
            self.bValve = True
        elif self.fLevel > 60.0:
            self.bValve = False


def script(caption: str) -> str:
    text = PAGE.read_text(encoding="utf-8")
    found = re.search(r"^```\{code-block\} python\n:caption: " + re.escape(caption) + r"\n\n(.*?)^```$", text, re.M | re.S)
    assert found is not None, f"no block {caption} in {PAGE.name}"
    return found[1]


def test_the_pyads_script_of_the_page(tmp_path: Path) -> None:
    code = script("tank_hmi.py")
    assert '"127.0.0.1")' in code  # the address of a server on the AMS router's port, 48898
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), TankMain())
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
