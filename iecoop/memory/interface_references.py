"""Interface variables: ``itf : I_Motor;`` holds a checked reference to an instance, or ``NullInterface``.

``InterfaceInfo`` describes a variable of an interface type; its value is the
instance it references, or a falsy ``NullInterface`` (ST ``itf = 0``) through
which every call raises RTSEXCPT_ACCESS_VIOLATION.
"""

from __future__ import annotations

import ctypes
import typing
from typing import Any

from iecoop.memory._aggregates import dynamic_class
from iecoop.memory._handles import access_violation, allocation_of, hold, resolve
from iecoop.memory._infos import TypeInfo
from iecoop.memory._resolve import register_class_info
from iecoop.metadata import Kind

__all__ = ["InterfaceInfo", "NullInterface"]


class NullInterface:
    """The value of an interface variable that references nothing (ST: ``itf = 0``).

    It is falsy; calling a method or reading a property through it raises
    RTSEXCPT_ACCESS_VIOLATION, as the PLC does.
    """

    __slots__ = ("_iface", "_where")

    def __init__(self, iface: str, where: str) -> None:
        object.__setattr__(self, "_iface", iface)
        object.__setattr__(self, "_where", where)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__") and name.endswith("__"):
            # Python's own protocol lookups (copy, pickle, inspect) are not PLC calls.
            raise AttributeError(name)
        raise access_violation(f"{self._where}: {self._iface}.{name} called through a null interface reference")

    def __setattr__(self, name: str, value: Any) -> None:
        raise access_violation(f"{self._where}: {self._iface}.{name} written through a null interface reference")

    def __bool__(self) -> bool:
        return False

    def __eq__(self, other: object) -> bool:
        return other is None or isinstance(other, NullInterface) or (isinstance(other, int) and other == 0)

    def __hash__(self) -> int:
        return 0

    def __repr__(self) -> str:
        return f"<{self._iface} = 0>"


class InterfaceInfo(TypeInfo):
    direct = False
    ctype = ctypes.c_uint64

    def __init__(self, iface: type) -> None:
        self.iface = iface
        self.name = iface.__name__

    def handle_for(self, value: Any, where: str) -> int:
        return self.handle_and_block(value, where)[0]

    def handle_and_block(self, value: Any, where: str) -> tuple[int, Any]:
        """The handle an assignment stores, and the block it keeps alive (None for the null reference)."""
        if value is None or isinstance(value, NullInterface):
            return 0, None
        if isinstance(value, int) and not isinstance(value, bool) and value == 0:
            return 0, None
        if not isinstance(value, self.iface):
            raise TypeError(
                f"{where}: {type(value).__name__} does not implement {self.name} and cannot be assigned to it"
            )
        alloc, offset = allocation_of(value)
        return (alloc.id << 32) | offset, alloc.ref()

    def value_for(self, handle: int, where: str) -> Any:
        if handle == 0:
            return NullInterface(self.name, where)
        root, offset = resolve(handle, 8, where)
        cls = dynamic_class(root, offset, f"{where}: interface reference")
        if offset == 0 and type(root) is cls:
            return root
        return typing.cast(Any, cls).from_buffer(root, offset)

    def load(self, root: Any, offset: int) -> Any:
        return self.value_for(ctypes.c_uint64.from_buffer(root, offset).value, self.name)

    def store(self, root: Any, offset: int, value: Any, where: str) -> None:
        handle, block = self.handle_and_block(value, where)
        ctypes.c_uint64.from_buffer(root, offset).value = handle
        hold(root, offset, block)

    def validate(self, value: Any, where: str) -> None:
        if value is None or isinstance(value, NullInterface):
            return
        if not isinstance(value, self.iface):
            raise TypeError(f"{where}: {type(value).__name__} does not implement {self.name}")


    def descriptor(self, raw: Any, name: str, owner: str) -> Any:
        return _InterfaceField(self, raw, f"{owner}.{name}")


class _InterfaceField:
    __slots__ = ("info", "raw", "where")

    def __init__(self, info: InterfaceInfo, raw: Any, where: str) -> None:
        self.info, self.raw, self.where = info, raw, where

    def __get__(self, obj: Any, owner: Any = None) -> Any:
        if obj is None:
            return self
        return self.info.value_for(self.raw.__get__(obj), self.where)

    def __set__(self, obj: Any, value: Any) -> None:
        handle, block = self.info.handle_and_block(value, self.where)
        raw = self.raw
        # Storing the instance the variable already holds (every cycle, often) changes nothing.
        if raw.__get__(obj) != handle:
            raw.__set__(obj, handle)
            hold(obj, raw.offset, block)


register_class_info(Kind.INTERFACE, InterfaceInfo)
