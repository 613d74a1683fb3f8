"""``iecoop serve``: run a PROGRAM in real time behind an OPC UA server.

::

    iecoop serve plant.st                                until Ctrl+C, on opc.tcp://127.0.0.1:4840
    iecoop serve plant/ --program MAIN --endpoint opc.tcp://127.0.0.1:4841 --duration 5m
    iecoop serve state --no-script                       a catalogue name: the clients set the inputs

The source is Structured Text, as ``iecoop st run`` reads it (its PROGRAM on
a 10 ms ``PlcTask``), or a name a plugged-in catalogue knows (the showcase's
patterns, with their scripted events and plant simulation, which run before
each cycle unless ``--no-script`` is given). It is paced by the wall clock.
An HMI, SCADA or script connects to the endpoint; the variables are under
the namespace ``urn:iecoop`` by instance path (``PlcTask.MAIN.nCount``).
Needs the ``opcua`` extra (``pip install "iecoop[opcua]"``).

Exit status: 0 after the duration or Ctrl+C, 1 on a PLC fault or a server
that cannot start, 2 for an unknown name or a bad option.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
from collections.abc import Sequence
from typing import TextIO

from iecoop import PlcException, T
from iecoop.cli.base import Command, Names, Served, usage_errors
from iecoop.cli.st import load_program, plc_task
from iecoop.runtime import Runtime

__all__ = ["HELP", "add_arguments", "command", "serve"]

#: The PLC time one ``Runtime.run`` call covers when serving until interrupted.
_SLICE = T("1s")

#: The help line of ``iecoop serve``.
HELP = "run one pattern or example in real time behind an OPC UA server (namespace urn:iecoop)"


def _time(text: str) -> int:
    try:
        value = T(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be longer than 0 ms, got {text!r}")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop serve``."""
    parser.add_argument("name", help="an ST file or folder, or a name from 'iecoop list', e.g. state")
    parser.add_argument("--program", default="MAIN", help="the PROGRAM of an ST source to serve (default MAIN)")
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


def _st_source(args: argparse.Namespace) -> Served:
    program = load_program(args.name, args.program, args.profile)
    runtime = Runtime(store=":memory:", profile=args.profile)
    runtime.add_task(plc_task(), program)
    return Served(args.program, f"{args.program} of {args.name}", runtime)


def _served(args: argparse.Namespace, names: Names | None, err: TextIO) -> Served | None:
    """The scenario ``args.name`` names, or None when nothing knows it (the reason is written to ``err``)."""
    found = names.scenario(args.name, args.profile) if names is not None else None
    if found is not None:
        return found
    path = pathlib.Path(args.name)
    if names is None or path.exists() or path.suffix or len(path.parts) > 1:
        return _st_source(args)
    err.write(names.unknown(args.name, "iecoop serve"))
    return None


def command(names: Names | None = None) -> Command:
    """The ``iecoop serve`` subcommand, taking the names of ``names`` besides ST sources."""

    @usage_errors("iecoop serve")
    def run(args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
        try:
            served = _served(args, names, err)
        except PlcException as exc:
            err.write(f"iecoop serve: {args.name}: PLC fault at start-up: {exc.code.name} ({exc})\n")
            return 1
        if served is None:
            return 2
        return _serve(served, args, out, err)

    return Command(HELP, add_arguments, run)


def _serve(served: Served, args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    try:
        from iecoop.opcua import OpcUaServer
    except ImportError as exc:
        err.write(f"iecoop serve: {exc}\n")
        return 1
    runtime = served.runtime
    try:
        server = OpcUaServer(runtime, endpoint=args.endpoint)
        server.start()
    except Exception as exc:  # a bad endpoint, a port in use, a failed start: say which and stop
        err.write(f"iecoop serve: the OPC UA server cannot start on {args.endpoint}: {exc}\n")
        return 1
    script = served.script
    if script is not None and not args.no_script:
        cycle = 0

        def play() -> None:
            nonlocal cycle
            cycle += 1
            script(cycle)

        runtime.on_cycle_start.append(play)
    how_long = f"for {args.duration} ms" if args.duration is not None else "until Ctrl+C"
    out.write(f"iecoop serve: {served.title}\n")
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
        err.write(f"iecoop serve: {served.name}: PLC fault: {exc.code.name} ({exc})\n")
        return 1
    finally:
        server.stop()
    out.write(f"iecoop serve: stopped after {runtime.time_ms} ms of PLC time\n")
    return 0


def serve(argv: Sequence[str] | None = None, out: TextIO | None = None, err: TextIO | None = None,
          names: Names | None = None) -> int:
    """The ``iecoop serve`` command: its arguments after ``serve``; returns the exit status."""
    out = sys.stdout if out is None else out
    err = sys.stderr if err is None else err
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # --help, or a bad option (argparse has printed why)
        return exc.code if isinstance(exc.code, int) else 0
    return command(names).run(args, out, err)
