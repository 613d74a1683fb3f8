"""The simulated plant that several patterns share: devices and the functions they run on.

A project keeps such things in a small library of its own; here they stand
in for the field: a Modbus frequency converter, a PLCopen motion kernel with
its function blocks, a contactor with its auxiliary contact, and ``ramp``,
the rate limiter the simulated devices and the SOLID examples follow their
setpoints with. The patterns drive these devices; the devices are not part
of any pattern.

- ``patterns.plant.functions``: ``ramp`` (``FUNCTION F_Ramp : REAL``).
- ``patterns.plant.vfd``: ``VfdSim``, the drive's side of a Modbus link, and its register map.
- ``patterns.plant.motion``: ``AxisRef``, ``AxisSim`` and ``MC_Power``, ``MC_MoveVelocity``,
  ``MC_Stop``, ``MC_Reset`` (PLCopen Part 1 behaviour: Execute, Busy, Done, Error).
- ``patterns.plant.contactor``: ``ContactorSim``, a contactor with pull-in delay and overload relay.
"""

from __future__ import annotations

from patterns.plant.functions import ramp

__all__ = ["ramp"]
