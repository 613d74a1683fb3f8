"""Proxy: setpoint writes through an access-level guard, and remote I/O read through a cache.

Intent
------

Provide a surrogate or placeholder for another object to control access to
it.

The PLC problem
---------------

Two everyday cases on a curing oven line.

*Protection proxy.* The HMI writes the oven zone's temperature setpoint.
An operator may nudge it within the product's window, maintenance may
move it further, the process engineer may use the oven's whole range, and
a login above operator falls back after some idle minutes. Putting those
checks into the setpoint FB ties plant logic to the HMI's user model; doing
them in the HMI lets any other client (a recipe, a SCADA write) bypass
them. The access proxy implements the same ``ISetpoint`` interface as the
setpoint itself, checks each write against a CONSTANT table of limits per
``AccessLevel``, forwards the accepted ones and counts and reports the
refused ones.

*Remote proxy with a cache.* The tank level comes from a remote I/O
station over Modbus TCP. Each read is a transaction that takes several
cycles and can time out. Logic that asks the station directly floods the
network with a request per answer and waits for each one. The caching
proxy implements the same ``IAnalogInput`` interface, answers every read at
once from its cache, refreshes the cache in the background at a poll
interval, and flags the value STALE when its watchdog TON sees no good
answer for too long, so the logic can tell an old value from a fresh one.

Roles
-----

- Subject → ``ISetpoint`` (``I_Setpoint``) and ``IAnalogInput`` (``I_AnalogInput``)
- Real subjects → ``OvenSetpoint`` (``FB_OvenSetpoint``) and
  ``RemoteAnalogInput`` (``FB_RemoteAnalogInput``)
- Protection proxy → ``SetpointAccessProxy`` (``FB_SetpointAccessProxy``)
- Remote / caching proxy → ``CachedAnalogInput`` (``FB_CachedAnalogInput``)
- Client → ``OvenMain`` (``PRG_OvenMain``)

IEC 61131-3 mapping
-------------------

::

    TYPE E_AccessLevel : (OPERATOR := 1, MAINTENANCE := 2, ENGINEER := 3) INT; END_TYPE
    TYPE E_Quality : (GOOD, STALE, BAD, NO_DATA) INT; END_TYPE

    INTERFACE I_Setpoint
        METHOD Write : BOOL  VAR_INPUT fValue : LREAL; END_VAR
        PROPERTY Setpoint : LREAL

    FUNCTION_BLOCK FB_SetpointAccessProxy IMPLEMENTS I_Setpoint
        VAR CONSTANT aLimits : ARRAY[E_AccessLevel.OPERATOR..E_AccessLevel.ENGINEER]
            OF ST_SetpointLimits := [...]; END_VAR
        VAR iSubject : I_Setpoint; eLevel : E_AccessLevel; fbIdle : TON; END_VAR
        VAR_OUTPUT nRefused : UDINT; eLastRefusal : E_Refusal; sMessage : STRING(80); END_VAR
        METHOD Login  VAR_INPUT eLevel : E_AccessLevel; END_VAR

    INTERFACE I_AnalogInput
        METHOD Read : BOOL
        PROPERTY Value : LREAL; PROPERTY Quality : E_Quality

    FUNCTION_BLOCK FB_CachedAnalogInput IMPLEMENTS I_AnalogInput
        VAR_INPUT tPoll : TIME := T#500MS; tStaleAfter : TIME := T#2S; END_VAR
        VAR iStation : I_AnalogInput; fCache : LREAL; fbPoll, fbWatchdog : TON; END_VAR

When not to use it on a PLC
---------------------------

An access proxy is no safety function: a setpoint whose wrong value can
hurt someone needs limits in the controlled FB itself (or a safety PLC),
whatever the client. A cache is wrong for values the logic must see the
instant they change (an end switch, a trip): read those every cycle
through the process image, and never let a STALE value drive an actuator
without checking its quality.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994, "Proxy".
- IEC 61131-3:2013, 3rd ed., 6.6.5 (interfaces), 6.4.4 (enumerated types), 6.5.2 (CONSTANT).
- Beckhoff InfoSys, TwinCAT 3 PLC: "Interface", "Property", "TON", "Remanent variables - PERSISTENT, RETAIN";
  TF6250 TwinCAT 3 Modbus TCP: "FB_MBReadRegs".
- CODESYS Online Help: "Object: Interface", "Data Type: Enumeration", "User Management" (HMI access levels).
- IEC 62443-3-3: System security requirements and security levels (role-based use control).
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    LREAL,
    STRING,
    TIME,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    PRIVATE,
    FunctionBlock,
    IecEnum,
    Interface,
    Program,
    Struct,
    T,
    call_after_init,
    method,
    prop,
)
from iecoop.conversions import DINT_TO_LREAL, LREAL_TO_DINT, LREAL_TO_STRING
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.showcase.entry import Column, Scenario, Showcase

__all__ = [
    "AccessLevel",
    "CachedAnalogInput",
    "IAnalogInput",
    "ISetpoint",
    "OvenMain",
    "OvenSetpoint",
    "Quality",
    "Refusal",
    "RemoteAnalogInput",
    "SetpointAccessProxy",
    "SetpointLimits",
    "main",
]


# ---------------------------------------------------------------------------
# Protection proxy: setpoint writes by access level
# ---------------------------------------------------------------------------


def tenths(value: LREAL) -> STRING:
    """``FUNCTION F_Tenths : STRING``: ``value`` to one decimal, as the HMI shows it ('72.5', '80.0').

    ST has no format specifier: round to tenths as a DINT, back to LREAL, and let
    LREAL_TO_STRING write the fewest digits that read back ('72.5', not '72.500000').
    """
    return LREAL_TO_STRING(DINT_TO_LREAL(LREAL_TO_DINT(value * 10.0)) / 10.0)


class AccessLevel(IecEnum):
    """``TYPE E_AccessLevel : (OPERATOR := 1, MAINTENANCE := 2, ENGINEER := 3) INT;``"""

    OPERATOR = 1
    MAINTENANCE = 2
    ENGINEER = 3


class Refusal(IecEnum):
    """``TYPE E_Refusal``: why the last write was refused."""

    NONE = 0
    BELOW_LIMIT = 1
    ABOVE_LIMIT = 2
    STEP_TOO_LARGE = 3
    SUBJECT_REFUSED = 4


class SetpointLimits(Struct):
    """``STRUCT ST_SetpointLimits``: the window and the largest single change for one access level."""

    low: LREAL = 0.0
    high: LREAL = 0.0
    max_step: LREAL = 0.0


class ISetpoint(Interface):
    """``INTERFACE I_Setpoint``."""

    @method
    def write(self, value: LREAL) -> BOOL:
        raise NotImplementedError

    @prop
    def setpoint(self) -> LREAL:
        raise NotImplementedError


class OvenSetpoint(FunctionBlock, ISetpoint, final=True):
    """``FUNCTION_BLOCK FINAL FB_OvenSetpoint IMPLEMENTS I_Setpoint``: the zone setpoint, PERSISTENT.

    It refuses only what the oven physically cannot do (outside
    ``PLANT_MIN`` .. ``PLANT_MAX``); who may write what is not its business.
    """

    PLANT_MIN: LREAL = VAR(0.0, constant=True)
    PLANT_MAX: LREAL = VAR(400.0, constant=True)
    value: LREAL = VAR(180.0, persistent=True)
    writes: UDINT = VAR_OUTPUT(0)

    @method
    def write(self, value: LREAL) -> BOOL:
        if not self.PLANT_MIN <= value <= self.PLANT_MAX:
            return False
        self.value = value
        self.writes += 1
        return True

    @prop
    def setpoint(self) -> LREAL:
        return self.value


class SetpointAccessProxy(FunctionBlock, ISetpoint):
    """``FUNCTION_BLOCK FB_SetpointAccessProxy IMPLEMENTS I_Setpoint``: checks each write against the level.

    The subject is injected at FB_init (``SetpointAccessProxy(subject=sp)``)
    or through the ``subject`` property. Call the FB every cycle: after
    ``logout_after`` without a write, a higher level falls back to OPERATOR.
    """

    LEVEL_LIMITS: ARRAY[SetpointLimits] = VAR(
        [
            {"low": 150.0, "high": 250.0, "max_step": 10.0},
            {"low": 100.0, "high": 300.0, "max_step": 50.0},
            {"low": 0.0, "high": 400.0, "max_step": 400.0},
        ],
        bounds=(AccessLevel.OPERATOR, AccessLevel.ENGINEER),
        constant=True,
    )
    logout_after: TIME = VAR_INPUT(T("5m"))
    subject_ref: ISetpoint = VAR()
    user_level: AccessLevel = VAR(AccessLevel.OPERATOR)
    idle: TON = VAR()
    refused: UDINT = VAR_OUTPUT(0)
    last_refusal: Refusal = VAR_OUTPUT(Refusal.NONE)
    message: STRING = VAR_OUTPUT("", length=80)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, subject: ISetpoint | None = None) -> None:
        if subject is not None:
            self.subject_ref = subject

    def body(self) -> None:
        self.idle(IN=self.user_level != AccessLevel.OPERATOR, PT=self.logout_after)
        if self.idle.Q:
            self.logout()

    @prop
    def subject(self) -> ISetpoint:
        return self.subject_ref

    @subject.setter
    def subject(self, subject: ISetpoint) -> None:
        self.subject_ref = subject

    @prop
    def level(self) -> AccessLevel:
        return self.user_level

    @method
    def login(self, level: AccessLevel) -> None:
        """The HMI has checked the user; from now on writes are judged at ``level``."""
        self.user_level = level
        self.idle(IN=False)

    @method
    def logout(self) -> None:
        self.user_level = AccessLevel.OPERATOR
        self.idle(IN=False)

    @prop
    def limits(self) -> SetpointLimits:
        """The row of ``LEVEL_LIMITS`` for the current level."""
        return self.LEVEL_LIMITS[self.user_level]

    @method
    def write(self, value: LREAL) -> BOOL:
        # ST names are case-blind: the row is not called like the property Limits.
        allowed = self.LEVEL_LIMITS[self.user_level]
        if value < allowed.low:
            return self.refuse(Refusal.BELOW_LIMIT, value, f"below {tenths(allowed.low)}")
        if value > allowed.high:
            return self.refuse(Refusal.ABOVE_LIMIT, value, f"above {tenths(allowed.high)}")
        if abs(value - self.subject_ref.setpoint) > allowed.max_step:
            return self.refuse(Refusal.STEP_TOO_LARGE, value, f"step over {tenths(allowed.max_step)}")
        if not self.subject_ref.write(value):
            return self.refuse(Refusal.SUBJECT_REFUSED, value, "refused by the oven")
        self.idle(IN=False)
        self.last_refusal = Refusal.NONE
        return True

    @method(PRIVATE)
    def refuse(self, reason: Refusal, value: LREAL, why: STRING) -> BOOL:
        self.refused += 1
        self.last_refusal = reason
        self.message = f"{self.user_level.name} write {tenths(value)} refused: {why}"
        return False

    @prop
    def setpoint(self) -> LREAL:
        return self.subject_ref.setpoint


# ---------------------------------------------------------------------------
# Remote proxy: a cached remote analog input with a watchdog
# ---------------------------------------------------------------------------


class Quality(IecEnum):
    """``TYPE E_Quality : (GOOD, STALE, BAD, NO_DATA) INT;``"""

    GOOD = 0
    STALE = 1
    BAD = 2
    NO_DATA = 3


class IAnalogInput(Interface):
    """``INTERFACE I_AnalogInput``: ``read()`` is TRUE when ``value`` and ``quality`` hold an answer."""

    @method
    def read(self) -> BOOL:
        raise NotImplementedError

    @prop
    def value(self) -> LREAL:
        raise NotImplementedError

    @prop
    def quality(self) -> Quality:
        raise NotImplementedError


class RemoteAnalogInput(FunctionBlock, IAnalogInput, final=True):
    """``FUNCTION_BLOCK FINAL FB_RemoteAnalogInput IMPLEMENTS I_AnalogInput``: a value on a remote station.

    Each read is a bus transaction: it answers after ``response_time`` while
    the link is up (GOOD), or after ``timeout`` when it is down (BAD).
    ``remote_value`` and ``link_ok`` stand for the station and the network.
    """

    remote_value: LREAL = VAR_INPUT(0.0)
    link_ok: BOOL = VAR_INPUT(True)
    response_time: TIME = VAR_INPUT(T("40ms"))
    timeout: TIME = VAR_INPUT(T("200ms"))
    requests: UDINT = VAR_OUTPUT(0)
    busy: BOOL = VAR_OUTPUT(False)
    received: LREAL = VAR(0.0)
    signal: Quality = VAR(Quality.NO_DATA)
    answer: TON = VAR()
    no_answer: TON = VAR()

    @method
    def read(self) -> BOOL:
        if not self.busy:
            self.busy = True
            self.requests += 1
            self.answer(IN=False)
            self.no_answer(IN=False)
        self.answer(IN=True, PT=self.response_time)
        self.no_answer(IN=True, PT=self.timeout)
        if self.link_ok and self.answer.Q:
            self.received = self.remote_value
            self.signal = Quality.GOOD
        elif self.no_answer.Q:
            self.signal = Quality.BAD
        else:
            return False
        self.busy = False
        return True

    @prop
    def value(self) -> LREAL:
        return self.received

    @prop
    def quality(self) -> Quality:
        return self.signal


class CachedAnalogInput(FunctionBlock, IAnalogInput):
    """``FUNCTION_BLOCK FB_CachedAnalogInput IMPLEMENTS I_AnalogInput``: answers at once from its cache.

    Call the FB every cycle: it polls the station every ``poll_interval``
    (at once while it has no data) and its watchdog flags the value STALE
    when no GOOD answer came for ``stale_after``. The last good value is kept.
    """

    poll_interval: TIME = VAR_INPUT(T("500ms"))
    stale_after: TIME = VAR_INPUT(T("2s"))
    station_ref: IAnalogInput = VAR()
    cache: LREAL = VAR(0.0)
    has_data: BOOL = VAR(False)
    in_flight: BOOL = VAR(False)
    poll: TON = VAR()
    watchdog: TON = VAR()
    refreshes: UDINT = VAR_OUTPUT(0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, station: IAnalogInput | None = None) -> None:
        if station is not None:
            self.station_ref = station

    @prop
    def station(self) -> IAnalogInput:
        return self.station_ref

    @station.setter
    def station(self, station: IAnalogInput) -> None:
        self.station_ref = station

    def body(self) -> None:
        if not self.in_flight:
            self.poll(IN=self.has_data, PT=self.poll_interval)
            if self.poll.Q or not self.has_data:
                self.in_flight = True
                self.poll(IN=False)
        if self.in_flight and self.station_ref.read():
            self.in_flight = False
            if self.station_ref.quality == Quality.GOOD:
                self.cache = self.station_ref.value
                self.has_data = True
                self.refreshes += 1
                self.watchdog(IN=False)
        self.watchdog(IN=self.has_data, PT=self.stale_after)

    @method
    def read(self) -> BOOL:
        return True

    @prop
    def value(self) -> LREAL:
        return self.cache

    @prop
    def quality(self) -> Quality:
        if not self.has_data:
            return Quality.NO_DATA
        return Quality.STALE if self.watchdog.Q else Quality.GOOD


# ---------------------------------------------------------------------------
# The client
# ---------------------------------------------------------------------------


class OvenMain(Program):
    """``PROGRAM PRG_OvenMain``: the HMI writes through ``hmi_setpoint``; the logic reads ``tank_level``.

    ``direct`` is a second station read without the proxy, for comparing the bus load.
    """

    oven_setpoint: OvenSetpoint = VAR()
    access: SetpointAccessProxy = VAR()
    station: RemoteAnalogInput = VAR()
    cached_level: CachedAnalogInput = VAR()
    direct: RemoteAnalogInput = VAR()
    hmi_setpoint: ISetpoint = VAR()
    tank_level: IAnalogInput = VAR()
    level_m: LREAL = VAR_OUTPUT(0.0)
    level_quality: Quality = VAR_OUTPUT(Quality.NO_DATA)
    direct_level_m: LREAL = VAR_OUTPUT(0.0)

    @call_after_init
    def wire(self) -> None:
        self.access.subject = self.oven_setpoint
        self.cached_level.station = self.station
        self.hmi_setpoint = self.access
        self.tank_level = self.cached_level

    def body(self) -> None:
        self.access()
        self.cached_level()
        if self.tank_level.read():
            self.level_m = self.tank_level.value
            self.level_quality = self.tank_level.quality
        if self.direct.read():
            self.direct_level_m = self.direct.value


def main() -> None:
    """Write setpoints at three access levels, then read a remote level through the cache.

    >>> main()
    OPERATOR write 185.0 accepted: setpoint 185.0
    OPERATOR write 240.0 refused: step over 10.0 (STEP_TOO_LARGE)
    ENGINEER write 320.0 accepted: setpoint 320.0
    idle 5 min: level back to OPERATOR
    OPERATOR write 325.0 refused: above 250.0 (ABOVE_LIMIT)
    refused writes: 2
    t= 1000 ms  level 2.50 m GOOD    bus requests: cached  2, direct  20
    t= 3000 ms  level 2.50 m STALE   bus requests: cached  5, direct  29  (link down at 1000 ms)
    t= 4000 ms  level 2.75 m GOOD    bus requests: cached  6, direct  49
    """
    prog = OvenMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), prog)

    def write(value: float) -> None:
        level = prog.access.level.name
        if prog.hmi_setpoint.write(value):
            print(f"{level} write {value:.1f} accepted: setpoint {prog.hmi_setpoint.setpoint:.1f}")
        else:
            print(f"{prog.access.message} ({prog.access.last_refusal.name})")

    write(185.0)
    write(240.0)
    prog.access.login(AccessLevel.ENGINEER)
    write(320.0)
    rt.run(duration=T("5m10ms"))
    print(f"idle 5 min: level back to {prog.access.level.name}")
    write(325.0)
    print(f"refused writes: {prog.access.refused}")

    def show(note: str = "") -> None:
        cached, direct = prog.station.requests - cached0, prog.direct.requests - direct0
        print(f"t={rt.time_ms - t0:5d} ms  level {prog.level_m:.2f} m {prog.level_quality.name:<7} "
              f"bus requests: cached {cached:2d}, direct {direct:3d}{note}")

    t0, cached0, direct0 = rt.time_ms, prog.station.requests, prog.direct.requests
    prog.station.remote_value = prog.direct.remote_value = 2.5
    rt.run(cycles=100)
    show()
    prog.station.link_ok = prog.direct.link_ok = False
    rt.run(cycles=200)
    show("  (link down at 1000 ms)")
    prog.station.link_ok = prog.direct.link_ok = True
    prog.station.remote_value = prog.direct.remote_value = 2.75
    rt.run(cycles=100)
    show()


def _oven(scenario: Scenario, cycle: int) -> None:
    prog = scenario.program
    if cycle == 1:
        prog.station.remote_value = prog.direct.remote_value = 2.5
    writes = {2: 185.0, 3: 240.0, 5: 320.0, 7: 325.0}
    if cycle == 4:
        prog.access.login(AccessLevel.ENGINEER)
    if cycle == 6:
        prog.access.logout()
    if cycle in writes:
        prog.hmi_setpoint.write(writes[cycle])
    if cycle == 101:
        prog.station.link_ok = prog.direct.link_ok = False
    if cycle == 301:
        prog.station.link_ok = prog.direct.link_ok = True
        prog.station.remote_value = prog.direct.remote_value = 2.75


SHOWCASE = Showcase(
    use_when="access to a block is guarded by access level, or a slow remote value is cached with its quality",
    columns=(
        Column("access", lambda p: p.access.level),
        Column("setpoint", lambda p: p.hmi_setpoint.setpoint, ".1f"),
        Column("refused", lambda p: p.access.refused),
        Column("level", lambda p: f"{p.level_m:.2f} m {p.level_quality.name}"),
        Column("bus requests: cached", lambda p: p.station.requests, watch=False),
        Column("direct", lambda p: p.direct.requests, watch=False),
    ),
    script=_oven,
    cycles=400,
    tour_cycles=400,
    expected=(
        ("refused", "an OPERATOR writes setpoints above the operator limit in cycles 3 and 7"),
        ("STALE", "the remote I/O link is lost from cycle 101"),
    ),
)


if __name__ == "__main__":
    main()
