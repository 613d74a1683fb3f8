"""A frequency converter on Modbus, simulated: ``FUNCTION_BLOCK FB_VfdSim`` and its register map.

The control WORD and the speed reference are the drive's holding registers,
the status WORD and the actual speed its input registers; every flag is one
bit (ST ``wControl.0``, ``wStatus.3``). The constants are the bit masks.
"""

from __future__ import annotations

from iecoop import BOOL, LREAL, REAL, UDINT, VAR, VAR_INPUT, VAR_OUTPUT, WORD, FunctionBlock, T
from iecoop.runtime import now_ms
from iecoop.stdlib import R_TRIG, TON
from patterns.plant.functions import ramp

__all__ = [
    "CW_FAULT_RESET", "CW_RUN", "RPM_PER_HZ", "SW_AT_SPEED", "SW_FAULT", "SW_READY", "SW_RUNNING", "VFD_MAX_RPM",
    "VfdSim", "has_bit",
]

CW_RUN = 1 << 0  #: wControl.0: run
CW_FAULT_RESET = 1 << 7  #: wControl.7: fault reset, acted on at the rising edge
SW_READY = 1 << 0  #: wStatus.0: ready (no fault)
SW_RUNNING = 1 << 1  #: wStatus.1: output stage running
SW_AT_SPEED = 1 << 2  #: wStatus.2: output frequency at the reference
SW_FAULT = 1 << 3  #: wStatus.3: drive tripped
RPM_PER_HZ = 30.0  #: a 4-pole motor: 1500 rpm at 50 Hz
VFD_MAX_RPM = 1800.0  #: 60 Hz


def has_bit(word: WORD, mask: WORD) -> BOOL:
    """``word.n`` in ST: is the bit under ``mask`` set."""
    return (word & mask) != 0


class VfdSim(FunctionBlock):
    """The drive's side of the Modbus link: ``FUNCTION_BLOCK FB_VfdSim``.

    A RUN bit magnetises the motor for 50 ms, then the frequency ramps
    toward the reference at ``ramp_hz_per_s``. ``trip`` simulates an
    overcurrent trip; a rising FAULT_RESET bit clears it once ``trip`` is
    gone. Frequencies are in 0.1 Hz, as in the registers.
    """

    control_word: WORD = VAR_INPUT(0)
    speed_ref: WORD = VAR_INPUT(0)
    trip: BOOL = VAR_INPUT(False)
    ramp_hz_per_s: REAL = VAR_INPUT(100.0)
    status_word: WORD = VAR_OUTPUT(SW_READY)
    speed_act: WORD = VAR_OUTPUT(0)
    frequency: LREAL = VAR(0.0)
    faulted: BOOL = VAR(False)
    last_ms: UDINT = VAR(0)
    magnetise: TON = VAR()
    reset_edge: R_TRIG = VAR()

    def body(self) -> None:
        now = now_ms()
        step = self.ramp_hz_per_s * 10.0 * (now - self.last_ms) / 1000.0
        self.last_ms = now
        self.reset_edge(CLK=has_bit(self.control_word, CW_FAULT_RESET))
        if self.trip:
            self.faulted = True
        elif self.reset_edge.Q:
            self.faulted = False
        run = has_bit(self.control_word, CW_RUN) and not self.faulted
        self.magnetise(IN=run, PT=T("50ms"))
        if self.faulted:
            self.frequency = 0.0  # the output stage is off: the motor coasts
        else:
            target = float(self.speed_ref) if self.magnetise.Q else 0.0
            self.frequency = ramp(self.frequency, target, step)
        status = 0 if self.faulted else SW_READY
        if self.magnetise.Q or self.frequency > 0.0:
            status |= SW_RUNNING
        if run and self.magnetise.Q and abs(self.frequency - self.speed_ref) < 5.0:
            status |= SW_AT_SPEED
        if self.faulted:
            status |= SW_FAULT
        self.status_word = status
        self.speed_act = round(self.frequency)
