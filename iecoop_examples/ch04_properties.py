"""Properties: a variable's Get and Set accessors, written as methods.

A PROPERTY looks like a variable to the caller (``fbTank.Setpoint := 150``)
but each read runs its Get accessor and each write its Set accessor, so the
block keeps its data private and still checks what it is given: here the Set
accessor clamps the setpoint to 0..100 %. Deleting the Set accessor makes a
property read-only; a Get can also compute its value (``Volume``) instead of
returning a stored one; and each accessor can carry its own access specifier
(``Capacity`` is read by anyone, set only by FB_Tank itself, in FB_init).

ST::

    FUNCTION_BLOCK FB_Tank
    VAR
        fLevel    : REAL;                 // %
        fSetpoint : REAL := 50.0;         // %
        fCapacity : REAL := 1000.0;       // l
    END_VAR
    // the level follows the setpoint by at most 2 % per cycle
    IF fLevel < fSetpoint THEN
        fLevel := MIN(fLevel + 2.0, fSetpoint);
    ELSIF fLevel > fSetpoint THEN
        fLevel := MAX(fLevel - 2.0, fSetpoint);
    END_IF

    METHOD FB_init : BOOL
    VAR_INPUT bInitRetains : BOOL; bInCopyCode : BOOL; fCapacity : REAL := 1000.0; END_VAR
    THIS^.Capacity := fCapacity;          // the PRIVATE Set, from FB_Tank's own code

    PROPERTY Setpoint : REAL
        Get: Setpoint := fSetpoint;
        Set: fSetpoint := LIMIT(0.0, Setpoint, 100.0);

    PROPERTY Level : REAL                 // no Set accessor: read-only
        Get: Level := fLevel;

    PROPERTY Volume : REAL                // computed on every read
        Get: Volume := fLevel * fCapacity / 100.0;

    PROPERTY Capacity : REAL
        PUBLIC Get:  Capacity := fCapacity;
        PRIVATE Set: fCapacity := MAX(Capacity, 0.0);

    PROGRAM MAIN
    VAR
        fbTank : FB_Tank(fCapacity := 2000.0);
        nCycle : INT;
    END_VAR
    nCycle := nCycle + 1;
    IF nCycle = 1 THEN
        fbTank.Setpoint := 150.0;         // the Set accessor makes it 100.0
    ELSIF nCycle = 30 THEN
        fbTank.Setpoint := 40.0;
    END_IF
    fbTank();
"""

from __future__ import annotations

from iecoop import BOOL, INT, PRIVATE, REAL, VAR, AccessError, FunctionBlock, Program, T, method, prop
from iecoop.runtime import Runtime, Task
from patterns.showcase.entry import Column, Showcase

__all__ = ["Main", "Tank", "main"]


class Tank(FunctionBlock):
    """``FUNCTION_BLOCK FB_Tank``: its data reached only through properties."""

    level_internal: REAL = VAR(0.0)
    setpoint_internal: REAL = VAR(50.0)
    capacity_internal: REAL = VAR(1000.0)

    def fb_init(self, init_retains: BOOL, in_copy_code: BOOL, capacity: REAL = 1000.0) -> BOOL:
        self.capacity = capacity
        return True

    def body(self) -> None:
        if self.level_internal < self.setpoint_internal:
            self.level_internal = min(self.level_internal + 2.0, self.setpoint_internal)
        elif self.level_internal > self.setpoint_internal:
            self.level_internal = max(self.level_internal - 2.0, self.setpoint_internal)

    @prop
    def setpoint(self) -> REAL:
        """``PROPERTY Setpoint : REAL`` (Get and Set)."""
        return self.setpoint_internal

    @setpoint.setter
    def setpoint(self, value: REAL) -> None:
        self.setpoint_internal = max(0.0, min(value, 100.0))

    @prop
    def level(self) -> REAL:
        """``PROPERTY Level : REAL``: Get only, so read-only."""
        return self.level_internal

    @prop
    def volume(self) -> REAL:
        """``PROPERTY Volume : REAL``: computed from the level and the capacity."""
        return self.level_internal * self.capacity_internal / 100.0

    @prop
    def capacity(self) -> REAL:
        """``PROPERTY Capacity : REAL``: PUBLIC Get, PRIVATE Set."""
        return self.capacity_internal

    @capacity.setter
    @method(PRIVATE)
    def capacity(self, value: REAL) -> None:
        self.capacity_internal = max(value, 0.0)


class Main(Program):
    """``PROGRAM MAIN``: moves the setpoint twice and calls the tank every cycle."""

    tank: Tank = VAR(fb_init={"capacity": 2000.0})
    cycle: INT = VAR(0)

    def body(self) -> None:
        self.cycle += 1
        if self.cycle == 1:
            self.tank.setpoint = 150.0
        elif self.cycle == 30:
            self.tank.setpoint = 40.0
        self.tank()


def main() -> None:
    """Run MAIN for 500 ms, then try the two writes the properties forbid.

    >>> main()
    t=100 ms  Setpoint=100.0 %  Level=20.0 %  Volume=400.0 l of 2000.0 l
    t=290 ms  Setpoint=100.0 %  Level=58.0 %  Volume=1160.0 l of 2000.0 l
    t=500 ms  Setpoint=40.0 %  Level=40.0 %  Volume=800.0 l of 2000.0 l
    fbTank.Level := 10: AttributeError: PROPERTY Tank.level has no Set accessor: it is read-only
    fbTank.Capacity := 5000: AccessError: PRIVATE PROPERTY Tank.capacity (Set) cannot be called from main in module ...
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    tank = program.tank
    for cycles in (10, 19, 21):
        rt.run(cycles=cycles)
        print(
            f"t={rt.time_ms} ms  Setpoint={tank.setpoint} %  Level={tank.level} %  "
            f"Volume={tank.volume} l of {tank.capacity} l"
        )
    try:
        setattr(tank, "level", 10.0)  # ST: a compile error, the property has no Set accessor
    except AttributeError as exc:
        print(f"fbTank.Level := 10: AttributeError: {exc}")
    try:
        tank.capacity = 5000.0
    except AccessError as exc:
        print(f"fbTank.Capacity := 5000: AccessError: {exc}")


SHOWCASE = Showcase(
    columns=(Column("Setpoint %", lambda p: p.tank.setpoint, ".1f"), Column("Level %", lambda p: p.tank.level, ".1f"),
             Column("Volume l", lambda p: p.tank.volume, ".1f")),
    cycles=50,
)


if __name__ == "__main__":
    main()
