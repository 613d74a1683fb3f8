"""What ``iecoop st run`` takes from a project and its command line: the ``.TcTTO`` tasks, ``--set`` and ``--trace``.

A TwinCAT task object (``PlcTask.TcTTO``) gives ``<CycleTime>`` in microseconds (10000 is 10 ms, as TwinCAT's
comment in the file says), ``<Priority>`` and the programs the task calls, in order
(``<PouCall><Name>MAIN</Name></PouCall>``); ``--set MAIN.bStart=TRUE@100ms`` writes a value at a PLC time (``Runtime.write``, applied
at the next cycle start), ``--trace MAIN.eState,MAIN.fbStation.nBottles`` chooses the traced variables.
"""

from __future__ import annotations

import dataclasses
import pathlib
import re
from collections.abc import Callable, Sequence
from typing import Any

from iecoop import T
from iecoop.cli.base import UsageError
from iecoop.runtime import Runtime, Task

__all__ = ["ProjectTask", "Write", "parse_set", "project_task", "project_tasks", "writes_before"]

_TIME = re.compile(r"^\d+(\.\d+)?(ms|s|us|m|h)$", re.IGNORECASE)


@dataclasses.dataclass(frozen=True)
class ProjectTask:
    """A task of the project's ``.TcTTO`` files and the POUs it calls (``<PouCall><Name>MAIN</Name></PouCall>``), in order."""

    task: Task
    calls: tuple[str, ...]
    file: pathlib.Path


def project_tasks(source: str) -> list[ProjectTask]:
    """The tasks of the ``.TcTTO`` files beside ``source`` (a folder, ``.plcproj`` or file), by file name; [] when there is none."""
    path = pathlib.Path(source)
    folder = path if path.is_dir() else path.parent
    found = sorted(folder.rglob("*.TcTTO")) if folder.is_dir() else []
    return [_task_file(file) for file in found]


def project_task(source: str) -> Task | None:
    """The task of the first ``.TcTTO`` beside ``source`` (a folder, ``.plcproj`` or file), None when there is none."""
    tasks = project_tasks(source)
    return tasks[0].task if tasks else None


def _task_file(file: pathlib.Path) -> ProjectTask:
    from iecoop.st.read.parse import StSyntaxError, read_xml  # the reader's safe XML: no DTD, entity or network

    try:
        root = read_xml(file)
    except StSyntaxError as exc:
        raise UsageError(f"not a TwinCAT task file: {exc}") from None
    task = next((e for e in root.iter() if isinstance(e.tag, str) and _local(e.tag) == "Task"), None)
    if task is None:
        raise UsageError(f"{file}: no <Task> in it")
    fields = {_local(child.tag): (child.text or "").strip() for child in task if isinstance(child.tag, str)}
    cycle, priority = fields.get("CycleTime"), fields.get("Priority")
    try:
        interval_us = int(cycle or "10000")  # <CycleTime> counts microseconds (the task's CycleTime, 100 ns)
        level = int(priority or "20")
    except ValueError:
        raise UsageError(f"{file}: <CycleTime> and <Priority> must be whole numbers") from None
    if interval_us < 1000 or interval_us % 1000:
        raise UsageError(f"{file}: a cycle time of {interval_us} us is not a whole number of ms, which iecoop's runtime counts in")
    calls = tuple(
        (name.text or "").strip()
        for call in task if isinstance(call.tag, str) and _local(call.tag) == "PouCall"
        for name in call if isinstance(name.tag, str) and _local(name.tag) == "Name" and (name.text or "").strip()
    )
    interval = T(f"{interval_us // 1000}ms")
    return ProjectTask(Task(task.get("Name") or "PlcTask", interval=interval, priority=level), calls, file)


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


@dataclasses.dataclass(frozen=True)
class Write:
    """``--set PATH=VALUE@TIME``: write ``value`` to ``path`` when the PLC time reaches ``at_ms``."""

    path: str
    value: Any
    at_ms: int


def parse_set(text: str) -> Write:
    """``MAIN.bStart=TRUE@100ms`` (``@TIME`` optional: at the start) as a :class:`Write`."""
    assignment, _, when = text.partition("@")
    path, equals, value = assignment.partition("=")
    if not equals or not path.strip():
        raise UsageError(f"--set {text!r}: write it PATH=VALUE@TIME, e.g. MAIN.bStart=TRUE@100ms")
    at_ms = 0
    if when:
        if not _TIME.match(when.strip()):
            raise UsageError(f"--set {text!r}: {when!r} is not a time like 100ms or 2s")
        at_ms = int(T(when.strip()))
    return Write(path.strip(), _value(value.strip()), at_ms)


def _value(text: str) -> Any:
    if text.upper() in ("TRUE", "FALSE"):
        return text.upper() == "TRUE"
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    if len(text) >= 2 and text[0] == text[-1] == "'":
        return text[1:-1]
    raise UsageError(f"--set: {text!r} is not TRUE, FALSE, a number or a 'string'")


def writes_before(runtime: Runtime, writes: Sequence[Write]) -> Callable[[int], None]:
    """The ``before_cycle`` of ``run_cycles`` that hands each write to the runtime once its time has come."""
    pending = sorted(writes, key=lambda w: w.at_ms)

    def before(_cycle: int) -> None:
        while pending and pending[0].at_ms <= runtime.time_ms:
            write = pending.pop(0)
            try:
                runtime.write(write.path, write.value)
            except Exception as exc:  # AccessError for a path or value the PLC refuses
                raise UsageError(f"--set {write.path}: {exc}") from None

    return before
