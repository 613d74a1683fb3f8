"""Bridge: pumps and valves over local I/O, Modbus TCP or a simulation, chosen independently.

Intent
------

Decouple an abstraction from its implementation so that the two can vary
independently.

The PLC problem
---------------

A water treatment skid has pumps and valves. Some are wired to the PLC's own
terminals, some sit behind a Modbus TCP coupler in a remote cabinet, and
during factory acceptance tests all of them run against a simulation. Writing
``FB_PumpLocal``, ``FB_PumpModbus``, ``FB_PumpSim``, ``FB_ValveLocal``, ...
multiplies device kinds by channel kinds, and every new fieldbus adds a column
of copies.

The bridge splits the two hierarchies. A device (the abstraction) holds an
``I_Channel`` it is given through FB_init and speaks only in points and
values: "write 60 % to point 1", "read point 1". A channel (the
implementation) knows how a value reaches the field: directly through the
process image, through Modbus registers with a few cycles of latency and a
link that can fail, or through a plant model. Any device runs on any channel;
a device that was never given one stops the task at its first call with
RTSEXCPT_ACCESS_VIOLATION, the PLC's fault for a call through a null interface.

Roles
-----

- Abstraction → ``Device`` (``FB_Device``, ABSTRACT), holding the injected
  ``IChannel``.
- Refined abstractions → ``Pump`` (``FB_Pump``), ``Valve`` (``FB_Valve``),
  both behind ``IDevice`` (``I_Device``).
- Implementor → ``IChannel`` (``I_Channel``).
- Concrete implementors → ``LocalIo`` (``FB_LocalIo``), ``ModbusTcp``
  (``FB_ModbusTcp``), ``SimChannel`` (``FB_SimChannel``).
- The field side of the simulation → ``FieldSim`` (``FB_FieldSim``) over a
  ``FieldImage`` (``ST_FieldImage``).
- Client → ``SkidMain`` (``PROGRAM SkidMain``): all six device × channel
  combinations.

IEC 61131-3 mapping
-------------------

::

    INTERFACE I_Channel
        METHOD Write        VAR_INPUT nPoint : USINT; fValue : REAL; END_VAR
        METHOD Read : REAL  VAR_INPUT nPoint : USINT; END_VAR
        METHOD Cyclic
        PROPERTY Healthy : BOOL    PROPERTY Kind : STRING

    FUNCTION_BLOCK ABSTRACT FB_Device IMPLEMENTS I_Device
        VAR iChannel : I_Channel; nPoint : USINT; sTag : STRING(10); END_VAR
        METHOD FB_init : BOOL
            VAR_INPUT bInitRetains, bInCopyCode : BOOL;
                      sTag : STRING; iChannel : I_Channel; nPoint : USINT; END_VAR
        METHOD FINAL Cyclic                       // the channel's health, then Update()
        METHOD PROTECTED ABSTRACT Update

    FUNCTION_BLOCK FB_Pump EXTENDS FB_Device      // Start(fSpeed), Stop, Running, Speed
    FUNCTION_BLOCK FB_Valve EXTENDS FB_Device     // Open, Close, IsOpen, IsClosed, tonTravel

    FUNCTION_BLOCK FB_LocalIo IMPLEMENTS I_Channel
        VAR stImage : ST_FieldImage; END_VAR       // the process image
    FUNCTION_BLOCK FB_ModbusTcp IMPLEMENTS I_Channel
        VAR aRequest, aResponse : ARRAY[1..4] OF INT; nLatency : UINT; tonTimeout : TON; END_VAR
    FUNCTION_BLOCK FB_SimChannel EXTENDS FB_LocalIo  // the same image, answered by a model
        VAR fbModel : FB_FieldSim; END_VAR

When not to use it on a PLC
---------------------------

When devices and channels do not really vary independently: a skid whose I/O
is all local needs no channel interface, and a second level of indirection
on every read and write costs scan time on a small controller. A Bridge pays
off once a second channel kind (a fieldbus, a simulation for virtual
commissioning) is real, not hypothetical.

References
----------

- Gamma, Helm, Johnson, Vlissides: *Design Patterns*, Addison-Wesley 1994,
  "Bridge".
- IEC 61131-3:2013 (3rd ed.), ABSTRACT function blocks and methods,
  interfaces, FB_init (vendor extension).
- Beckhoff InfoSys, TwinCAT 3 PLC: "ABSTRACT concept", "FB_init,
  FB_reinit, FB_exit"; "Tc2_ModbusSrv" (Modbus TCP).
- CODESYS Online Help: "Extending a Function Block", "Implementing an
  Interface", "Methods FB_init, FB_reinit, FB_exit".
- Modbus Organization: *MODBUS Messaging on TCP/IP Implementation Guide*
  V1.0b.
"""

from __future__ import annotations

from operator import attrgetter
from typing import Any

from iecoop import (
    ABSTRACT,
    ARRAY,
    BOOL,
    FINAL,
    INT,
    PROTECTED,
    REAL,
    STRING,
    UINT,
    USINT,
    VAR,
    VAR_IN_OUT,
    VAR_INPUT,
    VAR_OUTPUT,
    FunctionBlock,
    Interface,
    Program,
    Struct,
    T,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import TON
from patterns.plant import ramp
from patterns.showcase.entry import Column, Showcase, steps

__all__ = [
    "POINTS",
    "Device",
    "FieldImage",
    "FieldSim",
    "IChannel",
    "IDevice",
    "LocalIo",
    "ModbusTcp",
    "Pump",
    "SimChannel",
    "SkidMain",
    "Valve",
    "main",
]

#: Points (analog values, 0..100 %) per channel, in each direction.
POINTS = 4


class FieldImage(Struct):
    """``TYPE ST_FieldImage``: what the terminals see: commands out (``q``), feedback in (``i``)."""

    q: ARRAY[REAL] = VAR(bounds=(1, POINTS))
    i: ARRAY[REAL] = VAR(bounds=(1, POINTS))


class FieldSim(FunctionBlock):
    """The actuators behind the terminals: ``FUNCTION_BLOCK FB_FieldSim`` (``VAR_IN_OUT stImage``).

    Every feedback follows its command at ``rate`` % per scan (a pump
    ramping, a valve travelling).
    """

    image: FieldImage = VAR_IN_OUT()
    rate: REAL = VAR_INPUT(5.0)

    def body(self) -> None:
        for k in range(1, POINTS + 1):
            self.image.i[k] = ramp(self.image.i[k], self.image.q[k], self.rate)


# ---------------------------------------------------------------------------
# The implementor side: channels
# ---------------------------------------------------------------------------


class IChannel(Interface):
    """``INTERFACE I_Channel``: how a value reaches the field and comes back."""

    @method
    def write(self, point: USINT, value: REAL) -> None: ...

    @method
    def read(self, point: USINT) -> REAL:
        raise NotImplementedError

    @method
    def cyclic(self) -> None:
        """Communication housekeeping, once per scan."""
        ...

    @prop
    def healthy(self) -> BOOL:
        """Values read are current."""
        raise NotImplementedError

    @prop
    def kind(self) -> STRING:
        raise NotImplementedError


class LocalIo(FunctionBlock, IChannel):
    """``FUNCTION_BLOCK FB_LocalIo IMPLEMENTS I_Channel``: the controller's own terminals, no latency."""

    image: FieldImage = VAR()

    @method
    def write(self, point: USINT, value: REAL) -> None:
        self.image.q[point] = value

    @method
    def read(self, point: USINT) -> REAL:
        return self.image.i[point]

    @method
    def cyclic(self) -> None:
        pass  # the process image is exchanged by the task itself

    @prop
    def healthy(self) -> BOOL:
        return True

    @prop
    def kind(self) -> STRING:
        return "local I/O"


class ModbusTcp(FunctionBlock, IChannel):
    """``FUNCTION_BLOCK FB_ModbusTcp IMPLEMENTS I_Channel``: a remote coupler polled over Modbus TCP.

    One transaction (write the holding registers, read the input registers)
    completes every ``latency`` scans. Registers are INT in 0.1 %, so values
    are rounded to one decimal. With ``link_up`` FALSE no transaction
    completes, and after 100 ms without an answer the channel is unhealthy.
    ``remote`` is the coupler's side of the link.
    """

    link_up: BOOL = VAR_INPUT(True)
    remote: FieldImage = VAR()
    request: ARRAY[INT] = VAR(bounds=(1, POINTS))
    response: ARRAY[INT] = VAR(bounds=(1, POINTS))
    latency: UINT = VAR(3)
    waited: UINT = VAR(0)
    answered: BOOL = VAR(False)
    timeout: TON = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, latency: UINT = 3) -> None:
        self.latency = max(latency, 1)

    @method
    def write(self, point: USINT, value: REAL) -> None:
        self.request[point] = round(value * 10.0)

    @method
    def read(self, point: USINT) -> REAL:
        return self.response[point] / 10.0

    @method
    def cyclic(self) -> None:
        self.waited += 1
        done = self.link_up and self.waited >= self.latency
        if done:
            for k in range(1, POINTS + 1):
                self.remote.q[k] = self.request[k] / 10.0
                self.response[k] = round(self.remote.i[k] * 10.0)
            self.waited = 0
            self.answered = True
        self.timeout(IN=not done, PT=T("100ms"))

    @prop
    def healthy(self) -> BOOL:
        return self.answered and not self.timeout.Q

    @prop
    def kind(self) -> STRING:
        return "Modbus TCP"


class SimChannel(LocalIo):
    """``FUNCTION_BLOCK FB_SimChannel EXTENDS FB_LocalIo``: no hardware; a plant model answers.

    For virtual commissioning: the same devices, the same code, the same
    process image, with the field replaced by ``FieldSim`` running inside
    the channel.
    """

    model: FieldSim = VAR()

    @method
    def cyclic(self) -> None:
        self.model(image=self.image)

    @prop
    def kind(self) -> STRING:
        return "simulated"


# ---------------------------------------------------------------------------
# The abstraction side: devices
# ---------------------------------------------------------------------------


class IDevice(Interface):
    """``INTERFACE I_Device``: what the skid sequence needs from any device."""

    @method
    def cyclic(self) -> None: ...

    @prop
    def fault(self) -> BOOL:
        raise NotImplementedError

    @prop
    def tag(self) -> STRING:
        raise NotImplementedError


class Device(FunctionBlock, IDevice, abstract=True):
    """The abstraction: ``FUNCTION_BLOCK ABSTRACT FB_Device IMPLEMENTS I_Device``.

    Holds the channel and the point it uses on it. ``Cyclic`` is FINAL: it
    records the channel's health, then calls the device's own ``Update``. A
    device given no channel faults there with RTSEXCPT_ACCESS_VIOLATION, the
    PLC's own fault for a call through a null interface.
    """

    channel_ref: IChannel = VAR()
    point: USINT = VAR(1)
    tag_name: STRING = VAR("", length=10)
    comm_ok: BOOL = VAR_OUTPUT(False)

    def fb_init(
        self,
        init_retains: BOOL,
        in_copy_code: BOOL,
        tag: STRING = "",
        channel: IChannel | None = None,
        point: USINT = 1,
    ) -> None:
        self.tag_name = tag
        self.point = point
        if channel is not None:
            self.channel_ref = channel

    @prop
    def channel(self) -> IChannel:
        """``PROPERTY Channel : I_Channel``: Set lets a program inject a sibling instance."""
        return self.channel_ref

    @channel.setter
    def channel(self, value: IChannel) -> None:
        self.channel_ref = value

    @prop
    def tag(self) -> STRING:
        return self.tag_name

    @method(FINAL)
    def cyclic(self) -> None:
        # No check for 0: a device given no channel faults here with RTSEXCPT_ACCESS_VIOLATION, as on the PLC.
        self.comm_ok = self.channel_ref.healthy
        self.update()

    @method(PROTECTED | ABSTRACT)
    def update(self) -> None:
        """Write the commands and read the feedback through ``channel_ref``."""
        ...

    @prop
    def fault(self) -> BOOL:
        return not self.comm_ok


class Pump(Device):
    """``FUNCTION_BLOCK FB_Pump EXTENDS FB_Device``: speed setpoint out, actual speed in (both %)."""

    setpoint: REAL = VAR(0.0)
    feedback: REAL = VAR_OUTPUT(0.0)

    @method
    def start(self, speed: REAL) -> None:
        self.setpoint = max(0.0, min(100.0, speed))

    @method
    def stop(self) -> None:
        self.setpoint = 0.0

    @method(PROTECTED)
    def update(self) -> None:
        self.channel_ref.write(self.point, self.setpoint)
        self.feedback = self.channel_ref.read(self.point)

    @prop
    def running(self) -> BOOL:
        return self.feedback > 1.0

    @prop
    def at_speed(self) -> BOOL:
        return self.setpoint > 0.0 and abs(self.feedback - self.setpoint) < 0.5


class Valve(Device):
    """``FUNCTION_BLOCK FB_Valve EXTENDS FB_Device``: position command out, position feedback in.

    A travel that has not reached its end position within 1 s latches a
    fault (``tonTravel``), whatever the channel.
    """

    open_cmd: BOOL = VAR(False)
    position: REAL = VAR_OUTPUT(0.0)
    travel_fault: BOOL = VAR_OUTPUT(False)
    travel: TON = VAR()

    @method
    def open(self) -> None:
        self.open_cmd = True

    @method
    def close(self) -> None:
        self.open_cmd = False

    @method(PROTECTED)
    def update(self) -> None:
        self.channel_ref.write(self.point, 100.0 if self.open_cmd else 0.0)
        self.position = self.channel_ref.read(self.point)
        in_position = self.is_open if self.open_cmd else self.is_closed
        self.travel(IN=not in_position, PT=T("1s"))
        if self.travel.Q:
            self.travel_fault = True

    @prop
    def is_open(self) -> BOOL:
        return self.position >= 99.0

    @prop
    def is_closed(self) -> BOOL:
        return self.position <= 1.0

    @prop
    def fault(self) -> BOOL:
        return not self.comm_ok or self.travel_fault


# ---------------------------------------------------------------------------
# The client: every device kind on every channel kind
# ---------------------------------------------------------------------------


class SkidMain(Program):
    """``PROGRAM SkidMain``: a pump (point 1) and a valve (point 2) on each of the three channels.

    ST::

        VAR
            fbLocal : FB_LocalIo;  fbModbus : FB_ModbusTcp(nLatency := 3);  fbSim : FB_SimChannel;
            pLoc : FB_Pump(sTag := 'P-LOC', nPoint := 1);  vLoc : FB_Valve(sTag := 'V-LOC', nPoint := 2);
            ...
            aDevices : ARRAY[1..6] OF I_Device;
        END_VAR
        pLoc.Channel := fbLocal;  ...                 // in FB_init: siblings are injected here
    """

    cmd_run: BOOL = VAR_INPUT(False)
    speed: REAL = VAR_INPUT(60.0)
    local: LocalIo = VAR()
    modbus: ModbusTcp = VAR(fb_init={"latency": 3})
    sim: SimChannel = VAR()
    p_loc: Pump = VAR(fb_init={"tag": "P-LOC", "point": 1})
    v_loc: Valve = VAR(fb_init={"tag": "V-LOC", "point": 2})
    p_mb: Pump = VAR(fb_init={"tag": "P-MB", "point": 1})
    v_mb: Valve = VAR(fb_init={"tag": "V-MB", "point": 2})
    p_sim: Pump = VAR(fb_init={"tag": "P-SIM", "point": 1})
    v_sim: Valve = VAR(fb_init={"tag": "V-SIM", "point": 2})
    devices: ARRAY[IDevice] = VAR(bounds=(1, 6))
    channels: ARRAY[IChannel] = VAR(bounds=(1, 3))
    field_local: FieldSim = VAR()
    field_remote: FieldSim = VAR()

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL) -> None:
        self.channels[1] = self.local
        self.channels[2] = self.modbus
        self.channels[3] = self.sim
        self.p_loc.channel = self.local
        self.v_loc.channel = self.local
        self.p_mb.channel = self.modbus
        self.v_mb.channel = self.modbus
        self.p_sim.channel = self.sim
        self.v_sim.channel = self.sim
        self.devices[1] = self.p_loc
        self.devices[2] = self.v_loc
        self.devices[3] = self.p_mb
        self.devices[4] = self.v_mb
        self.devices[5] = self.p_sim
        self.devices[6] = self.v_sim

    def body(self) -> None:
        for k in range(1, 4):
            self.channels[k].cyclic()
        if self.cmd_run:
            self.p_loc.start(self.speed)
            self.v_loc.open()
            self.p_mb.start(self.speed)
            self.v_mb.open()
            self.p_sim.start(self.speed)
            self.v_sim.open()
        else:
            self.p_loc.stop()
            self.v_loc.close()
            self.p_mb.stop()
            self.v_mb.close()
            self.p_sim.stop()
            self.v_sim.close()
        for k in range(1, 7):
            self.devices[k].cyclic()
        # The field behind the real channels (the simulated one carries its own).
        self.field_local(image=self.local.image)
        self.field_remote(image=self.modbus.remote)


def main() -> None:
    """Run two device kinds on three channel kinds, then cut the Modbus link.

    >>> main()
    t=   0 ms  run: pumps to 60 %, valves open
    t= 120 ms  P-LOC  on local I/O   at speed
    t= 120 ms  P-SIM  on simulated   at speed
    t= 140 ms  P-MB   on Modbus TCP  at speed
    t= 200 ms  V-LOC  on local I/O   open
    t= 200 ms  V-SIM  on simulated   open
    t= 230 ms  V-MB   on Modbus TCP  open
    t= 400 ms  Modbus link down
    t= 490 ms  faulted: P-MB, V-MB
    """
    skid = SkidMain()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), skid)
    skid.cmd_run = True
    print("t=   0 ms  run: pumps to 60 %, valves open")
    reported: set[str] = set()
    for _ in range(40):
        t = rt.time_ms
        rt.run(cycles=1)
        for pump, valve in ((skid.p_loc, skid.v_loc), (skid.p_mb, skid.v_mb), (skid.p_sim, skid.v_sim)):
            kind = pump.channel.kind
            for name, done, what in ((pump.tag, pump.at_speed, "at speed"), (valve.tag, valve.is_open, "open")):
                if done and name not in reported:
                    reported.add(name)
                    print(f"t={t:4d} ms  {name:<6} on {kind:<10}  {what}")
    skid.modbus.link_up = False
    print(f"t={rt.time_ms:4d} ms  Modbus link down")
    for _ in range(15):
        t = rt.time_ms
        rt.run(cycles=1)
        failed = [skid.devices[k].tag for k in range(1, 7) if skid.devices[k].fault]
        if failed:
            print(f"t={t:4d} ms  faulted: {', '.join(failed)}")
            break


def _bridge_faults(skid: Any) -> object:
    return " ".join(skid.devices[k].tag for k in range(1, 7) if skid.devices[k].fault) or "-"


SHOWCASE = Showcase(
    use_when="devices and their channels (local I/O, fieldbus, simulation) really vary independently",
    columns=(
        *(Column(f"P-{channel}", attrgetter(f"p_{channel.lower()}.at_speed")) for channel in ("LOC", "MB", "SIM")),
        Column("V-MB open", lambda p: p.v_mb.is_open),
        Column("Modbus link", lambda p: p.modbus.link_up),
        Column("faulted", _bridge_faults),
    ),
    script=steps((1, "cmd_run", True), (41, "modbus.link_up", False)),
    cycles=60,
    tour_cycles=60,
    expected=(("faulted P-MB V-MB", "the Modbus TCP link drops in cycle 41"),),
)
