"""Plant functions several patterns share: what a project keeps in its own small utility library.

``ramp`` is ``FUNCTION F_Ramp : REAL``: one step of a rate limiter. The SOLID
examples ramp drive and actuator setpoints with it, and the simulated
devices (a VFD's frequency, an axis's velocity, a valve positioner, the
field behind a channel) follow their commands with it, one step per scan.

::

    FUNCTION F_Ramp : REAL
    VAR_INPUT actual, target, step : REAL; END_VAR
        IF actual < target THEN
            F_Ramp := MIN(actual + step, target);
        ELSE
            F_Ramp := MAX(actual - step, target);
        END_IF

>>> ramp(10.0, 25.0, 4.0), ramp(24.0, 25.0, 4.0), ramp(10.0, 0.0, 4.0), ramp(5.0, 5.0, 4.0)
(14.0, 25.0, 6.0, 5.0)
"""

from __future__ import annotations

from iecoop import REAL

__all__ = ["ramp"]


def ramp(actual: REAL, target: REAL, step: REAL) -> REAL:
    """``FUNCTION F_Ramp : REAL``: one step of at most ``step`` from ``actual`` towards ``target``."""
    if actual < target:
        return min(actual + step, target)
    return max(actual - step, target)
