"""The showcase catalogue: every pattern, SOLID principle and course example, ready to run.

An :class:`Entry` names a module, says how to build its scenario on a
runtime (its ``Program`` on a 10 ms ``PlcTask``), what to do to its inputs
during the run (the *script*) and which variables the trace shows. Modules
without a hand-written entry are found by :func:`entries` anyway and get a
generic one: the module's ``Program`` and its first elementary outputs.

>>> state = find("state")
>>> state.category, state.module
('behavioral', 'patterns.behavioral.state')
>>> scenario = build(state)
>>> scenario.runtime.run(cycles=1)
>>> [column.label for column in state.columns]
['state', 'packs', 'transitions', 'refused', 'batches']
>>> [show(read(scenario, column)) for column in state.columns]
['RESETTING', '0', '1', '0', '0']
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import importlib
import inspect
import pkgutil
import re
import sys
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import patterns
from iecoop import TYPE_CLASS, FunctionBlock, Program, T, var_info
from iecoop.runtime import Runtime, Task
from iecoop.uml import class_diagram

__all__ = [
    "CATEGORIES",
    "Column",
    "Entry",
    "Scenario",
    "build",
    "entries",
    "find",
    "plc_task",
    "read",
    "show",
    "write",
]

#: Category key -> heading, in catalogue order.
CATEGORIES: dict[str, str] = {
    "creational": "Creational patterns",
    "structural": "Structural patterns",
    "behavioral": "Behavioral patterns",
    "solid": "SOLID principles",
    "examples": "Course examples",
}

#: The packages searched for modules, by category.
_PACKAGES: dict[str, str] = {
    "creational": "patterns.creational",
    "structural": "patterns.structural",
    "behavioral": "patterns.behavioral",
    "solid": "patterns.solid",
    "examples": "iecoop_examples",
}


@dataclasses.dataclass
class Scenario:
    """A built scenario: the runtime and its program instances (the first one is traced).

    ``sim`` holds the state of a script's plant simulation (a tank level).
    """

    runtime: Runtime
    programs: list[Any]
    module: ModuleType
    sim: dict[str, float] = dataclasses.field(default_factory=dict)

    @property
    def program(self) -> Any:
        """The traced program instance."""
        return self.programs[0]


#: Reads one traced value from a scenario.
Getter = Callable[[Scenario], object]
#: Called before each cycle with the scenario and the number (from 1) of the cycle about to run.
Script = Callable[[Scenario, int], None]
#: Builds the programs of a scenario on a runtime (adding its tasks) and returns them.
Builder = Callable[[ModuleType, Runtime], Sequence[Any]]


@dataclasses.dataclass(frozen=True)
class Column:
    """One traced variable: a dotted path into the program (``"unit.execute.packs"``) or a getter.

    ``fmt`` is a format spec (``".1f"``) or a function giving the text;
    ``watch=False`` marks a value that moves every cycle (a temperature, a
    position): it is shown, but its changes alone do not make a trace row.
    """

    label: str
    source: str | Getter
    fmt: str | Callable[[Any], str] = ""
    watch: bool = True


@dataclasses.dataclass(frozen=True)
class Entry:
    """One module of the catalogue and how to run it.

    ``generic`` marks an entry made by discovery rather than by hand;
    ``demo`` one whose module has no ``Program`` but a ``main()``, which
    ``iecoop run`` calls instead of tracing; ``problem`` says why an entry
    cannot run (its module does not import, or has nothing to run).
    """

    name: str
    category: str
    module: str
    columns: tuple[Column, ...] = ()
    program: str | None = None
    script: Script | None = None
    setup: Callable[[Scenario], None] | None = None
    builder: Builder | None = None
    cycles: int = 100
    tour_cycles: int = 30
    title: str = ""
    generic: bool = False
    demo: bool = False
    problem: str = ""
    #: One line on when the pattern or principle pays off on a PLC (the patterns index of the docs shows it).
    use_when: str = ""
    #: The deliberate faults of the scenario, ``(what the trace shows, why)``: printed as expected.
    expected: tuple[tuple[str, str], ...] = ()

    @property
    def runnable(self) -> bool:
        """False when the module cannot be imported or has no ``Program`` to run."""
        return not self.problem

    def load(self) -> ModuleType:
        """Import the entry's module."""
        return importlib.import_module(self.module)

    def heading(self) -> str:
        """The title: the first line of the module docstring unless the entry sets one."""
        if self.title:
            return self.title
        try:
            doc = inspect.getdoc(self.load()) or ""
        except Exception as exc:  # a module being edited may not import
            return f"(cannot import: {type(exc).__name__})"
        first = doc.strip().splitlines()[0] if doc.strip() else self.module
        return first.replace("``", "")


# ---------------------------------------------------------------------------
# Reading and writing variables by path
# ---------------------------------------------------------------------------

_STEP = re.compile(r"([A-Za-z_]\w*)((?:\[-?\d+\])*)$")


@functools.lru_cache(maxsize=None)
def _parse(path: str) -> tuple[tuple[str, tuple[int, ...]], ...]:
    steps = []
    for part in path.split("."):
        match = _STEP.match(part)
        if match is None:
            raise ValueError(f"bad variable path {path!r}: {part!r}")
        indices = tuple(int(i) for i in re.findall(r"-?\d+", match.group(2)))
        steps.append((match.group(1), indices))
    return tuple(steps)


def _walk(root: Any, steps: Sequence[tuple[str, tuple[int, ...]]]) -> Any:
    value = root
    for name, indices in steps:
        value = getattr(value, name)
        for index in indices:
            value = value[index]
    return value


def resolve(root: Any, path: str) -> Any:
    """The value at ``path`` below ``root``: ``resolve(line, "unit.execute.packs")``, ``"drives[1].running"``."""
    return _walk(root, _parse(path))


def write(root: Any, path: str, value: object) -> None:
    """Write ``value`` at ``path`` below ``root`` (only inputs may be written from outside a block)."""
    steps = _parse(path)
    name, indices = steps[-1]
    holder = _walk(root, steps[:-1])
    if indices:
        target = getattr(holder, name)
        for index in indices[:-1]:
            target = target[index]
        target[indices[-1]] = value
    else:
        setattr(holder, name, value)


def read(scenario: Scenario, column: Column) -> object:
    """The current value of ``column`` in ``scenario``."""
    if isinstance(column.source, str):
        return resolve(scenario.program, column.source)
    return column.source(scenario)


def show(value: object, fmt: str | Callable[[Any], str] = "") -> str:
    """A value as the trace prints it: ``TRUE`` / ``FALSE``, enum names, REALs to two decimals."""
    if callable(fmt):
        return fmt(value)
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, enum.Enum):
        return value.name
    if isinstance(value, float):
        return format(value, fmt or ".2f")
    if fmt:
        return format(value, fmt)
    return str(value)


def ms(value: Any) -> str:
    """A TIME value as ``250ms``."""
    return f"{int(value)}ms"


# ---------------------------------------------------------------------------
# Scripts
# ---------------------------------------------------------------------------


def steps(*events: tuple[int, str, object]) -> Script:
    """A script writing ``value`` to ``path`` before cycle ``n``, for each ``(n, path, value)``."""
    plan: dict[int, list[tuple[str, object]]] = {}
    for cycle, path, value in events:
        plan.setdefault(cycle, []).append((path, value))

    def script(scenario: Scenario, cycle: int) -> None:
        for path, value in plan.get(cycle, ()):
            write(scenario.program, path, value)

    return script


def press(path: str, *cycles: int, hold: int = 1) -> list[tuple[int, str, object]]:
    """Events pressing the button at ``path`` at each of ``cycles``, held for ``hold`` cycles."""
    events: list[tuple[int, str, object]] = []
    for cycle in cycles:
        events += [(cycle, path, True), (cycle + hold, path, False)]
    return events


def chain(*scripts: Script) -> Script:
    """One script running ``scripts`` in order."""

    def script(scenario: Scenario, cycle: int) -> None:
        for each in scripts:
            each(scenario, cycle)

    return script


# ---------------------------------------------------------------------------
# Building
# ---------------------------------------------------------------------------


def plc_task() -> Task:
    """The showcase's cyclic task: ``PlcTask``, 10 ms, priority 20."""
    return Task("PlcTask", interval=T("10ms"), priority=20)


def program_classes(module: ModuleType) -> list[type[Program]]:
    """The concrete ``Program`` subclasses defined in ``module``, in definition order."""
    found: list[tuple[int, type[Program]]] = []
    for value in vars(module).values():
        if (
            isinstance(value, type)
            and issubclass(value, Program)
            and value is not Program
            and value.__module__ == module.__name__
            and not getattr(value, "_iec_abstract_", False)
        ):
            try:
                line = inspect.getsourcelines(value)[1]
            except (OSError, TypeError):
                line = 0
            found.append((line, value))
    return [cls for _, cls in sorted(found, key=lambda item: item[0])]


def build(entry: Entry, profile: str = "twincat") -> Scenario:
    """Instantiate the entry's programs on a fresh ``Runtime(store=":memory:")`` and run its setup."""
    if entry.problem or entry.demo:
        raise LookupError(f"{entry.name}: {entry.problem or 'no Program to build: run its main()'}")
    module = entry.load()
    runtime = Runtime(store=":memory:", profile=profile)
    if entry.builder is not None:
        programs = list(entry.builder(module, runtime))
    else:
        if entry.program is not None:
            classes: list[type[Program]] = [getattr(module, entry.program)]
        else:
            classes = program_classes(module)
        programs = [cls() for cls in classes]
        runtime.add_task(plc_task(), *programs)
    scenario = Scenario(runtime, programs, module)
    if entry.setup is not None:
        entry.setup(scenario)
    return scenario


_NOT_ELEMENTARY = {
    TYPE_CLASS.TYPE_POINTER,
    TYPE_CLASS.TYPE_REFERENCE,
    TYPE_CLASS.TYPE_ARRAY,
    TYPE_CLASS.TYPE_USERDEF,
    TYPE_CLASS.TYPE_INTERFACE,
    TYPE_CLASS.TYPE_PARAMS,
    TYPE_CLASS.TYPE_NONE,
    TYPE_CLASS.TYPE_ANY,
}


def _declared(instance: Any, base: type, sections: Sequence[str]) -> list[tuple[str, TYPE_CLASS]]:
    """``(name, type class)`` of the variables ``instance`` declares in ``sections``, in order."""
    own = [c for c in reversed(type(instance).__mro__) if isinstance(c, type) and issubclass(c, base) and c is not base]
    found: list[tuple[str, TYPE_CLASS]] = []
    for box in class_diagram(*own, related=False).classes:
        for field in box.fields:
            if field.section in sections and not field.static and field.name not in dict(found):
                try:
                    found.append((field.name, var_info(instance, field.name).TypeClass))
                except Exception:
                    continue
    return found


def generic_columns(cls: type[Program], limit: int = 5) -> tuple[Column, ...]:
    """The first ``limit`` elementary variables of ``cls``: VAR_OUTPUT, VAR, then the nested blocks' outputs.

    VAR_INPUT is used only when nothing else is found.
    """
    sample = cls()
    direct = _declared(sample, Program, ("VAR_OUTPUT", "VAR"))
    chosen = [(name, kind) for name, kind in direct if kind not in _NOT_ELEMENTARY]
    for name, kind in direct:
        block = getattr(sample, name, None)
        if kind == TYPE_CLASS.TYPE_USERDEF and getattr(type(block), "_iec_kind_", "") == "fb":
            outputs = _declared(block, FunctionBlock, ("VAR_OUTPUT",))
            chosen += [(f"{name}.{inner}", k) for inner, k in outputs if k not in _NOT_ELEMENTARY]
    if not chosen:
        chosen = [(n, k) for n, k in _declared(sample, Program, ("VAR_INPUT",)) if k not in _NOT_ELEMENTARY]
    timed = (TYPE_CLASS.TYPE_TIME, TYPE_CLASS.TYPE_LTIME)
    return tuple(Column(name, name, ms if kind in timed else "") for name, kind in chosen[:limit])


# ---------------------------------------------------------------------------
# Discovery
# ---------------------------------------------------------------------------


def _import_package(package: str) -> ModuleType | None:
    """Import ``package``, or None when it is not installed."""
    try:
        return importlib.import_module(package)
    except ImportError:
        return None


def _modules(package: str) -> Iterator[str]:
    root = _import_package(package)
    if root is None:
        return
    for info in pkgutil.walk_packages(root.__path__, prefix=f"{package}.", onerror=lambda name: None):
        leaf = info.name.rsplit(".", 1)[-1]
        if leaf.startswith(("_", "test")):
            continue
        yield info.name


def _no_arguments(function: Callable[..., object]) -> bool:
    try:
        parameters = inspect.signature(function).parameters.values()
    except (TypeError, ValueError):
        return False
    return all(p.default is not p.empty or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD) for p in parameters)


def _generic_entry(name: str, category: str, module_name: str) -> Entry | None:
    try:
        module = importlib.import_module(module_name)
    except Exception as exc:
        return Entry(name, category, module_name, generic=True, problem=f"cannot import: {type(exc).__name__}: {exc}")
    classes = program_classes(module)
    if not classes:
        main = getattr(module, "main", None)
        if callable(main) and _no_arguments(main):
            return Entry(name, category, module_name, generic=True, demo=True)
        if getattr(module, "__path__", None) is not None:
            return None  # a package of examples, not an example
        return Entry(name, category, module_name, generic=True, problem="no Program and no main() to run")
    try:
        columns = generic_columns(classes[0])
    except Exception as exc:
        return Entry(name, category, module_name, generic=True, problem=f"cannot build: {type(exc).__name__}: {exc}")
    return Entry(name, category, module_name, columns=columns, generic=True)


def _short_names(category: str, modules: Sequence[str]) -> dict[str, str]:
    """Module -> short name: ``factory_method`` -> ``factory-method``; ``iecoop_examples.ch09_x`` -> ``ch09``."""
    base = {m: m.rsplit(".", 1)[-1].replace("_", "-").lower() for m in modules}
    if category == "examples":
        prefixes = {m: re.match(r"(ch\d+)", name) for m, name in base.items()}
        counts: dict[str, int] = {}
        for match in prefixes.values():
            if match:
                counts[match.group(1)] = counts.get(match.group(1), 0) + 1
        for m, match in prefixes.items():
            if match and counts[match.group(1)] == 1:
                base[m] = match.group(1)
    clashes = {n for n in base.values() if list(base.values()).count(n) > 1}
    for m, name in base.items():
        if name in clashes:
            base[m] = m.split(".", 1)[-1].replace(".", "-").replace("_", "-").lower()
    return base


def entries() -> list[Entry]:
    """Every entry, by category: the hand-written ones, then any other module found (examples by chapter)."""
    known = {entry.module for entry in ENTRIES}
    taken = {entry.name for entry in ENTRIES}
    result: list[Entry] = []
    for category, package in _PACKAGES.items():
        group = [entry for entry in ENTRIES if entry.category == category]
        extra = [m for m in _modules(package) if m not in known]
        for module_name, name in _short_names(category, extra).items():
            if name in taken:
                name = f"{category}-{name}"
            entry = _generic_entry(name, category, module_name)
            if entry is not None:
                group.append(entry)
                taken.add(name)
        if category == "examples":
            group.sort(key=lambda entry: entry.module)  # chapter order
        result += group
    return result


def names() -> list[str]:
    """The short names of every entry."""
    return [entry.name for entry in entries()]


def normalise(name: str) -> str:
    """``Factory_Method`` -> ``factory-method``."""
    return name.strip().lower().replace("_", "-")


def find(name: str) -> Entry:
    """The entry called ``name`` (case and ``_`` / ``-`` do not matter); KeyError if there is none."""
    wanted = normalise(name)
    for entry in entries():
        if entry.name == wanted or entry.module == name:
            return entry
    raise KeyError(name)


# ---------------------------------------------------------------------------
# The hand-written entries
# ---------------------------------------------------------------------------


def _hex(value: Any) -> str:
    return f"16#{int(value):04X}"


def _flag(value: Any) -> str:
    return "ON" if value else "-"


# -- Abstract Factory: a simulated tank behind each bus ------------------------------------------


def _tanks(scenario: Scenario, cycle: int) -> None:
    farm = scenario.program
    if cycle == 1:
        scenario.sim.update(a=0.5, b=0.8)
        return  # the factories bind the modules in the first scan
    for key, tank, bus, full_scale in (("a", farm.tank_a, farm.ec_bus, 32767), ("b", farm.tank_b, farm.pn_bus, 27648)):
        level = scenario.sim[key] + (0.1 if tank.pump_on else -0.04)
        scenario.sim[key] = level = min(max(level, 0.0), 4.0)
        address = tank.level_sensor.address
        raw = round(level / 4.0 * full_scale)
        if key == "a":
            bus.inputs[address] = scenario.module.EC_STATUS_ERROR if 71 <= cycle < 81 else 0
            bus.inputs[address + 1] = raw
        else:
            bus.inputs[address] = raw


# -- Prototype: re-measure one point of the shared compensation table ----------------------------


def _remeasure(scenario: Scenario, cycle: int) -> None:
    if cycle == 211:
        scenario.program.master.set_compensation(3, 30.0)


def _load_error(station: int) -> Getter:
    def get(scenario: Scenario) -> object:
        s = scenario.program.stations[station]
        return (s.load_position - s.position) * 1000.0

    return get


# -- Singleton: the plant log is one global instance ---------------------------------------------


def _clear_log(scenario: Scenario) -> None:
    scenario.module.GVL_PlantEvents.plant_events.clear()


def _newest_event(scenario: Scenario) -> object:
    log = scenario.module.GVL_PlantEvents.plant_events
    if not log.held:
        return ""
    event = log.newest(0)
    return f"{event.source} {event.text}"


# -- Adapter: one interface, three drives --------------------------------------------------------


def _drive_state(index: int) -> Getter:
    def get(scenario: Scenario) -> object:
        drive = scenario.program.drives[index]
        return "fault" if drive.fault else "running" if drive.running else "stopped"

    return get


def _drive_speed(index: int) -> Getter:
    return lambda scenario: scenario.program.drives[index].actual_speed


# -- Bridge, Composite, Factory Method: lists of devices -------------------------------------------


def _bridge_faults(scenario: Scenario) -> object:
    skid = scenario.program
    return " ".join(skid.devices[k].tag for k in range(1, 7) if skid.devices[k].fault) or "-"


def _sections_on(scenario: Scenario) -> object:
    prog = scenario.program
    return " ".join(s.name for s in (prog.s1, prog.s2, prog.s3, prog.s4, prog.s5) if s.contactor) or "-"


def _valve_open(row: int) -> Getter:
    def get(scenario: Scenario) -> object:
        valve = scenario.program.factory.valve(row)
        return bool(valve) and valve.is_open

    return get


# -- Decorator: a pulsating pressure, a transmitter error, then simulation -----------------------


def _pressure(scenario: Scenario, cycle: int) -> None:
    prog = scenario.program
    t = (cycle - 1) * 10
    bar = 9.0 if t == 50 else 7.0 if 100 <= t < 200 or t >= 500 else 2.0
    prog.pt101.raw = round(bar / 10.0 * scenario.module.RAW_FULL_SCALE)
    prog.pt101.error = 300 <= t < 400
    if t == 500:
        prog.override.sim_value = 4.5
        prog.override.simulate = True


def _pt101(scenario: Scenario) -> object:
    pt101 = scenario.program.pt101
    return "-.--" if pt101.error else f"{pt101.value:.2f}"


# -- Facade: the HMI buttons and the e-stop ------------------------------------------------------

_FACADE = {1: "start", 211: "estop", 221: "reset", 231: "estop", 241: "reset", 251: "start", 331: "stop"}


def _cell_buttons(scenario: Scenario, cycle: int) -> None:
    hmi = scenario.program
    action = _FACADE.get(cycle, "")
    hmi.estop_ok = hmi.estop_ok != (action == "estop")
    hmi.btn_start = action == "start"
    hmi.btn_stop = action == "stop"
    hmi.btn_reset = action == "reset"


# -- Flyweight: readings arriving over the first cycles ------------------------------------------

_READINGS = {1: (1, 4096, 0.0), 2: (2, 41276, -1.5), 3: (150, 41276, 0.0), 11: (151, 80000, 0.0), 21: (150, 60000, 0.0)}


def _thermocouples(scenario: Scenario, cycle: int) -> None:
    if cycle in _READINGS:
        index, raw_uv, offset = _READINGS[cycle]
        tc = scenario.program.thermocouples[index]
        tc.raw_uv = raw_uv
        tc.offset = offset


# -- Proxy: HMI writes at three access levels, a remote level behind a cache ---------------------


def _oven(scenario: Scenario, cycle: int) -> None:
    prog = scenario.program
    if cycle == 1:
        prog.station.remote_value = prog.direct.remote_value = 2.5
    writes = {2: 185.0, 3: 240.0, 5: 320.0, 7: 325.0}
    if cycle == 4:
        prog.access.login(scenario.module.AccessLevel.ENGINEER)
    if cycle == 6:
        prog.access.logout()
    if cycle in writes:
        prog.hmi_setpoint.write(writes[cycle])
    if cycle == 101:
        prog.station.link_ok = prog.direct.link_ok = False
    if cycle == 301:
        prog.station.link_ok = prog.direct.link_ok = True
        prog.station.remote_value = prog.direct.remote_value = 2.75


# -- Command: the skid's buttons, then four undos ------------------------------------------------

_COMMANDS = [
    *[(c, "panel.buttons[2]", v) for c, v in ((2, True), (5, False))],
    *[(c, "panel.buttons[4]", v) for c, v in ((6, True), (9, False))],
    *[(c, "panel.buttons[1]", v) for c, v in ((10, True), (12, False))],
    *[(c, "panel.undo_button", v) for n in range(4) for c, v in ((13 + 3 * n, True), (15 + 3 * n, False))],
]


def _audit(scenario: Scenario) -> object:
    audit = scenario.program.panel.audit
    if not audit.count:
        return "-"
    line = audit.entry(audit.count)
    return f"{scenario.module.AuditAction(line.action).name} {line.command}"


# -- Interpreter: heat the batch, then change the other inputs -----------------------------------


def _heat(scenario: Scenario, cycle: int) -> None:
    prog = scenario.program
    if cycle <= 70:
        prog.tt101 = 20.0 + cycle
    prog.pt102 = 3.0 if cycle > 70 else 1.0
    prog.bypass = cycle > 80
    prog.ls3 = cycle > 90


# -- Memento: edit, snapshot, restore, commit ----------------------------------------------------


def _recipe(scenario: Scenario, cycle: int) -> None:
    station = scenario.program
    editor = station.editor
    if cycle == 2:
        editor.rename("Base")
        editor.set_dose(120.0)
        editor.set_pump_speed(60.0)
        editor.set_mix_time(T("45s"))
        station.label = "before speed trial"
    if cycle == 5:
        editor.set_pump_speed(95.0)
    station.snapshot_button = cycle == 3
    station.restore_button = cycle == 7
    station.commit_button = cycle == 9


# -- SRP: both designs on one task, the HMI on a slower one --------------------------------------


def _srp(module: ModuleType, runtime: Runtime) -> Sequence[Any]:
    violating, motion, hmi = module.ViolatingCell(), module.MotionMain(), module.HmiMain()
    hmi.drive = motion.drive
    runtime.add_task(plc_task(), motion, violating)
    runtime.add_task(Task("HmiTask", interval=T("100ms"), priority=30), hmi)
    return [motion, violating, hmi]


def _srp_buttons(scenario: Scenario, cycle: int) -> None:
    plan = {1: {"start_button": True}, 31: {"start_button": False, "overload": True},
            36: {"overload": False, "reset_button": True}, 41: {"reset_button": False, "start_button": True}}
    for name, value in plan.get(cycle, {}).items():
        for cell in scenario.programs[:2]:
            setattr(cell, name, value)


# -- DIP and ISP ---------------------------------------------------------------------------------


def _lamp(value: Any) -> str:
    return str(value.name)


def _running(*names: str) -> Getter:
    def get(scenario: Scenario) -> object:
        cell = scenario.program
        return " ".join(getattr(cell, n).tag for n in names if getattr(cell, n).running) or "-"

    return get


def _modes(scenario: Scenario, cycle: int) -> None:
    modes = {2001: "PWM", 3001: "PID", 4001: "ON_OFF"}
    if cycle in modes:
        scenario.program.mode = scenario.module.ControlMode[modes[cycle]]


def _strategy_name(scenario: Scenario) -> object:
    return scenario.program.zone.strategy.name


ENTRIES: tuple[Entry, ...] = (
    # -- creational --------------------------------------------------------------------------
    Entry(
        "abstract-factory", "creational", "patterns.creational.abstract_factory",
        use_when="a library sold with several I/O hardware options, or a simulated family swapped in for commissioning",
        columns=(
            Column("A level m", "tank_a.level", ".2f", watch=False),
            Column("A pump", "tank_a.pump_on", _flag),
            Column("A fault", "tank_a.fault"),
            Column("EC QW0", "ec_bus.outputs[0]", _hex),
            Column("B level m", "tank_b.level", ".2f", watch=False),
            Column("PN QW0", "pn_bus.outputs[0]", _hex),
        ),
        script=_tanks, cycles=120, tour_cycles=90,
    ),
    Entry(
        "builder", "creational", "patterns.creational.builder",
        use_when="motion profiles or recipes assembled at run time from HMI or product data, checked in one place",
        columns=(
            Column("jog build", "jog_result"),
            Column("step", "runner.step"),
            Column("v mm/s", "runner.velocity", ".1f", watch=False),
            Column("x mm", "runner.position", ".1f", watch=False),
            Column("busy", "runner.busy"),
            Column("finished", "runner.finished"),
        ),
        cycles=100, tour_cycles=90,
    ),
    Entry(
        "factory-method", "creational", "patterns.creational.factory_method",
        use_when="the device mix varies per machine (options, retrofits) while the sequence code stays untouched",
        columns=(
            Column("created", "factory.created"),
            Column("error", "factory.error"),
            *(Column(f"V10{row} open", _valve_open(row)) for row in range(1, 5)),
        ),
        cycles=110, tour_cycles=110,
        expected=(("UNKNOWN_TYPE", "row 5 of the I/O table names a BUTTERFLY valve, a type no factory builds"),),
    ),
    Entry(
        "prototype", "creational", "patterns.creational.prototype",
        use_when="new stations start from a tuned parameter block and each needs its own copy, not a shared reference",
        columns=(
            Column("x1 mm", "stations[1].position", ".1f", watch=False),
            Column("in pos", lambda s: "".join("T" if st.in_position else "-" for st in s.program.stations)),
            Column("table[3] um", "screw_table.error_um[3]", ".0f"),
            *(Column(f"err{i} um", _load_error(i), "+.1f", watch=False) for i in range(1, 4)),
        ),
        script=_remeasure, cycles=220, tour_cycles=220,
    ),
    Entry(
        "singleton", "creational", "patterns.creational.singleton",
        use_when="something that is one by physics (the controller's clock, its diagnostic buffer); otherwise inject it",
        columns=(
            Column("CV101", "cv101.motor_on", _flag),
            Column("CV102", "cv102.motor_on", _flag),
            Column("P101", "p101.motor_on", _flag),
            Column("logged", lambda s: s.module.GVL_PlantEvents.plant_events.count),
            Column("newest event", _newest_event),
        ),
        setup=_clear_log,
        script=steps((1, "cmd_run", True), (6, "overload_cv102", True), (9, "dry_run_p101", True), (13, "cmd_run", False)),
        cycles=20, tour_cycles=20,
    ),
    # -- structural --------------------------------------------------------------------------
    Entry(
        "adapter", "structural", "patterns.structural.adapter",
        use_when="devices of different makes must look alike to the line without hiding what matters about them",
        columns=(
            Column("VFD", _drive_state(1)), Column("rpm", _drive_speed(1), ".0f", watch=False),
            Column("AXIS", _drive_state(2)), Column("rpm ", _drive_speed(2), ".0f", watch=False),
            Column("DOL", _drive_state(3)), Column(" rpm", _drive_speed(3), ".0f", watch=False),
        ),
        script=steps(*press("cmd_start", 1), *press("vfd_sim.trip", 51), *press("cmd_stop", 61), *press("cmd_reset", 71)),
        cycles=100, tour_cycles=100,
        expected=(("VFD fault", "the Modbus drive trips in cycle 51 and is reset in cycle 71"),),
    ),
    Entry(
        "bridge", "structural", "patterns.structural.bridge",
        use_when="devices and their channels (local I/O, fieldbus, simulation) really vary independently",
        columns=(
            Column("P-LOC", "p_loc.at_speed"),
            Column("P-MB", "p_mb.at_speed"),
            Column("P-SIM", "p_sim.at_speed"),
            Column("V-MB open", "v_mb.is_open"),
            Column("Modbus link", "modbus.link_up"),
            Column("faulted", _bridge_faults),
        ),
        script=steps((1, "cmd_run", True), (41, "modbus.link_up", False)),
        cycles=60, tour_cycles=60,
        expected=(("faulted P-MB V-MB", "the Modbus TCP link drops in cycle 41"),),
    ),
    Entry(
        "composite", "structural", "patterns.structural.composite",
        use_when="a line of zones of sections is commanded and queried through one interface, wired once at start-up",
        columns=(
            Column("running", "running"),
            Column("faulted", "faulted"),
            Column("kW", "power_kw", ".2f"),
            Column("contactors on", _sections_on),
        ),
        script=steps(
            *press("cmd_start", 1), (62, "s4.motor_trip", True), *press("cmd_reset", 82, hold=20),
            (102, "s4.motor_trip", False), *press("cmd_reset", 103), *press("cmd_start", 122),
        ),
        cycles=190, tour_cycles=190,
        expected=(("faulted", "the motor of section S4 trips in cycle 62"),),
    ),
    Entry(
        "decorator", "structural", "patterns.structural.decorator",
        use_when="signal treatments (filtering, simulation, counting) are stacked per channel at configuration",
        columns=(
            Column("PT101 bar", _pt101),
            Column("logic bar", "pressure", ".2f", watch=False),
            Column("ok", "pressure_ok"),
            Column("simulate", "override.simulate"),
            Column("switchings", "counter.switchings"),
        ),
        script=_pressure, cycles=70, tour_cycles=70,
    ),
    Entry(
        "facade", "structural", "patterns.structural.facade",
        use_when="an HMI or a line controller needs a few buttons, not the detail of every subsystem of a cell",
        columns=(
            Column("state", "cell.state"),
            Column("message", "cell.message"),
            Column("pallets", "cell.pallets_done"),
            Column("cases", "cell.robot.placed", watch=False),
        ),
        script=_cell_buttons, cycles=380, tour_cycles=250,
        expected=(("TRIPPED, reset refused", "the e-stop is pressed in cycle 211, a reset tried while it is still pressed"),),
    ),
    Entry(
        "flyweight", "structural", "patterns.structural.flyweight",
        use_when="hundreds of instances share large, immutable data such as a calibration table per sensor type",
        columns=(
            Column("TC2 degC", "thermocouples[2].temperature", ".1f"),
            Column("TC150 degC", "thermocouples[150].temperature", ".1f"),
            Column("hottest degC", "hottest", ".1f"),
            Column("at TC", "hottest_at"),
            Column("out of range", "out_of_range"),
        ),
        script=_thermocouples, cycles=30, tour_cycles=25,
    ),
    Entry(
        "proxy", "structural", "patterns.structural.proxy",
        use_when="access to a block is guarded by access level, or a slow remote value is cached with its quality",
        columns=(
            Column("access", "access.level"),
            Column("setpoint", "hmi_setpoint.setpoint", ".1f"),
            Column("refused", "access.refused"),
            Column("level", lambda s: f"{s.program.level_m:.2f} m {s.program.level_quality.name}"),
            Column("bus requests: cached", "station.requests", watch=False),
            Column("direct", "direct.requests", watch=False),
        ),
        script=_oven, cycles=400, tour_cycles=400,
        expected=(
            ("refused", "an OPERATOR writes setpoints above the operator limit in cycles 3 and 7"),
            ("STALE", "the remote I/O link is lost from cycle 101"),
        ),
    ),
    # -- behavioral --------------------------------------------------------------------------
    Entry(
        "chain-of-responsibility", "behavioral", "patterns.behavioral.chain_of_responsibility",
        use_when="stages (signal conditioning, permissives) are chosen per channel or added without editing the base",
        columns=(
            Column("mA", "pt205.signal.raw_ma", ".2f", watch=False),
            Column("bar", "pt205.signal.value", ".2f", watch=False),
            Column("quality", "pt205.signal.quality"),
            Column("status", "pt205.signal.status"),
            Column("high", "pt205.signal.high_alarm"),
            Column("blocked by", lambda s: s.program.blocked_by or "- (start permitted)"),
        ),
        script=steps((76, "door_closed", False), (81, "estop_released", False), (86, "door_closed", True),
                     (91, "estop_released", True)),
        cycles=100, tour_cycles=100,
        expected=(
            ("SPIKE_HELD, WIRE_BREAK", "the simulated transmitter sends a spike and a broken-wire current"),
            ("blocked by", "the guard door opens in cycle 76 and the e-stop is pressed in cycle 81"),
        ),
    ),
    Entry(
        "command", "behavioral", "patterns.behavioral.command",
        use_when="HMI actions must be logged, queued, combined into macros or undone",
        columns=(
            Column("XV101", "inlet.is_open"),
            Column("P201 %", "pump.speed", ".0f"),
            Column("M301", "mixer.running"),
            Column("history", "panel.history.count"),
            Column("audit", _audit),
        ),
        script=steps(*_COMMANDS), cycles=26, tour_cycles=26,
        expected=(("REFUSED undo: history empty", "Undo is pressed once more than there are commands to undo"),),
    ),
    Entry(
        "interpreter", "behavioral", "patterns.behavioral.interpreter",
        use_when="conditions arrive with the recipe at download time rather than at design time",
        columns=(
            Column("TT101", "tt101", ".1f", watch=False),
            Column("LS3", "ls3"),
            Column("PT102", "pt102", ".1f"),
            Column("BYPASS", "bypass"),
            Column("pump", "pump_on", _flag),
            Column("starts", "pump_starts"),
        ),
        script=_heat, cycles=100, tour_cycles=100,
    ),
    Entry(
        "iterator", "behavioral", "patterns.behavioral.iterator",
        use_when="a client walks a storage (a ring buffer, a filtered view) without seeing how it is kept",
        columns=(
            Column("raised", "history.total", watch=False),
            Column("kept", "history.count", watch=False),
            Column("page", "all_pager.page"),
            Column("rows", "all_pager.row_count"),
            Column("more", "all_pager.more"),
            Column("top row", lambda s: s.program.all_pager.rows[1].text if s.program.all_pager.row_count else "-"),
        ),
        script=steps((1, "simulate", True), (11, "simulate", False), *press("all_pager.first_page", 12),
                     *press("all_pager.next_page", 14), *press("all_pager.first_page", 16)),
        cycles=18, tour_cycles=18,
    ),
    Entry(
        "mediator", "behavioral", "patterns.behavioral.mediator",
        use_when="the stations of a cell must coordinate without knowing each other",
        columns=(
            Column("arrived", "infeed.arrived"),
            Column("filling", "filler.valve_open", watch=False),
            Column("divert", "gate.divert", watch=False),
            Column("good", "cell.good_count"),
            Column("rejected", "cell.reject_count"),
        ),
        cycles=200, tour_cycles=200,
    ),
    Entry(
        "memento", "behavioral", "patterns.behavioral.memento",
        use_when="an operator edits a data set and must be able to return to a snapshot or the last good one",
        columns=(
            Column("recipe", "editor.working.name", repr),
            Column("dose l", "editor.working.dose_litres", ".0f"),
            Column("pump %", "editor.working.pump_speed", ".0f"),
            Column("snapshots", "snapshots.used"),
            Column("message", "message"),
        ),
        script=_recipe, cycles=12, tour_cycles=12,
    ),
    Entry(
        "observer", "behavioral", "patterns.behavioral.observer",
        use_when="consumers of a value come and go at run time and the producer must stay closed to edits",
        columns=(
            Column("TT101 C", "tt101.value", ".1f", watch=False),
            Column("quality", "tt101.quality"),
            Column("observers", "tt101.observer_count"),
            Column("alarm", "high_alarm.active"),
            Column("sensor fault", "high_alarm.sensor_fault"),
            Column("log", "logger.total", watch=False),
        ),
        cycles=100, tour_cycles=100,
    ),
    Entry(
        "state", "behavioral", "patterns.behavioral.state",
        use_when="states have behaviour of their own (entry actions, timing, commands) reviewed against a diagram, as in PackML",
        columns=(
            Column("state", "unit.state"),
            Column("packs", "unit.execute.packs"),
            Column("transitions", "unit.transitions"),
            Column("refused", "unit.refused"),
            Column("batches", "batches"),
        ),
        cycles=250, tour_cycles=250,
        expected=(("refused", "Start is pressed again while the unit is already in EXECUTE"),),
    ),
    Entry(
        "strategy", "behavioral", "patterns.behavioral.strategy",
        use_when="an algorithm (PID, PWM, on/off) is swapped at run time behind one interface, without a bump",
        columns=(
            Column("mode", "mode"),
            Column("strategy", _strategy_name),
            Column("T degC", "process.temperature", ".1f", watch=False),
            Column("output %", "zone.output", ".1f", watch=False),
            Column("swaps", "zone.swaps"),
        ),
        script=_modes,
        cycles=5000, tour_cycles=5000,
    ),
    Entry(
        "template-method", "behavioral", "patterns.behavioral.template_method",
        use_when="axis variants share one fixed homing sequence and differ only in its steps",
        columns=(
            Column("X switch", "x_homing.step"),
            Column("Y index", "y_homing.step"),
            Column("Z absolute", "z_homing.step"),
            Column("W switch", "w_homing.step"),
            Column("all done", "all_done"),
        ),
        cycles=150, tour_cycles=150,
    ),
    Entry(
        "visitor", "behavioral", "patterns.behavioral.visitor",
        use_when="new reports or exports over a fixed set of device kinds are added often",
        columns=(
            Column("exports", "exports"),
            Column("report rows", "report.count"),
            Column("faults", "report.faults"),
            Column("warnings", "report.warnings"),
            Column("energy Wh", "energy.total_wh", ".1f"),
        ),
        script=steps(
            (1, "motor1.run", True), (1, "motor2.run", True), (1, "tt101.raw_ma", 12.0), (1, "lt201.raw_ma", 2.1),
            *press("export", 50), (101, "motor3.run", True), (101, "valve2.stuck", True),
            (101, "valve1.open_cmd", True), (101, "valve2.open_cmd", True), *press("export", 150),
            (251, "motor1.overload", True), *press("export", 300), *press("export", 400),
        ),
        cycles=400, tour_cycles=400,
        expected=(("faults, warnings", "a valve sticks in cycle 101 and a motor overloads in cycle 251"),),
    ),
    # -- SOLID -------------------------------------------------------------------------------
    Entry(
        "srp", "solid", "patterns.solid.srp",
        use_when="a block starts mixing control, HMI text and logging: split it so that each part changes for one reason",
        columns=(
            Column("drive", "drive.state"),
            Column("speed %", "drive.speed_ref", ".1f", watch=False),
            Column("events", "log.event_total"),
            Column("texts: violating", lambda s: s.programs[1].drive.format_count, watch=False),
            Column("compliant", lambda s: s.programs[2].formatter.format_count, watch=False),
            Column("HMI text", lambda s: s.programs[2].formatter.status_text, watch=False),
        ),
        builder=_srp, script=_srp_buttons, cycles=100, tour_cycles=100,
    ),
    Entry(
        "ocp", "solid", "patterns.solid.ocp",
        use_when="new device types must join without editing a CASE in code that is already commissioned",
        columns=(
            *(Column(f"CASE {k}", f"by_case[{i}].position", ".0f") for i, k in ((1, "sol"), (2, "mot"), (3, "prop"))),
            Column("CASE errors", lambda s: " ".join(_hex(s.program.by_case[i].error_id) for i in range(1, 4)
                                                     if s.program.by_case[i].error) or "-"),
            Column("manifold all open", "manifold.all_open"),
        ),
        script=steps((1, "cmd_open", True)), cycles=40, tour_cycles=40,
    ),
    Entry(
        "lsp", "solid", "patterns.solid.lsp",
        use_when="a derived block must work wherever its base does: never extend a base whose promises it cannot keep",
        columns=(
            Column("actuator %", "actuator.value", ".1f", watch=False),
            Column("sensor-as-actuator %", "sensor_on_base.value", ".1f"),
            Column("timed out", "ramp_sensor.timed_out"),
            Column("refused", "sensor_on_base.refused", watch=False),
            Column("output %", "output.value", ".1f", watch=False),
            Column("done", "output_ramp.done"),
        ),
        cycles=250, tour_cycles=250,
    ),
    Entry(
        "isp", "solid", "patterns.solid.isp",
        use_when="clients need only part of a device's abilities: give them small interfaces, not one large one",
        columns=(
            Column("fat: running", _running("fat_pump", "fat_transmitter", "fat_fan")),
            Column("failed slot", "fat_sequencer.failed_slot"),
            Column("healthy", "fat_scanner.healthy"),
            Column("small: running", _running("pump", "fan")),
            Column("healthy ", "scanner.healthy"),
            Column("fault code", "scanner.first_fault_code", _hex),
        ),
        script=steps((1, "start_request", True), (1, "fat_transmitter.raw_in", 32767), (1, "transmitter.raw_in", 32767)),
        cycles=200, tour_cycles=200,
    ),
    Entry(
        "dip", "solid", "patterns.solid.dip",
        use_when="a controller is to be tested or reused with other devices: it depends on interfaces given at FB_init",
        columns=(
            Column("fixed: contactor", "fixed.drive.q_contactor", _flag),
            Column("lamp", "fixed.lamp.mode", _lamp),
            Column("injected: contactor", "drive.q_contactor", _flag),
            Column("lamp ", "lamp.mode", _lamp),
            Column("jam", "jam"),
        ),
        script=steps((1, "start_request", True), (1, "contactor_feedback", True), (2, "start_request", False),
                     (21, "jam", True), (22, "contactor_feedback", False), (81, "jam", False)),
        cycles=90, tour_cycles=90,
    ),
    # -- the course examples ---------------------------------------------------------------
    Entry(
        "ch01", "examples", "iecoop_examples.ch01_classes_and_objects",
        columns=(Column("fbMercedes", "mercedes.action"), Column("fbBMW", "bmw.action"),
                 Column("fbAudi", "audi.action"), Column("sColor", "color")),
        script=steps(*press("accelerate", 2), *press("drive", 4), *press("brake", 6)), cycles=8,
    ),
    Entry(
        "ch02", "examples", "iecoop_examples.ch02_fb_declaration_and_access",
        columns=(Column("start", "start"), Column("stop", "stop"), Column("running", "pump.running"),
                 Column("MAIN's starts", "pump_starts")),
        script=steps(*press("start", 2), *press("stop", 5), *press("start", 8)), cycles=10,
    ),
    Entry("ch03", "examples", "iecoop_examples.ch03_method_return_types", demo=True),
    Entry(
        "ch04", "examples", "iecoop_examples.ch04_properties",
        columns=(Column("Setpoint %", "tank.setpoint", ".1f"), Column("Level %", "tank.level", ".1f"),
                 Column("Volume l", "tank.volume", ".1f")),
        cycles=50,
    ),
    Entry(
        "ch05", "examples", "iecoop_examples.ch05_inheritance",
        columns=(Column("FB_Engine running", "engine.running"), Column("odometer", "engine.odometer", ".1f"),
                 Column("FB_NewEngine running", "new_engine.running"), Column("odometer ", "new_engine.odometer", ".1f"),
                 Column("gear", "new_engine.gear")),
        cycles=10,
    ),
    Entry("ch06", "examples", "iecoop_examples.ch06_struct_and_interface_extends", demo=True),
    Entry(
        "ch07", "examples", "iecoop_examples.ch07_this_and_super",
        columns=(Column("iBaseCnt", "i_base_cnt"), Column("iFb1Cnt", "i_fb1_cnt"), Column("fb1.iThis", "fb1.i_this"),
                 Column("fb1.iBase", "fb1.i_base")),
        cycles=5,
    ),
    Entry(
        "ch08", "examples", "iecoop_examples.ch08_interfaces",
        columns=(Column("nRunning", "running"), Column("motor", "motor.running"), Column("valve", "valve.running"),
                 Column("lamp", "lamp.running"), Column("motor cycles", "motor.run_cycles", watch=False)),
        script=steps(*press("start_all", 1), *press("stop_all", 51)), cycles=60,
    ),
    Entry(
        "ch09", "examples", "iecoop_examples.ch09_pointers_and_references", program="SrAverage",
        columns=(Column("avg by value", "avg_values", ".4f"), Column("by reference", "avg_reference", ".4f")),
        cycles=3,
    ),
    Entry(
        "ch10", "examples", "iecoop_examples.ch10_abstract",
        columns=(Column("raw", "raw"), Column("degC", "temperature.value", ".2f"), Column("bar", "pressure.value", ".2f"),
                 Column("nAlarms", "alarms")),
        cycles=20,
    ),
    Entry("ch11", "examples", "iecoop_examples.ch11_abstract_fb_vs_interface", demo=True),
    Entry(
        "ch12", "examples", "iecoop_examples.ch12_fluent_interface",
        columns=(Column("MAIN.cycle", "cycle"), Column("fResult", "result", ".1f"), Column("fHalf", "half", ".1f"),
                 Column("bError", "error")),
        cycles=5,
    ),
    Entry(
        "ch13", "examples", "iecoop_examples.ch13_interface_vs_inheritance",
        columns=(Column("nOn", "count_on"), Column("brightness %", "dimmer.brightness"), Column("fan rpm", "fan.rpm"),
                 Column("valve open", "valve.open"), Column("nSwitchings", "switchings")),
        script=steps((1, "all_on", True), (2, "all_on", False), (2, "dim", 30), (3, "all_off", True),
                     (4, "all_off", False), (4, "all_on", True), (5, "all_on", False)),
        cycles=6,
    ),
    Entry(
        "ch14", "examples", "iecoop_examples.ch14_operators", program="MainOperators",
        columns=(Column("instances before", "before"), Column("after __NEW", "after_new"),
                 Column("after __DELETE", "after_delete"), Column("p = 0", "deleted_is_null"),
                 Column("__ISVALIDREF", "valid_before")),
        cycles=3,
    ),
    Entry(
        "ch15", "examples", "iecoop_examples.ch15_exst",
        columns=(Column("running", "motor.running"), Column("follow", "motor.follow"), Column("alarm", "motor.alarm")),
        script=steps(*press("start", 2), *press("fault", 5), *press("ack", 8), *press("start", 10), *press("stop", 13)),
        cycles=16,
    ),
)
