"""Pass 2, TwinCAT's system lists read by name: ``_TaskInfo[i].CycleTime`` and ``_AppInfo.ProjectName``.

Both are globals of ``TwinCAT_SystemInfoVarList`` (written bare or with the list's name): the running task's
``TaskInfo`` (``iecoop.runtime.current_task``) and the application's ``AppInfo`` (``iecoop.libraries.tc2_system``),
read-only.
"""

from __future__ import annotations

from typing import Any

from iecoop.st.language import TASK_INFO_MEMBERS
from iecoop.st.read.frames import Ex, Scope
from iecoop.st.read.literals import Literals
from iecoop.st.read.table import STRING, TypeRef
from iecoop.st.read.trees import app_info_member, task_info_member

__all__ = ["SystemLists"]


class SystemLists(Literals):
    """The readers of ``_TaskInfo`` and ``_AppInfo``."""

    def task_info(self, elements: list[Any], node: Any, scope: Scope, store: bool) -> Ex:
        """``_TaskInfo[GETCURTASKINDEXEX()].CycleTime`` (TwinCAT's Tc2_System): the running task's ``current_task()``;
        ``_TaskInfo[fbTask.index]`` checks at run time that the index is the running task's (``task_info_at``)."""
        found = task_info_member(elements, store)
        if isinstance(found, str):
            raise self.fail(found, node)
        member, index, running = found
        type_ = STRING if member == "TaskName" else TypeRef("elem", TASK_INFO_MEMBERS[member])
        if running:
            self.need("iecoop.runtime", "current_task")
            return Ex(f"current_task().{member}", type_)
        self.need("iecoop.libraries.tc2_system", "task_info_at")
        return Ex(f"task_info_at({self.expr(index, scope).code}).{member}", type_)

    def app_info(self, elements: list[Any], node: Any, store: bool) -> Ex:
        """``_AppInfo.ProjectName`` (TwinCAT_SystemInfoVarList): ``app_info(__name__)``, the application of this code."""
        member = app_info_member(elements, store)
        if member.startswith("_AppInfo"):
            raise self.fail(member, node)
        self.need("iecoop.libraries.tc2_system", "app_info")
        return Ex(f"app_info(__name__).{member}", STRING if member != "AdsPort" else TypeRef("elem", "UINT"))
