"""The cyclic runtime: tasks, virtual time, the task clock and remanent data."""

from iecoop.runtime.clock import (
    Clock, ManualWall, SystemWall, VirtualClock, Wall, WallClock, current_clock, default_clock, now_ms,
    task_clock, use_clock,
)
from iecoop.runtime.runtime import Fault, Runtime, Task, TaskInfo, current_task

__all__ = [
    "Clock",
    "Fault",
    "ManualWall",
    "Runtime",
    "SystemWall",
    "Task",
    "TaskInfo",
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
