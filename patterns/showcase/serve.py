"""``iecoop serve NAME``: run a pattern or example in real time behind an OPC UA server.

::

    iecoop serve state                                   until Ctrl+C, on opc.tcp://127.0.0.1:4840
    iecoop serve state --endpoint opc.tcp://127.0.0.1:4841 --duration 5m
    iecoop serve observer --no-script                    the inputs are left to the OPC UA clients

The scenario is the one ``iecoop run NAME`` traces (the same programs on a
10 ms ``PlcTask``), paced by the wall clock. Its scripted events and plant
simulation run before each cycle, as in ``run``, unless ``--no-script`` is
given. An HMI, SCADA or script connects to the endpoint; the variables are
under the namespace ``urn:iecoop`` by instance path (``PlcTask.PackagingLine.state``).
Needs the ``opcua`` extra (``pip install "iecoop[opcua]"``).

Exit status: 0 after the duration or Ctrl+C, 1 on a PLC fault or a server
that cannot start, 2 for an unknown name or a bad option.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import TextIO

from iecoop import PlcException, T
from patterns.showcase.catalogue import Entry, build, find, unknown_name

__all__ = ["add_arguments", "run", "serve"]

#: The PLC time one ``Runtime.run`` call covers when serving until interrupted.
_SLICE = T("1s")


def _time(text: str) -> int:
    try:
        value = T(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be longer than 0 ms, got {text!r}")
    return value


#: The help line of ``iecoop serve``.
HELP = "run one pattern or example in real time behind an OPC UA server (namespace urn:iecoop)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop serve``."""
    parser.add_argument("name", help="a name from 'iecoop list', e.g. state")
    parser.add_argument("--endpoint", default="opc.tcp://127.0.0.1:4840", metavar="URL",
                        help="where the server listens (default: %(default)s; port 0 picks a free one)")
    parser.add_argument("--duration", type=_time, metavar="TIME",
                        help="how long to run, a TIME literal such as 30s or 5m (default: until Ctrl+C)")
    parser.add_argument("--profile", choices=("twincat", "codesys"), default="twincat", help="the PLC profile")
    parser.add_argument("--no-script", action="store_true",
                        help="do not run the scenario's scripted events and simulation: the clients set the inputs")


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="iecoop serve", description=HELP[0].upper() + HELP[1:] + ".")
    add_arguments(parser)
    return parser


def _entry(name: str, err: TextIO) -> Entry | None:
    try:
        entry = find(name)
    except KeyError:
        err.write(unknown_name(name, "iecoop serve"))
        return None
    if entry.problem or entry.demo:
        err.write(f"iecoop serve: {entry.name} cannot be served: {entry.problem or 'it has no Program'}\n")
        return None
    return entry


def serve(argv: Sequence[str] | None = None, out: TextIO | None = None, err: TextIO | None = None) -> int:
    """The ``iecoop serve`` command: its arguments after ``serve``; returns the exit status."""
    out = sys.stdout if out is None else out
    err = sys.stderr if err is None else err
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # --help, or a bad option (argparse has printed why)
        return exc.code if isinstance(exc.code, int) else 0
    return run(args, out, err)


def run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    """Serve the entry that the parsed ``args`` name; returns the exit status."""
    entry = _entry(args.name, err)
    if entry is None:
        return 2
    try:
        from iecoop.opcua import OpcUaServer
    except ImportError as exc:
        err.write(f"iecoop serve: {exc}\n")
        return 1
    try:
        scenario = build(entry, args.profile)
    except PlcException as exc:
        err.write(f"iecoop serve: {entry.name}: PLC fault at start-up: {exc.code.name} ({exc})\n")
        return 1
    runtime = scenario.runtime
    try:
        server = OpcUaServer(runtime, endpoint=args.endpoint)
        server.start()
    except Exception as exc:  # a bad endpoint, a port in use, a failed start: say which and stop
        err.write(f"iecoop serve: the OPC UA server cannot start on {args.endpoint}: {exc}\n")
        return 1
    script = entry.script
    if script is not None and not args.no_script:
        cycle = 0

        def play() -> None:
            nonlocal cycle
            cycle += 1
            script(scenario, cycle)

        runtime.on_cycle_start.append(play)
    how_long = f"for {args.duration} ms" if args.duration is not None else "until Ctrl+C"
    out.write(f"iecoop serve: {entry.name} -- {entry.heading()}\n")
    out.write(f"OPC UA server at {server.endpoint}, namespace urn:iecoop; running in real time {how_long}\n")
    out.write(f"writable: {', '.join(server.writable()) or '(nothing)'}\n")
    out.flush()
    try:
        if args.duration is not None:
            runtime.run(duration=args.duration, realtime=True)
        else:
            while True:
                runtime.run(duration=_SLICE, realtime=True)
    except KeyboardInterrupt:
        pass  # Ctrl+C is how a serve without --duration ends
    except PlcException as exc:
        err.write(f"iecoop serve: {entry.name}: PLC fault: {exc.code.name} ({exc})\n")
        return 1
    finally:
        server.stop()
    out.write(f"iecoop serve: stopped after {runtime.time_ms} ms of PLC time\n")
    return 0
