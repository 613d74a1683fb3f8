"""Draw the plots the pages show, at every build, from runs of the runtime: ``docs/_generated/*.png``.

The commissioning page's tank (a PROGRAM keeping a level between 40 and 60,
a plant model in ``on_cycle_end``) runs for two seconds of PLC time in
virtual time, and ``Trace.plot`` draws its level and valve. The run is
deterministic, and the file is rewritten only when its bytes change, so
incremental builds stay incremental.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

from sphinx.application import Sphinx

from iecoop import BOOL, REAL, Program, T, VAR_INPUT, VAR_OUTPUT
from iecoop.runtime import Runtime, Task


class _Tank(Program, st_name="MAIN"):
    fLevel: REAL = VAR_INPUT(50.0)
    bValve: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        if self.fLevel < 40.0:
            self.bValve = True
        elif self.fLevel > 60.0:
            self.bValve = False


def _tank_plot(target: Path) -> None:
    main = _Tank()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms")), main)

    def plant() -> None:
        main.fLevel = max(0.0, main.fLevel + (3.0 if main.bValve else 0.0) - 1.0)

    rt.on_cycle_end.append(plant)
    trace = rt.trace(["MAIN.fLevel", "MAIN.bValve"])
    rt.run(duration=T("2s"))
    rt.stop()
    with tempfile.TemporaryDirectory() as folder:
        drawn = trace.plot(Path(folder) / target.name)
        data = drawn.read_bytes()
    if not target.exists() or target.read_bytes() != data:
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)


def _generate(app: Sphinx) -> None:
    _tank_plot(Path(app.srcdir) / "_generated" / "commissioning-tank.png")


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("builder-inited", _generate)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
