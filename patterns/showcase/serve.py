"""``iecoop serve NAME``: a pattern or example in real time behind an OPC UA server.

The command is :mod:`iecoop.cli.serve`; this module plugs the catalogue's
names into it, so that the scenario served is the one ``iecoop run NAME``
traces (the same programs on a 10 ms ``PlcTask``), with its scripted events
and plant simulation unless ``--no-script`` is given::

    iecoop serve state                                   until Ctrl+C, on opc.tcp://127.0.0.1:4840
    iecoop serve state --endpoint opc.tcp://127.0.0.1:4841 --duration 5m
    iecoop serve observer --no-script                    the inputs are left to the OPC UA clients
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TextIO

from iecoop.cli import serve as command
from patterns.showcase.catalogue import NAMES

__all__ = ["serve"]


def serve(argv: Sequence[str] | None = None, out: TextIO | None = None, err: TextIO | None = None) -> int:
    """``iecoop serve`` with the catalogue's names: its arguments after ``serve``; returns the exit status."""
    return command.serve(argv, out, err, names=NAMES)
