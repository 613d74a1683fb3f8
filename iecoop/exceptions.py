"""Runtime faults and definition errors.

``PlcException`` is what a PLC raises at run time (ST: the exception caught by
``__TRY ... __CATCH(exc)``); its ``.code`` is an ``ExceptionCode``
(``__SYSTEM.ExceptionCode``). ``DefinitionError`` is the analog of a compile
error and ``AccessError`` of a forbidden access.

>>> try:
...     raise PlcException(ExceptionCode.RTSEXCPT_DIVIDEBYZERO, "INT division by zero")
... except PlcException as exc:
...     print(exc.code.name, hex(exc.code))
RTSEXCPT_DIVIDEBYZERO 0x102
"""

from __future__ import annotations

import enum
import sys
import types
from collections.abc import Iterator
from contextlib import contextmanager
from typing import NamedTuple

__all__ = [
    "AccessError",
    "DefinitionError",
    "ExceptionCode",
    "IecError",
    "PlcException",
    "SourceLocation",
    "TryBlock",
    "location_of",
    "st_caller",
    "try_catch",
]


class ExceptionCode(enum.IntEnum):
    """``__SYSTEM.ExceptionCode`` (a UDINT enum, identical in TwinCAT 3 and CODESYS)."""

    RTSEXCPT_NOEXCEPTION = 0x00000000
    RTSEXCPT_WATCHDOG = 0x10
    RTSEXCPT_HARDWAREWATCHDOG = 0x11
    RTSEXCPT_IO_CONFIG_ERROR = 0x12
    RTSEXCPT_PROGRAMCHECKSUM = 0x13
    RTSEXCPT_FIELDBUS_ERROR = 0x14
    RTSEXCPT_IOUPDATE_ERROR = 0x15
    RTSEXCPT_CYCLE_TIME_EXCEED = 0x16
    RTSEXCPT_ONLCHANGE_PROGRAM_EXCEEDED = 0x17
    RTSEXCPT_UNRESOLVED_EXTREFS = 0x18
    RTSEXCPT_DOWNLOAD_REJECTED = 0x19
    RTSEXCPT_BOOTPROJECT_REJECTED_DUE_RETAIN_ERROR = 0x1A
    RTSEXCPT_LOADBOOTPROJECT_FAILED = 0x1B
    RTSEXCPT_OUT_OF_MEMORY = 0x1C
    RTSEXCPT_RETAIN_MEMORY_ERROR = 0x1D
    RTSEXCPT_BOOTPROJECT_CRASH = 0x1E
    RTSEXCPT_BOOTPROJECTTARGETMISMATCH = 0x21
    RTSEXCPT_SCHEDULEERROR = 0x22
    RTSEXCPT_FILE_CHECKSUM_ERR = 0x23
    RTSEXCPT_RETAIN_IDENTITY_MISMATCH = 0x24
    RTSEXCPT_IEC_TASK_CONFIG_ERROR = 0x25
    RTSEXCPT_APP_TARGET_MISMATCH = 0x26
    RTSEXCPT_ILLEGAL_INSTRUCTION = 0x50
    RTSEXCPT_ACCESS_VIOLATION = 0x51
    RTSEXCPT_PRIV_INSTRUCTION = 0x52
    RTSEXCPT_IN_PAGE_ERROR = 0x53
    RTSEXCPT_STACK_OVERFLOW = 0x54
    RTSEXCPT_INVALID_DISPOSITION = 0x55
    RTSEXCPT_INVALID_HANDLE = 0x56
    RTSEXCPT_GUARD_PAGE = 0x57
    RTSEXCPT_DOUBLE_FAULT = 0x58
    RTSEXCPT_INVALID_OPCODE = 0x59
    RTSEXCPT_MISALIGNMENT = 0x100
    RTSEXCPT_ARRAYBOUNDS = 0x101
    RTSEXCPT_DIVIDEBYZERO = 0x102
    RTSEXCPT_OVERFLOW = 0x103
    RTSEXCPT_NONCONTINUABLE = 0x104
    RTSEXCPT_PROCESSORLOAD_WATCHDOG = 0x105
    RTSEXCPT_FPU_ERROR = 0x150
    RTSEXCPT_FPU_DENORMAL_OPERAND = 0x151
    RTSEXCPT_FPU_DIVIDEBYZERO = 0x152
    RTSEXCPT_FPU_INEXACT_RESULT = 0x153
    RTSEXCPT_FPU_INVALID_OPERATION = 0x154
    RTSEXCPT_FPU_OVERFLOW = 0x155
    RTSEXCPT_FPU_STACK_CHECK = 0x156
    RTSEXCPT_FPU_UNDERFLOW = 0x157
    RTSEXCPT_BREAKPOINT = 0x200
    RTSEXCPT_UNKNOWN = 0xFFFFFFFF


class IecError(Exception):
    """Base of every error iecoop raises on purpose."""


#: The files loaded Structured Text runs under (``.TcPOU``, ``.st``, ``<st text #N>``), filled by ``st.load``.
_ST_FILES: set[str] = set()


def register_st_file(name: str) -> None:
    """Code compiled under ``name`` is loaded Structured Text: a fault in it has a ``location``."""
    _ST_FILES.add(name)


class SourceLocation(NamedTuple):
    """Where in loaded Structured Text a fault arose: file, line, POU and member (None: the POU's body)."""

    file: str
    line: int
    pou: str
    member: str | None

    def __str__(self) -> str:
        where = f"{self.pou}.{self.member}" if self.member else self.pou
        return f"{self.file}:{self.line} ({where})"


def _st_frame(tb: types.TracebackType | None) -> SourceLocation | None:
    """The innermost frame of ``tb`` that runs loaded ST, as a SourceLocation."""
    found = None
    while tb is not None:
        code = tb.tb_frame.f_code
        if code.co_filename in _ST_FILES:
            found = (tb.tb_frame, code, tb.tb_lineno)
        tb = tb.tb_next
    if found is None:
        return None
    return _frame_location(*found)


def st_caller() -> SourceLocation | None:
    """The innermost frame of the running call stack that runs loaded ST (the ST line calling the caller), or None."""
    frame: types.FrameType | None = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_filename in _ST_FILES:
            return _frame_location(frame, frame.f_code, frame.f_lineno)
        frame = frame.f_back
    return None


def _frame_location(frame: types.FrameType, code: types.CodeType, line: int) -> SourceLocation:
    # The class builder compiles a body into its block's call inside helpers of its own (_iec_*).
    parts = [p for p in code.co_qualname.split(".") if p != "<locals>" and not p.startswith("_iec_")]
    owner = frame.f_locals.get("self")
    member: str | None = parts[-1] if parts else code.co_name
    if len(parts) >= 2:
        pou = parts[-2]
    elif owner is not None:
        pou = type(owner).__name__
    else:
        pou, member = member or code.co_name, None
    if member in ("body", "__call__"):
        member = None
    return SourceLocation(code.co_filename, line, pou, member)


class PlcException(IecError):
    """A runtime fault (ST: ``__CATCH(exc)``); ``.code`` is the ExceptionCode.

    ``.location`` is where in loaded ST it arose (a ``SourceLocation``: file,
    line, POU, member), read from the traceback of the fault or of what caused
    it; None for a fault outside loaded ST.
    """

    def __init__(self, code: ExceptionCode, message: str = "", location: SourceLocation | None = None) -> None:
        self.code = ExceptionCode(code)
        self.message = message
        self._location = location
        text = f"{self.code.name} (16#{int(self.code):X})"
        super().__init__(f"{text}: {message}" if message else text)

    @property
    def location(self) -> SourceLocation | None:
        """The innermost ST frame the fault passed through (its own traceback first, then its cause's)."""
        if getattr(self, "_location", None) is None:  # a subclass may not call this __init__
            self._location = location_of(self)
        return self._location


def location_of(exc: BaseException) -> SourceLocation | None:
    """Where in loaded ST ``exc`` (or the exception it was raised from) arose; None outside loaded ST."""
    seen: set[int] = set()
    current: BaseException | None = exc
    while current is not None and id(current) not in seen:
        seen.add(id(current))
        found = _st_frame(current.__traceback__)
        if found is not None:
            return found
        current = current.__cause__ or current.__context__
    return None


class DefinitionError(IecError, TypeError):
    """A class breaks an IEC 61131-3 rule: the analog of a compile error."""


class AccessError(IecError):
    """A member was used from where its access specifier or VAR section forbids it."""


class TryBlock:
    """What ``try_catch`` caught: ``.code`` is RTSEXCPT_NOEXCEPTION when nothing was raised."""

    __slots__ = ("code", "exception")

    def __init__(self) -> None:
        self.code: ExceptionCode = ExceptionCode.RTSEXCPT_NOEXCEPTION
        self.exception: PlcException | None = None


@contextmanager
def try_catch() -> Iterator[TryBlock]:
    """``__TRY ... __CATCH(exc) ... __ENDTRY``: a runtime fault skips the rest of the block.

    ZeroDivisionError is caught as RTSEXCPT_DIVIDEBYZERO, as the PLC would.

    >>> with try_catch() as exc:
    ...     x = 1 // 0
    >>> exc.code.name
    'RTSEXCPT_DIVIDEBYZERO'
    """
    block = TryBlock()
    try:
        yield block
    except PlcException as exc:
        block.code, block.exception = exc.code, exc
    except ZeroDivisionError as exc:
        fault = PlcException(ExceptionCode.RTSEXCPT_DIVIDEBYZERO, str(exc), location_of(exc))
        block.code, block.exception = fault.code, fault
