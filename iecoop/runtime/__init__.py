"""The cyclic runtime: tasks, virtual time, the task clock and remanent data."""

from iecoop.runtime.clock import (
    Clock, ManualWall, SystemWall, VirtualClock, Wall, WallClock, current_clock, default_clock, now_ms,
    task_clock, use_clock,
)
from iecoop.runtime.online import Symbol
from iecoop.runtime.runtime import Fault, Runtime, Task, TaskInfo, current_task
from iecoop.runtime.trace import DEFAULT_TRACE_SIZE, Trace

__all__ = [
    "Clock",
    "DEFAULT_TRACE_SIZE",
    "Fault",
    "ManualWall",
    "Runtime",
    "Symbol",
    "SystemWall",
    "Task",
    "TaskInfo",
    "Trace",
    "VirtualClock",
    "Wall",
    "WallClock",
    "current_clock",
    "current_task",
    "default_clock",
    "now_ms",
    "task_clock",
    "use_clock",
]
