"""``iecoop serve``: run a PROGRAM in real time behind OPC UA, ADS and Modbus TCP servers.

::

    iecoop serve plant.st                                until Ctrl+C, OPC UA on opc.tcp://127.0.0.1:4840
    iecoop serve plant.st --ads --modbus 5020            ADS on 48898 (AMS port 851) and Modbus TCP on 5020
    iecoop serve plant/ --program MAIN --opcua opc.tcp://127.0.0.1:4841 --duration 5m
    iecoop serve plant.st --ads 48999 --trace MAIN.nLevel,MAIN.bPump --csv run.csv --plot run.png
    iecoop serve state --no-script                       a catalogue name: the clients set the inputs

The source is Structured Text, as ``iecoop st run`` reads it (its PROGRAM on
a 10 ms ``PlcTask``), or a name a plugged-in catalogue knows (the showcase's
patterns, with their scripted events and plant simulation, which run before
each cycle unless ``--no-script`` is given). It is paced by the wall clock.

Servers: ``--opcua URL`` (the variables under the namespace ``urn:iecoop`` by
instance path, ``PlcTask.MAIN.nCount``), ``--ads [PORT]`` (TwinCAT symbol
names, ``MAIN.nCount``, AMS Net ID 127.0.0.1.1.1 port 851; PORT defaults to
48898) and ``--modbus PORT`` (the ST source's located variables, ``AT %IX0.0``,
as Modbus tables; ``--modbus-map codesys`` maps them as CODESYS's Modbus
slave device does, so that a plant simulator writes the inputs). Without any
of them, OPC UA is served on its default endpoint. ADS and Modbus listen on ``--host`` (127.0.0.1: this machine only).
``--online`` lets OPC UA and ADS clients write every variable but a
CONSTANT and force, as TwinCAT's online view does (off by default).
``--trace`` records symbol paths every cycle; ``--csv`` streams every row
to its file as it is taken, and at the end ``--plot`` draws the last
10,000 rows. Needs the extras of the servers asked for (``opcua``,
``ads``: none beyond the standard library for the server, ``modbus``).

Exit status: 0 after the duration or Ctrl+C, 1 on a PLC fault or a server
that cannot start, 2 for an unknown name or a bad option.
"""

from __future__ import annotations

import argparse
import contextlib
import pathlib
import sys
from collections.abc import Sequence
from typing import Any, TextIO

from iecoop import PlcException, T
from iecoop.cli.base import Command, Names, Served, UsageError, usage_errors
from iecoop.cli.st import load_tasks, translated
from iecoop.cli.trace import Progress, add_trace_arguments, check_trace_options, write_trace
from iecoop.exceptions import AccessError
from iecoop.runtime import Runtime, Trace

__all__ = ["HELP", "add_arguments", "command", "located_in", "serve", "trace_for"]

#: The PLC time one ``Runtime.run`` call covers when serving until interrupted.
_SLICE = T("1s")
#: The default OPC UA endpoint and ADS TCP port (the AMS router's).
_OPCUA = "opc.tcp://127.0.0.1:4840"
_ADS_PORT = 48898

#: The help line of ``iecoop serve``.
HELP = "run one pattern or example in real time behind OPC UA, ADS and Modbus TCP servers"


def _time(text: str) -> int:
    try:
        value = T(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be longer than 0 ms, got {text!r}")
    return value


def _port(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"a TCP port is a number 0..65535, got {text!r}") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"a TCP port is a number 0..65535, got {value}")
    return value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``iecoop serve``."""
    parser.add_argument("name", help="an ST file or folder, or a name from 'iecoop list', e.g. state")
    parser.add_argument("--program", default=None,
                        help="the PROGRAM of an ST source to serve (default: those its tasks call, else MAIN)")
    parser.add_argument("--opcua", "--endpoint", dest="opcua", metavar="URL",
                        help=f"serve OPC UA at URL (default when no server is named: {_OPCUA}; port 0 picks one)")
    parser.add_argument("--ads", nargs="?", const=_ADS_PORT, type=_port, metavar="PORT",
                        help=f"serve ADS on TCP PORT (default {_ADS_PORT}), AMS Net ID 127.0.0.1.1.1, AMS port 851")
    parser.add_argument("--modbus", type=_port, metavar="PORT",
                        help="serve the located variables (AT %%IX0.0 ...) over Modbus TCP on PORT")
    parser.add_argument("--modbus-map", choices=("areas", "codesys"), default="areas",
                        help="areas: %%I as discrete inputs / input registers, %%Q as coils / holding registers "
                             "(WAGO's mapping, the default); codesys: as CODESYS's Modbus slave device, the master "
                             "writes %%IX / %%IW as coils / holding registers and reads %%QX / %%QW")
    parser.add_argument("--online", action="store_true",
                        help="let OPC UA and ADS clients write any variable and force (TwinCAT's online write and force)")
    parser.add_argument("--host", default="127.0.0.1",
                        help="the address ADS and Modbus listen on (default 127.0.0.1: this machine only)")
    parser.add_argument("--duration", type=_time, metavar="TIME",
                        help="how long to run, a TIME literal such as 30s or 5m (default: until Ctrl+C)")
    parser.add_argument("--profile", choices=("twincat", "codesys"), default="twincat", help="the PLC profile")
    parser.add_argument("--no-script", action="store_true",
                        help="do not run the scenario's scripted events and simulation: the clients set the inputs")
    add_trace_arguments(parser)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="iecoop serve", description=HELP[0].upper() + HELP[1:] + ".")
    add_arguments(parser)
    return parser


def _st_source(args: argparse.Namespace) -> Served:
    # The project's .TcTTO tasks with the programs they call (cycle time and priority), as `iecoop st run` runs them.
    tasks = load_tasks(args.name, args.program, args.profile)
    runtime = Runtime(store=":memory:", profile=args.profile)
    for task, programs in tasks:
        runtime.add_task(task, *(program for _, program in programs))
    on = [f"{', '.join(name for name, _ in programs)} on {task.name} ({task.interval} ms)" for task, programs in tasks]
    names = tuple(name for _, programs in tasks for name, _ in programs)
    first, _, rest = on[0].partition(" on ")
    return Served(", ".join(names), "; ".join([f"{first} of {args.name} on {rest}", *on[1:]]), runtime, programs=names)


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


def located_in(source: str, *programs: str) -> dict[str, str]:
    """The located variables (``bStart AT %IX0.0 : BOOL;``) of the PROGRAMs ``programs`` and of the named GVLs in ``source``.

    Symbol path -> address; ``AT %I*`` (placed by the I/O configuration) is left out.
    """
    from iecoop.st.read.parse import is_st_identifier, parse_sources

    units = translated(source, lambda path: parse_sources(path))
    wanted = {program.casefold() for program in programs}
    found: dict[str, str] = {}

    def add(owner: str, name: str, location: Any) -> None:
        text = str(location).removeprefix("AT").strip() if location is not None else ""
        if text.startswith("%") and "*" not in text:
            found[f"{owner}.{name}"] = text

    for unit in units:
        for item in unit.tree.items:
            kind, owner = type(item).__name__, str(getattr(item, "name", "") or "")
            if kind == "Program" and owner.casefold() in wanted:
                for block in item.declarations:
                    for declaration in block.items:
                        for variable in getattr(declaration, "variables", ()):
                            add(owner, str(variable.variable.name), getattr(variable, "location", None))
            elif kind == "GlobalVariableDeclarations" and is_st_identifier(owner):
                for declaration in item.items:
                    spec = declaration.spec
                    for name in spec.variables:
                        add(owner, str(name), getattr(spec, "location", None))
    return found


def trace_for(runtime: Runtime, args: argparse.Namespace) -> Trace | None:
    """The runtime trace ``--trace`` asks for (None without it); UsageError for a path or an option that is wrong.

    A serve may run for hours: with ``--csv`` every row goes to the file as it
    is taken, and the buffer keeps the last ones for ``--plot``.
    """
    check_trace_options(args)
    if not args.trace:
        return None
    try:
        return runtime.trace(args.trace, file=args.csv)
    except AccessError as exc:
        raise UsageError(f"--trace: {exc}") from None
    except OSError as exc:
        raise UsageError(f"--csv {args.csv}: {exc.strerror or exc}") from None


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


def _start_servers(served: Served, args: argparse.Namespace, stack: contextlib.ExitStack, out: TextIO) -> None:
    """Start the servers asked for, each closed by ``stack``; UsageError / RuntimeError say which one failed."""
    runtime = served.runtime
    opcua = args.opcua if args.opcua is not None or (args.ads is None and args.modbus is None) else None
    if opcua is not None:
        url = opcua or _OPCUA
        try:
            from iecoop.opcua import OpcUaServer
            server = OpcUaServer(runtime, endpoint=url, online=args.online)
            server.start()
        except Exception as exc:  # a missing extra, a bad endpoint, a port in use: say which and stop
            raise _Failed(f"the OPC UA server cannot start on {url}: {exc}") from None
        stack.callback(server.stop)
        out.write(f"OPC UA server at {server.endpoint}, namespace urn:iecoop\n")
        if args.online:
            out.write("writable: every variable but the CONSTANTs; forced with the methods Online.Force / Release\n")
        else:
            out.write(f"writable: {', '.join(server.writable()) or '(nothing)'}\n")
    if args.ads is not None:
        from iecoop.ads import AdsServer
        try:
            ads = AdsServer(runtime, args.ads, host=args.host, online=args.online)
            ads.start()
        except Exception as exc:
            raise _Failed(f"the ADS server cannot start on {args.host}:{args.ads}: {exc}") from None
        stack.callback(ads.stop)
        online = ", online write and force" if args.online else ""
        out.write(f"ADS server at {ads.host}:{ads.port}, AMS Net ID {ads.net_id}, AMS port {ads.ams_port}{online}\n")
    if args.modbus is not None:
        located = located_in(args.name, *served.programs) if served.programs else {}
        if not located:
            raise UsageError(f"--modbus: {args.name} declares no located variable (bStart AT %IX0.0 : BOOL;) "
                             f"in {'PROGRAM ' + ', '.join(served.programs) if served.programs else 'its PROGRAMs'} or a GVL")
        try:
            from iecoop.modbus import ModbusServer
            from iecoop.modbus import CODESYS_DEVICE_TABLES, DEFAULT_TABLES
            tables = CODESYS_DEVICE_TABLES if args.modbus_map == "codesys" else DEFAULT_TABLES
            modbus = ModbusServer(runtime, args.modbus, host=args.host, located=located, tables=tables)
            modbus.start()
        except (ValueError, AccessError) as exc:
            raise UsageError(f"--modbus: {exc}") from None
        except Exception as exc:
            raise _Failed(f"the Modbus server cannot start on {args.host}:{args.modbus}: {exc}") from None
        stack.callback(modbus.stop)
        mapped = ", ".join(f"{v.address} {v.path} ({v.table.value} {v.first})" for v in modbus.variables)
        out.write(f"Modbus TCP server at {modbus.host}:{modbus.port}: {mapped}\n")


class _Failed(Exception):
    """A server that cannot start: the command says why and exits 1."""


def _serve(served: Served, args: argparse.Namespace, out: TextIO, err: TextIO) -> int:
    runtime = served.runtime
    trace = trace_for(runtime, args)
    out.write(f"iecoop serve: {served.title}\n")
    try:
        # Ctrl+C at any moment, a server still starting included, closes every server started.
        with contextlib.ExitStack() as stack:
            _start_servers(served, args, stack, out)
            _run(served, args, out)
    except KeyboardInterrupt:
        pass  # Ctrl+C is how a serve without --duration ends
    except _Failed as exc:
        err.write(f"iecoop serve: {exc}\n")
        return 1
    except PlcException as exc:
        err.write(f"iecoop serve: {served.name}: PLC fault: {exc.code.name} ({exc})\n")
        return 1
    write_trace(trace, args, out)
    out.write(f"iecoop serve: stopped after {runtime.time_ms} ms of PLC time\n")
    return 0


def _run(served: Served, args: argparse.Namespace, out: TextIO) -> None:
    """Run the served runtime in real time for ``--duration`` or until Ctrl+C, its script before each cycle."""
    runtime = served.runtime
    script = served.script
    if script is not None and not args.no_script:
        cycle = 0

        def play() -> None:
            nonlocal cycle
            cycle += 1
            script(cycle)

        runtime.on_cycle_start.append(play)
    how_long = f"for {args.duration} ms" if args.duration is not None else "until Ctrl+C"
    out.write(f"running in real time {how_long}\n")
    out.flush()
    if args.duration is not None:
        # On a terminal, the runtime's progress callback redraws a line as the PLC time passes.
        screen = out if out.isatty() else None
        total = args.duration // runtime.base_tick_ms
        line = Progress(total, screen) if screen is not None and total else None
        try:
            runtime.run(duration=args.duration, realtime=True, progress_every=10,
                        progress=None if line is None else lambda done, _total: line.update(done))
        finally:
            if line is not None:
                line.clear()
        return
    while True:
        runtime.run(duration=_SLICE, realtime=True)


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
