"""ExST, Extended Structured Text: the set and reset assignments ``S=`` and ``R=``.

``x S= c`` sets ``x`` to TRUE when ``c`` is TRUE and leaves it alone
otherwise, so once set it stays set, like a latching coil; ``x R= c`` resets
it the same way. Each is one line for ``IF c THEN x := TRUE; END_IF``, where a
plain ``x := c`` would follow ``c`` every cycle. Assignments chain, and every
one in a chain acts on the operand at the end of the line:
``bAlarm S= bRunning R= bFault`` sets the alarm *and* stops the motor on a
fault.

ST::

    FUNCTION_BLOCK FB_MotorControl
    VAR_INPUT
        bStart : BOOL;
        bStop  : BOOL;
        bFault : BOOL;
        bAck   : BOOL;
    END_VAR
    VAR_OUTPUT
        bFollow  : BOOL;                  // := follows the start button
        bRunning : BOOL;                  // S= / R= latch it
        bAlarm   : BOOL;
    END_VAR
    bFollow := bStart;
    bRunning S= bStart AND NOT bAlarm;    // IF bStart AND NOT bAlarm THEN bRunning := TRUE; END_IF
    bRunning R= bStop;                    // IF bStop THEN bRunning := FALSE; END_IF
    bAlarm S= bRunning R= bFault;         // on bFault: bAlarm := TRUE and bRunning := FALSE
    bAlarm R= bAck;

    PROGRAM MAIN
    VAR_INPUT bStart, bStop, bFault, bAck : BOOL; END_VAR   // push buttons
    VAR fbMotor : FB_MotorControl; END_VAR
    fbMotor(bStart := bStart, bStop := bStop, bFault := bFault, bAck := bAck);
"""

from __future__ import annotations

from iecoop import BOOL, VAR, VAR_INPUT, VAR_OUTPUT, FunctionBlock, Program, T
from iecoop.runtime import Runtime, Task
from iecoop.stdlib import R, S
from patterns.showcase.entry import Column, Showcase, press, steps

__all__ = ["Main", "MotorControl", "main"]


class MotorControl(FunctionBlock):
    """``FUNCTION_BLOCK FB_MotorControl``: a start/stop latch with a fault alarm, in ExST."""

    start: BOOL = VAR_INPUT(False)
    stop: BOOL = VAR_INPUT(False)
    fault: BOOL = VAR_INPUT(False)
    ack: BOOL = VAR_INPUT(False)
    follow: BOOL = VAR_OUTPUT(False)
    running: BOOL = VAR_OUTPUT(False)
    alarm: BOOL = VAR_OUTPUT(False)

    def body(self) -> None:
        self.follow = self.start
        S(self, "running", self.start and not self.alarm)
        R(self, "running", self.stop)
        S(self, "alarm", R(self, "running", self.fault))
        R(self, "alarm", self.ack)


class Main(Program):
    """``PROGRAM MAIN``: the push buttons, passed to fbMotor every cycle."""

    start: BOOL = VAR_INPUT(False)
    stop: BOOL = VAR_INPUT(False)
    fault: BOOL = VAR_INPUT(False)
    ack: BOOL = VAR_INPUT(False)
    motor: MotorControl = VAR()

    def body(self) -> None:
        self.motor(start=self.start, stop=self.stop, fault=self.fault, ack=self.ack)


#: One button pressed per cycle (or none): the sequence main() plays.
SEQUENCE = ("", "start", "", "stop", "start", "fault", "start", "ack", "start")


def main() -> None:
    """Press one button per cycle and print the three outputs after each cycle.

    >>> main()
    t=  0 ms  button -      bFollow=False  bRunning=False  bAlarm=False
    t= 10 ms  button start  bFollow=True   bRunning=True   bAlarm=False
    t= 20 ms  button -      bFollow=False  bRunning=True   bAlarm=False
    t= 30 ms  button stop   bFollow=False  bRunning=False  bAlarm=False
    t= 40 ms  button start  bFollow=True   bRunning=True   bAlarm=False
    t= 50 ms  button fault  bFollow=False  bRunning=False  bAlarm=True
    t= 60 ms  button start  bFollow=True   bRunning=False  bAlarm=True
    t= 70 ms  button ack    bFollow=False  bRunning=False  bAlarm=False
    t= 80 ms  button start  bFollow=True   bRunning=True   bAlarm=False
    """
    program = Main()
    rt = Runtime(store=":memory:")
    rt.add_task(Task("PlcTask", interval=T("10ms"), priority=20), program)
    for button in SEQUENCE:
        now = rt.time_ms
        for name in ("start", "stop", "fault", "ack"):
            setattr(program, name, name == button)
        rt.run(cycles=1)
        m = program.motor
        print(
            f"t={now:3d} ms  button {button or '-':<5}  bFollow={m.follow!s:<5}  "
            f"bRunning={m.running!s:<5}  bAlarm={m.alarm}"
        )


SHOWCASE = Showcase(
    columns=(Column("running", lambda p: p.motor.running), Column("follow", lambda p: p.motor.follow), Column("alarm", lambda p: p.motor.alarm)),
    script=steps(*press("start", 2), *press("fault", 5), *press("ack", 8), *press("start", 10), *press("stop", 13)),
    cycles=16,
)


if __name__ == "__main__":
    main()
