"""Interface or inheritance? "Is a" with shared code, or "can do" with a contract.

Inheritance says what a block *is*: FB_Lamp and FB_Fan are devices, and by
extending FB_Device they reuse its code (switching, counting switchings)
without writing it again; a ``POINTER TO FB_Device`` reaches all of them. But
a block has one base only: FB_Valve already extends the library's
FB_ValveDriver, so it can never be an FB_Device. An interface says what a
block *can do*: any block, whatever its base, can implement I_Switchable, and
a block can implement several interfaces (FB_DimmableLamp is I_Switchable and
I_Dimmable). So MAIN switches all four blocks through ``I_Switchable``, and
uses the FB_Device family only where it needs the family's own data.

ST::

    INTERFACE I_Switchable
    METHOD TurnOn
    METHOD TurnOff
    PROPERTY IsOn : BOOL                                // Get

    INTERFACE I_Dimmable
    PROPERTY Brightness : INT                           // %, Get and Set

    FUNCTION_BLOCK FB_Device IMPLEMENTS I_Switchable    // the shared code
    VAR bOn : BOOL; nSwitchings : UDINT; END_VAR
    METHOD TurnOn    IF NOT bOn THEN bOn := TRUE; nSwitchings := nSwitchings + 1; END_IF
    METHOD TurnOff   bOn := FALSE;
    PROPERTY IsOn : BOOL    Get: IsOn := bOn;

    FUNCTION_BLOCK FB_Lamp EXTENDS FB_Device

    FUNCTION_BLOCK FB_DimmableLamp EXTENDS FB_Lamp IMPLEMENTS I_Dimmable
    VAR nBrightness : INT := 100; END_VAR
    PROPERTY Brightness : INT
        Get: Brightness := SEL(bOn, 0, nBrightness);
        Set: nBrightness := LIMIT(0, Brightness, 100);

    FUNCTION_BLOCK FB_Fan EXTENDS FB_Device
    VAR_OUTPUT nRpm : INT; END_VAR
    nRpm := SEL(bOn, 0, 1400);

    FUNCTION_BLOCK FB_ValveDriver                       // from a valve library
    VAR_OUTPUT bOpen : BOOL; END_VAR
    METHOD Open     bOpen := TRUE;
    METHOD Close    bOpen := FALSE;

    FUNCTION_BLOCK FB_Valve EXTENDS FB_ValveDriver IMPLEMENTS I_Switchable
    METHOD TurnOn   Open();
    METHOD TurnOff  Close();
    PROPERTY IsOn : BOOL    Get: IsOn := bOpen;

    PROGRAM MAIN
    VAR_INPUT bAllOn : BOOL; bAllOff : BOOL; nDim : INT := 100; END_VAR
    VAR
        fbLamp      : FB_Lamp;
        fbDimmer    : FB_DimmableLamp;
        fbFan       : FB_Fan;
        fbValve     : FB_Valve;
        aSwitches   : ARRAY[1..4] OF I_Switchable;          // anything that switches
        aDevices    : ARRAY[1..3] OF POINTER TO FB_Device;  // the FB_Device family only
        itfDimmer   : I_Dimmable;
        nOn         : INT;
        nSwitchings : UDINT;
        i           : INT;
    END_VAR
    aSwitches[1] := fbLamp;  aSwitches[2] := fbDimmer;
    aSwitches[3] := fbFan;   aSwitches[4] := fbValve;
    aDevices[1] := ADR(fbLamp);  aDevices[2] := ADR(fbDimmer);  aDevices[3] := ADR(fbFan);
    itfDimmer := fbDimmer;
    itfDimmer.Brightness := nDim;
    nOn := 0;
    FOR i := 1 TO 4 DO
        IF bAllOn THEN aSwitches[i].TurnOn(); END_IF
        IF bAllOff THEN aSwitches[i].TurnOff(); END_IF
        IF aSwitches[i].IsOn THEN nOn := nOn + 1; END_IF
    END_FOR
    fbFan();
    nSwitchings := 0;
    FOR i := 1 TO 3 DO
        nSwitchings := nSwitchings + aDevices[i]^.nSwitchings;
    END_FOR

    FUNCTION_BLOCK FB_Valve EXTENDS FB_ValveDriver, FB_Device   // error: one base only
"""

from __future__ import annotations

from iecoop import (
    ARRAY,
    BOOL,
    INT,
    POINTER_TO,
    UDINT,
    VAR,
    VAR_INPUT,
    VAR_OUTPUT,
    DefinitionError,
    FunctionBlock,
    Interface,
    Program,
    T,
    adr,
    method,
    prop,
)
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase, steps

__all__ = [
    "Device",
    "DimmableLamp",
    "Fan",
    "IDimmable",
    "ISwitchable",
    "Lamp",
    "Main",
    "Valve",
    "ValveDriver",
    "main",
]


class ISwitchable(Interface):
    """``INTERFACE I_Switchable``."""

    @method
    def turn_on(self) -> None: ...

    @method
    def turn_off(self) -> None: ...

    @prop
    def is_on(self) -> BOOL:
        raise NotImplementedError


class IDimmable(Interface):
    """``INTERFACE I_Dimmable``."""

    @prop
    def brightness(self) -> INT:
        raise NotImplementedError

    @brightness.setter
    def brightness(self, value: INT) -> None: ...


class Device(FunctionBlock, ISwitchable):
    """``FUNCTION_BLOCK FB_Device IMPLEMENTS I_Switchable``: the code its family shares."""

    on: BOOL = VAR(False)
    switchings: UDINT = VAR(0)

    @method
    def turn_on(self) -> None:
        if not self.on:
            self.on = True
            self.switchings += 1

    @method
    def turn_off(self) -> None:
        self.on = False

    @prop
    def is_on(self) -> BOOL:
        return self.on


class Lamp(Device):
    """``FUNCTION_BLOCK FB_Lamp EXTENDS FB_Device``: a device, nothing to add."""


class DimmableLamp(Lamp, IDimmable):
    """``FUNCTION_BLOCK FB_DimmableLamp EXTENDS FB_Lamp IMPLEMENTS I_Dimmable``."""

    brightness_internal: INT = VAR(100)

    @prop
    def brightness(self) -> INT:
        return self.brightness_internal if self.on else 0

    @brightness.setter
    def brightness(self, value: INT) -> None:
        self.brightness_internal = max(0, min(value, 100))


class Fan(Device):
    """``FUNCTION_BLOCK FB_Fan EXTENDS FB_Device``."""

    rpm: INT = VAR_OUTPUT(0)

    def body(self) -> None:
        self.rpm = 1400 if self.on else 0


class ValveDriver(FunctionBlock):
    """``FUNCTION_BLOCK FB_ValveDriver``: a block from a valve library."""

    open: BOOL = VAR_OUTPUT(False)

    @method
    def open_valve(self) -> None:
        """``METHOD Open``."""
        self.open = True

    @method
    def close_valve(self) -> None:
        """``METHOD Close``."""
        self.open = False


class Valve(ValveDriver, ISwitchable):
    """``FUNCTION_BLOCK FB_Valve EXTENDS FB_ValveDriver IMPLEMENTS I_Switchable``."""

    @method
    def turn_on(self) -> None:
        self.open_valve()

    @method
    def turn_off(self) -> None:
        self.close_valve()

    @prop
    def is_on(self) -> BOOL:
        return self.open


class Main(Program):
    """``PROGRAM MAIN``: all four through I_Switchable, the family through POINTER TO FB_Device."""

    all_on: BOOL = VAR_INPUT(False)
    all_off: BOOL = VAR_INPUT(False)
    dim: INT = VAR_INPUT(100)
    lamp: Lamp = VAR()
    dimmer: DimmableLamp = VAR()
    fan: Fan = VAR()
    valve: Valve = VAR()
    switches: ARRAY[ISwitchable] = VAR(bounds=(1, 4))
    devices: ARRAY[POINTER_TO[Device]] = VAR(bounds=(1, 3))
    itf_dimmer: IDimmable = VAR()
    count_on: INT = VAR(0)
    switchings: UDINT = VAR(0)

    def body(self) -> None:
        self.switches[1] = self.lamp
        self.switches[2] = self.dimmer
        self.switches[3] = self.fan
        self.switches[4] = self.valve
        self.devices[1] = adr(self, "lamp")
        self.devices[2] = adr(self, "dimmer")
        self.devices[3] = adr(self, "fan")
        self.itf_dimmer = self.dimmer
        self.itf_dimmer.brightness = self.dim
        self.count_on = 0
        for i in range(1, 5):
            switch = self.switches[i]
            if self.all_on:
                switch.turn_on()
            if self.all_off:
                switch.turn_off()
            if switch.is_on:
                self.count_on += 1
        self.fan()
        self.switchings = 0
        for i in range(1, 4):
            self.switchings += self.devices[i].deref.switchings


def main() -> None:
    """Switch everything on, dim, off and on again, one step per cycle; then the double EXTENDS.

    >>> main()
    t= 0 ms  all on        nOn=4  brightness=100 %  fan 1400 rpm  valve open=True   nSwitchings=3
    t=10 ms  dim to 30 %   nOn=4  brightness= 30 %  fan 1400 rpm  valve open=True   nSwitchings=3
    t=20 ms  all off       nOn=0  brightness=  0 %  fan    0 rpm  valve open=False  nSwitchings=3
    t=30 ms  all on again  nOn=4  brightness= 30 %  fan 1400 rpm  valve open=True   nSwitchings=6
    DefinitionError: FUNCTION_BLOCK DeviceValve: EXTENDS allows one function block, got ValveDriver, Device
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    steps = (
        ("all on", True, False, 100),
        ("dim to 30 %", False, False, 30),
        ("all off", False, True, 30),
        ("all on again", True, False, 30),
    )
    for label, all_on, all_off, dim in steps:
        now = rt.time_ms
        program.all_on, program.all_off, program.dim = all_on, all_off, dim
        rt.run(cycles=1)
        print(
            f"t={now:2d} ms  {label:<13} nOn={program.count_on}  brightness={program.dimmer.brightness:3d} %  "
            f"fan {program.fan.rpm:4d} rpm  valve open={program.valve.open!s:<5}  nSwitchings={program.switchings}"
        )
    try:

        class DeviceValve(ValveDriver, Device):  # FB_Valve EXTENDS FB_ValveDriver, FB_Device
            pass

    except DefinitionError as exc:
        print(f"DefinitionError: {exc}")


SHOWCASE = Showcase(
    columns=(Column("nOn", lambda p: p.count_on), Column("brightness %", lambda p: p.dimmer.brightness), Column("fan rpm", lambda p: p.fan.rpm),
             Column("valve open", lambda p: p.valve.open), Column("nSwitchings", lambda p: p.switchings)),
    script=steps((1, "all_on", True), (2, "all_on", False), (2, "dim", 30), (3, "all_off", True),
                 (4, "all_off", False), (4, "all_on", True), (5, "all_on", False)),
    cycles=6,
)


if __name__ == "__main__":
    main()
