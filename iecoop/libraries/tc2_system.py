"""Tc2_System: Beckhoff's system library (strings, the ADS log, time, random numbers, files).

What a TwinCAT project calls from Tc2_System, written from Beckhoff's
documentation (Infosys, "TwinCAT 3 PLC Lib: Tc2_System"), with what is
simulated (see the "Tc2_System" library page for each name):

* ``ADSLOGSTR`` / ``ADSLOGDINT`` / ``ADSLOGLREAL`` write to Python ``logging``
  (logger ``iecoop.libraries.tc2_system``) and to ``adslog_messages()``, a
  list a test reads; the one ``%s`` / ``%d`` / ``%f`` of the format is
  rendered as Tc2_Utilities' FB_FormatString renders it.
* Time comes from the task clock (``iecoop.runtime.clock.current_clock()``):
  clock 0 ns is 1970-01-01 00:00:00 UTC (``DT#1970-01-01-00:00:00``, the DT
  origin), so in virtual time every time function is deterministic.
* The file blocks work in a sandbox folder a test or runtime gives with
  ``set_file_root(path)`` or ``with file_root(path):``; with none, they answer
  ADSERR_DEVICE_NOTFOUND. A path that leaves the folder (``..``, an absolute
  path, a symbolic link) is refused with ADSERR_DEVICE_INVALIDACCESS.

>>> from iecoop.runtime.clock import default_clock
>>> default_clock().set(0)
>>> F_GetSystemTime()            # 100 ns since 1601-01-01: the task clock's 0 is 1970-01-01
116444736000000000
>>> clear_adslog()
>>> ADSLOGDINT(ADSLOG_MSGTYPE_WARN, "level %d mm", 42)
0
>>> adslog_messages()[-1].text
'level 42 mm'
"""

from __future__ import annotations

import collections
import contextlib
import dataclasses
import logging
import os
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import Annotated, Any, BinaryIO, cast

from iecoop.declarations import VAR, VAR_INPUT, VAR_OUTPUT
from iecoop.exceptions import ExceptionCode, PlcException
from iecoop.libraries import known
from iecoop.libraries._printf import Arg, FormatError, render
from iecoop.lifecycle import project_of
from iecoop.memory import Alias, IecEnum, Pointer, Struct, memcmp, memcpy, memset
from iecoop.pou import FunctionBlock
from iecoop.runtime import current_task
from iecoop.runtime.clock import current_clock
from iecoop.types import BOOL, BYTE, DINT, DWORD, INT, LREAL, SINT, STRING, TIME, UDINT, UINT, ULINT, USINT, StringType

__all__ = [
    "ADSERR_DEVICE_SRVNOTSUPP", "ADSERR_TARGET_PORT_NOT_FOUND", "ADSRDWRT", "ADSREAD", "ADSREADEX", "ADSWRITE",
    "ADSLOGDINT", "ADSLOGLREAL", "ADSLOGSTR", "ADSLOG_MSGTYPE_ERROR", "ADSLOG_MSGTYPE_HINT", "ADSLOG_MSGTYPE_LOG",
    "ADSLOG_MSGTYPE_MSGBOX", "ADSLOG_MSGTYPE_RESOURCE", "ADSLOG_MSGTYPE_STRING", "ADSLOG_MSGTYPE_WARN",
    "CLEARBIT32", "CSETBIT32", "DEFAULT_ADS_TIMEOUT", "DRAND", "E_OpenPath", "E_SeekOrigin", "FB_CreateDir",
    "FB_FileClose", "FB_FileDelete", "FB_FileGets", "FB_FileOpen", "FB_FilePuts", "FB_FileRead", "FB_FileRename",
    "FB_FileSeek", "FB_FileTell", "FB_FileWrite", "FB_RemoveDir", "FOPEN_MODEAPPEND", "FOPEN_MODEBINARY",
    "FOPEN_MODEPLUS", "FOPEN_MODEREAD", "FOPEN_MODETEXT", "FOPEN_MODEWRITE", "F_GetSystemTime", "F_GetTaskTime",
    "F_GetVersionTcSystem", "F_ToASC", "F_ToCHR", "GETBIT32", "GETCPUCOUNTER", "GETCURTASKINDEX",
    "GETCURTASKINDEXEX", "GETSYSTEMTIME", "MAX_STRING_LENGTH", "MEMCMP", "MEMCPY", "MEMMOVE", "MEMSET", "SETBIT32",
    "ST_LibVersion", "T_AmsNetId", "T_AmsPort", "T_IPv4Addr", "T_MaxString", "stLibVersion_Tc2_System",
]

# --- types and constants ------------------------------------------------------------------------

#: ``TYPE T_MaxString : STRING(255)``: the longest STRING the library's blocks take.
T_MaxString = Annotated[str, StringType("STRING", 255), Alias("T_MaxString")]
#: ``TYPE T_AmsNetId : STRING(23)``: an AMS NetID as text ('' is the local system).
T_AmsNetId = Annotated[str, StringType("STRING", 23), Alias("T_AmsNetId")]
#: ``TYPE T_AmsPort : UINT``: an ADS port number.
T_AmsPort = Annotated[UINT, Alias("T_AmsPort")]
#: ``TYPE T_IPv4Addr : STRING(15)``: an IPv4 address as text.
T_IPv4Addr = Annotated[str, StringType("STRING", 15), Alias("T_IPv4Addr")]

MAX_STRING_LENGTH = 255  #: the length of T_MaxString
DEFAULT_ADS_TIMEOUT = 5000  #: T#5S, the ADS blocks' default tTimeout

# ADSLOG message-type flags: combine them in msgCtrlMask (Infosys, Tc2_System "ADSLOGSTR").
ADSLOG_MSGTYPE_HINT = 0x01
ADSLOG_MSGTYPE_WARN = 0x02
ADSLOG_MSGTYPE_ERROR = 0x04
ADSLOG_MSGTYPE_LOG = 0x10
ADSLOG_MSGTYPE_MSGBOX = 0x20
ADSLOG_MSGTYPE_RESOURCE = 0x40
ADSLOG_MSGTYPE_STRING = 0x80

# FB_FileOpen nMode flags (Infosys, Tc2_System "FB_FileOpen"), the letters of C's fopen.
FOPEN_MODEREAD = 0x01  #: 'r'
FOPEN_MODEWRITE = 0x02  #: 'w'
FOPEN_MODEAPPEND = 0x04  #: 'a'
FOPEN_MODEPLUS = 0x08  #: '+'
FOPEN_MODEBINARY = 0x10  #: 'b'
FOPEN_MODETEXT = 0x20  #: 't'

# The ADS return codes the file blocks give (Infosys, "ADS Return Codes").
ADSERR_TARGET_MACHINE_NOT_FOUND = 0x7  #: sNetId names another system (iecoop has no ADS route)
ADSERR_DEVICE_ERROR = 0x700  #: any other failure of the file system
ADSERR_DEVICE_INVALIDACCESS = 0x704  #: a path outside the sandbox, a link, a directory, a read-only file
ADSERR_DEVICE_NOMEMORY = 0x70A  #: MAX_OPEN_FILES files are open already
ADSERR_DEVICE_INVALIDPARM = 0x70B  #: an unknown hFile, an nMode without r / w / a, a null buffer
ADSERR_DEVICE_NOTFOUND = 0x70C  #: no such file or folder, or no sandbox folder set
ADSERR_DEVICE_EXISTS = 0x70F  #: the object already exists


class E_OpenPath(IecEnum):  # noqa: N801 - the ST name
    """``E_OpenPath``: which folder a file path is relative to (all of them the sandbox folder here)."""

    PATH_GENERIC = 1
    PATH_BOOTPRJ = 2
    PATH_BOOTDATA = 3
    PATH_BOOTPATH = 4
    PATH_USERPATH1 = 11
    PATH_USERPATH2 = 12
    PATH_USERPATH3 = 13
    PATH_USERPATH4 = 14
    PATH_USERPATH5 = 15
    PATH_USERPATH6 = 16
    PATH_USERPATH7 = 17
    PATH_USERPATH8 = 18
    PATH_USERPATH9 = 19


class ST_LibVersion(Struct):  # noqa: N801 - the ST name
    """``ST_LibVersion``: a library's version, as each library's ``stLibVersion_<library>`` constant holds it."""

    iMajor: UINT = 0
    iMinor: UINT = 0
    iBuild: UINT = 0
    iRevision: UINT = 0
    nFlags: DWORD = 0
    sVersion: STRING = VAR("", length=23)


def lib_version(title: str) -> ST_LibVersion:
    """The ``ST_LibVersion`` of the shipped library ``title``, from the version its ``KNOWN`` record follows."""
    library = known(title)
    assert library is not None, title
    major, minor, build, revision = (int(part) for part in library.version.split("."))
    return ST_LibVersion(iMajor=major, iMinor=minor, iBuild=build, iRevision=revision, sVersion=library.version)


def version_element(version: ST_LibVersion, nVersionElement: int) -> int:  # noqa: N803 - the ST name
    """Element 1 (major), 2 (minor), 3 (build) or 4 (revision) of ``version``; 0 for any other."""
    return {1: version.iMajor, 2: version.iMinor, 3: version.iBuild, 4: version.iRevision}.get(nVersionElement, 0)


#: ``stLibVersion_Tc2_System``: the version of Tc2_System iecoop follows.
stLibVersion_Tc2_System = lib_version("Tc2_System")


def F_GetVersionTcSystem(nVersionElement: INT) -> UINT:  # noqa: N802, N803 - the ST names
    """``F_GetVersionTcSystem(nVersionElement)``: 1 the major, 2 the minor, 3 the build number of Tc2_System."""
    return version_element(stLibVersion_Tc2_System, nVersionElement)


# --- the ADS log --------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class AdsLogMessage:
    """One message an ADSLOG function wrote: its msgCtrlMask and its text."""

    msg_ctrl_mask: int
    text: str


_log = logging.getLogger("iecoop.libraries.tc2_system")
# A library leaves output to the application's logging setup: no last-resort printing of warnings.
_log.addHandler(logging.NullHandler())
#: How many ADS log messages ``adslog_messages()`` keeps (the oldest go first), so a long run's memory stays bounded.
ADSLOG_KEEP = 10_000
_adslog: collections.deque[AdsLogMessage] = collections.deque(maxlen=ADSLOG_KEEP)


def adslog_messages() -> list[AdsLogMessage]:
    """The messages the ADSLOG functions wrote since the last ``clear_adslog()``, oldest first (the last ADSLOG_KEEP)."""
    return list(_adslog)


def clear_adslog() -> None:
    """Forget the messages ``adslog_messages()`` returns."""
    _adslog.clear()


def _adslog_write(mask: int, fmt: str, arg: Arg) -> int:
    try:
        text = render(fmt, [arg], MAX_STRING_LENGTH)
    except FormatError:
        text = fmt  # a format the formatter refuses is logged as written
    _adslog.append(AdsLogMessage(mask, text))
    if mask & ADSLOG_MSGTYPE_ERROR:
        level = logging.ERROR
    elif mask & ADSLOG_MSGTYPE_WARN:
        level = logging.WARNING
    else:
        level = logging.INFO
    _log.log(level, "%s", text)
    return 0


def ADSLOGSTR(msgCtrlMask: DWORD, msgFmtStr: T_MaxString, strArg: T_MaxString) -> DINT:  # noqa: N802, N803
    """``ADSLOGSTR(msgCtrlMask, msgFmtStr, strArg)``: log ``msgFmtStr`` with its ``%s`` replaced by ``strArg``; 0."""
    return _adslog_write(msgCtrlMask, msgFmtStr, Arg("STRING", strArg))


def ADSLOGDINT(msgCtrlMask: DWORD, msgFmtStr: T_MaxString, dintArg: DINT) -> DINT:  # noqa: N802, N803
    """``ADSLOGDINT(msgCtrlMask, msgFmtStr, dintArg)``: log ``msgFmtStr`` with its ``%d`` replaced by ``dintArg``; 0."""
    return _adslog_write(msgCtrlMask, msgFmtStr, Arg("DINT", dintArg))


def ADSLOGLREAL(msgCtrlMask: DWORD, msgFmtStr: T_MaxString, lrealArg: LREAL) -> DINT:  # noqa: N802, N803
    """``ADSLOGLREAL(msgCtrlMask, msgFmtStr, lrealArg)``: log ``msgFmtStr`` with its ``%f`` replaced by ``lrealArg``; 0."""
    return _adslog_write(msgCtrlMask, msgFmtStr, Arg("LREAL", lrealArg))


# --- time ---------------------------------------------------------------------------------------

#: 100 ns intervals from 1601-01-01 (the Windows FILETIME origin) to 1970-01-01, the task clock's 0.
FILETIME_AT_CLOCK_ZERO = 116_444_736_000_000_000


def filetime_now() -> int:
    """The task clock as a Windows FILETIME: 100 ns intervals since 1601-01-01 00:00:00 UTC."""
    return FILETIME_AT_CLOCK_ZERO + current_clock().now_ns() // 100


def F_GetSystemTime() -> ULINT:  # noqa: N802 - the ST name
    """``F_GetSystemTime()``: the system time in 100 ns since 1601-01-01 (the task clock, see the module)."""
    return filetime_now()


def F_GetTaskTime() -> ULINT:  # noqa: N802 - the ST name
    """``F_GetTaskTime()``: the start time of the running task's cycle, in 100 ns since 1601-01-01.

    A runtime sets its task clock once at the cycle start, so this is the
    instant every block of the cycle sees.
    """
    return filetime_now()


class GETSYSTEMTIME(FunctionBlock):
    """``GETSYSTEMTIME``: the system time (F_GetSystemTime) split into two DWORDs.

    ST: ``VAR_OUTPUT timeLoDW : UDINT; timeHiDW : UDINT; END_VAR``
    """

    timeLoDW: UDINT = VAR_OUTPUT(0)
    timeHiDW: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        now = filetime_now()
        self.timeLoDW = now & 0xFFFF_FFFF
        self.timeHiDW = now >> 32


class GETCPUCOUNTER(FunctionBlock):
    """``GETCPUCOUNTER``: a 64-bit counter of 100 ns ticks (here: the task clock since its 0).

    ST: ``VAR_OUTPUT cpuCntLoDW : UDINT; cpuCntHiDW : UDINT; END_VAR``
    """

    cpuCntLoDW: UDINT = VAR_OUTPUT(0)
    cpuCntHiDW: UDINT = VAR_OUTPUT(0)

    def body(self) -> None:
        ticks = current_clock().now_ns() // 100
        self.cpuCntLoDW = ticks & 0xFFFF_FFFF
        self.cpuCntHiDW = (ticks >> 32) & 0xFFFF_FFFF


# --- memory and bits ---------------------------------------------------------------------------
# Infosys, Tc2_System "MEMCPY", "MEMMOVE", "MEMSET", "MEMCMP": a 0 address or a count of 0 is refused
# by the return value, not a fault; the ranges themselves are checked as every iecoop pointer is.


def MEMCPY(destAddr: Pointer[Any], srcAddr: Pointer[Any], n: UDINT) -> UDINT:  # noqa: N802, N803 - the ST names
    """``MEMCPY(destAddr, srcAddr, n)``: copy n bytes; n, or 0 (nothing copied) when an address or n is 0."""
    if not destAddr or not srcAddr or not n:
        return 0
    return memcpy(destAddr, srcAddr, n)


def MEMMOVE(destAddr: Pointer[Any], srcAddr: Pointer[Any], n: UDINT) -> UDINT:  # noqa: N802, N803 - the ST names
    """``MEMMOVE(destAddr, srcAddr, n)``: MEMCPY for areas that may overlap (the source is read first)."""
    return MEMCPY(destAddr, srcAddr, n)  # iecoop's copy is a move already


def MEMSET(destAddr: Pointer[Any], fillByte: USINT, n: UDINT) -> UDINT:  # noqa: N802, N803 - the ST names
    """``MEMSET(destAddr, fillByte, n)``: fill n bytes with fillByte; n, or 0 when destAddr or n is 0."""
    if not destAddr or not n:
        return 0
    return memset(destAddr, fillByte & 0xFF, n)


def MEMCMP(pBuf1: Pointer[Any], pBuf2: Pointer[Any], n: UDINT) -> DINT:  # noqa: N802, N803 - the ST names
    """``MEMCMP(pBuf1, pBuf2, n)``: 0 equal, 1 / -1 as the first differing byte of pBuf1 is greater / smaller;
    16#FF when an address or n is 0."""
    if not pBuf1 or not pBuf2 or not n:
        return 0xFF
    return memcmp(pBuf1, pBuf2, n)


# Infosys, Tc2_System "SETBIT32" ...: bitNo is taken modulo 32.


def SETBIT32(inVal32: DWORD, bitNo: SINT) -> DWORD:  # noqa: N802, N803 - the ST names
    """``SETBIT32(inVal32, bitNo)``: inVal32 with bit bitNo (modulo 32) set."""
    return (inVal32 | (1 << (bitNo % 32))) & 0xFFFF_FFFF


def CLEARBIT32(inVal32: DWORD, bitNo: SINT) -> DWORD:  # noqa: N802, N803 - the ST names
    """``CLEARBIT32(inVal32, bitNo)``: inVal32 with bit bitNo (modulo 32) cleared."""
    return inVal32 & ~(1 << (bitNo % 32)) & 0xFFFF_FFFF


def CSETBIT32(inVal32: DWORD, bitNo: SINT, bitVal: BOOL) -> DWORD:  # noqa: N802, N803 - the ST names
    """``CSETBIT32(inVal32, bitNo, bitVal)``: inVal32 with bit bitNo (modulo 32) set to bitVal."""
    return SETBIT32(inVal32, bitNo) if bitVal else CLEARBIT32(inVal32, bitNo)


def GETBIT32(inVal32: DWORD, bitNo: SINT) -> BOOL:  # noqa: N802, N803 - the ST names
    """``GETBIT32(inVal32, bitNo)``: whether bit bitNo (modulo 32) of inVal32 is set."""
    return bool(inVal32 >> (bitNo % 32) & 1)


# --- characters ---------------------------------------------------------------------------------


def F_ToASC(str: STRING) -> BYTE:  # noqa: A002, N802 - the ST names
    """``F_ToASC(str)``: the code of the first character of str (Latin-1); 0 for an empty string."""
    return str.encode("latin-1")[0] if str else 0


def F_ToCHR(c: BYTE) -> STRING:  # noqa: N802 - the ST name
    """``F_ToCHR(c)``: the one-character STRING of code c; code 0 is the empty string (it ends a STRING)."""
    return bytes([c & 0xFF]).decode("latin-1") if c & 0xFF else ""


# --- tasks and random numbers -------------------------------------------------------------------

_task_numbers: dict[str, int] = {}


def GETCURTASKINDEXEX() -> BYTE:  # noqa: N802 - the ST name
    """``GETCURTASKINDEXEX()``: the running task's index, from 1 (see GETCURTASKINDEX)."""
    try:
        name = current_task().TaskName
    except RuntimeError:
        return 1  # outside a runtime cycle the code is in the one task there is
    return _task_numbers.setdefault(name, len(_task_numbers) + 1)


def task_info_at(index: int) -> Any:
    """``_TaskInfo[index]`` (TwinCAT_SystemInfoVarList): the running task's info when ``index`` is its GETCURTASKINDEX.

    iecoop knows the running task's information only: another index is an
    RTSEXCPT_ARRAYBOUNDS naming both.
    """
    own = GETCURTASKINDEXEX()
    if index != own:
        raise PlcException(ExceptionCode.RTSEXCPT_ARRAYBOUNDS,
                           f"_TaskInfo[{index}]: iecoop knows the running task's information only (its index is {own})")
    return current_task()


@dataclasses.dataclass(frozen=True)
class AppInfo:
    """What iecoop's virtual PLC reports of TwinCAT's ``_AppInfo`` (``PlcAppSystemInfo``): the project's name,
    the application's and its ADS port, as a TwinCAT 3 PLC's first application (port 851) has them."""

    ProjectName: str
    AppName: str = "Port_851"
    AdsPort: int = 851


def app_info(module: str) -> AppInfo:
    """``TwinCAT_SystemInfoVarList._AppInfo`` as the code of ``module`` reads it (its ProjectName: the project the
    code was loaded from, as instance paths start with it)."""
    return AppInfo(project_of(module))


class GETCURTASKINDEX(FunctionBlock):
    """``GETCURTASKINDEX``: the index of the task calling it (``_TaskInfo[index]``), from 1.

    ST: ``VAR_OUTPUT index : BYTE; END_VAR``. Tasks are numbered in the order
    they first ask, by task name; outside a runtime cycle the index is 1.
    """

    index: BYTE = VAR_OUTPUT(0)

    def body(self) -> None:
        self.index = GETCURTASKINDEXEX()


# --- ADS client blocks: ADSREAD, ADSREADEX, ADSWRITE, ADSRDWRT ------------------------------------

ADSERR_TARGET_PORT_NOT_FOUND = 0x6  #: no ADS device has that port on this system
ADSERR_DEVICE_SRVNOTSUPP = 0x701  #: the PLC's own port (851) serves nothing to its own code


class _AdsCommand(FunctionBlock, abstract=True):
    """The handshake of the ADS client blocks; ``TRIGGER`` names the block's rising-edge input.

    iecoop gives PLC code no ADS router, so no device answers: a rising edge sets BUSY; the first call in a
    later cycle (once the task clock has moved on, as an answer comes at a later cycle) drops it and sets
    ERR with ERRID 7 (another system's NETID), 6 (a port of this system) or 16#701 (the PLC's own port
    851). The buffers are left as they were; ERR stays until the next edge.
    """

    TRIGGER = ""
    NETID: T_AmsNetId = VAR_INPUT("")
    PORT: T_AmsPort = VAR_INPUT(0)
    IDXGRP: UDINT = VAR_INPUT(0)
    IDXOFFS: UDINT = VAR_INPUT(0)
    TMOUT: TIME = VAR_INPUT(DEFAULT_ADS_TIMEOUT)
    BUSY: BOOL = VAR_OUTPUT(False)
    ERR: BOOL = VAR_OUTPUT(False)
    ERRID: UDINT = VAR_OUTPUT(0)
    PREV_TRIGGER: BOOL = VAR(False)
    SENT_NS: ULINT = VAR(0)

    def body(self) -> None:
        trigger = bool(getattr(self, self.TRIGGER))
        if self.BUSY and current_clock().now_ns() > self.SENT_NS:
            self.BUSY, self.ERR = False, True
            if self.NETID not in ("", "127.0.0.1.1.1"):
                self.ERRID = ADSERR_TARGET_MACHINE_NOT_FOUND
            else:
                self.ERRID = ADSERR_DEVICE_SRVNOTSUPP if self.PORT == 851 else ADSERR_TARGET_PORT_NOT_FOUND
        elif trigger and not self.PREV_TRIGGER and not self.BUSY:
            self.BUSY, self.ERR, self.ERRID = True, False, 0
            self.SENT_NS = current_clock().now_ns()
        self.PREV_TRIGGER = trigger


class ADSREAD(_AdsCommand):
    """``ADSREAD``: LEN bytes of IDXGRP / IDXOFFS of the device NETID / PORT into DESTADDR, at READ's edge."""

    TRIGGER = "READ"
    LEN: UDINT = VAR_INPUT(0)
    DESTADDR: Pointer[Any] = VAR_INPUT()
    READ: BOOL = VAR_INPUT(False)


class ADSREADEX(ADSREAD):
    """``ADSREADEX``: ADSREAD with COUNT_R, the number of bytes read (0 here)."""

    COUNT_R: UDINT = VAR_OUTPUT(0)


class ADSWRITE(_AdsCommand):
    """``ADSWRITE``: LEN bytes from SRCADDR to IDXGRP / IDXOFFS of the device NETID / PORT, at WRITE's edge."""

    TRIGGER = "WRITE"
    LEN: UDINT = VAR_INPUT(0)
    SRCADDR: Pointer[Any] = VAR_INPUT()
    WRITE: BOOL = VAR_INPUT(False)


class ADSRDWRT(_AdsCommand):
    """``ADSRDWRT``: WRITELEN bytes from SRCADDR written, READLEN bytes into DESTADDR read, at WRTRD's edge."""

    TRIGGER = "WRTRD"
    WRITELEN: UDINT = VAR_INPUT(0)
    READLEN: UDINT = VAR_INPUT(0)
    SRCADDR: Pointer[Any] = VAR_INPUT()
    DESTADDR: Pointer[Any] = VAR_INPUT()
    WRTRD: BOOL = VAR_INPUT(False)


_MASK64 = 0xFFFF_FFFF_FFFF_FFFF


class DRAND(FunctionBlock):
    """``DRAND``: a pseudo-random LREAL in [0.0, 1.0); the same Seed gives the same sequence.

    ST: ``VAR_INPUT Seed : INT; END_VAR  VAR_OUTPUT Num : LREAL; END_VAR``.
    The generator (SplitMix64) is seeded at the first call and again when
    Seed changes; its state lives in the block, so a reset restarts it.

    >>> a, b = DRAND(), DRAND()
    >>> [a(Seed=7) or a.Num for _ in range(3)] == [b(Seed=7) or b.Num for _ in range(3)]
    True
    """

    Seed: INT = VAR_INPUT(0)
    Num: LREAL = VAR_OUTPUT(0.0)
    STATE: ULINT = VAR(0)
    SEEDED: BOOL = VAR(False)
    LAST_SEED: INT = VAR(0)

    def body(self) -> None:
        if not self.SEEDED or self.Seed != self.LAST_SEED:
            self.STATE = (self.Seed * 0x9E37_79B9_7F4A_7C15) & _MASK64
            self.LAST_SEED = self.Seed
            self.SEEDED = True
        state = (self.STATE + 0x9E37_79B9_7F4A_7C15) & _MASK64
        self.STATE = state
        z = ((state ^ (state >> 30)) * 0xBF58_476D_1CE4_E5B9) & _MASK64
        z = ((z ^ (z >> 27)) * 0x94D0_49BB_1331_11EB) & _MASK64
        z ^= z >> 31
        self.Num = (z >> 11) / float(1 << 53)


# --- files: the sandbox -------------------------------------------------------------------------

_root: Path | None = None
_files: dict[int, BinaryIO] = {}
_next_handle = 0


class _AdsError(Exception):
    def __init__(self, code: int) -> None:
        super().__init__(f"ADS error 16#{code:X}")
        self.code = code


def set_file_root(path: str | os.PathLike[str] | None) -> None:
    """Give the file blocks their sandbox folder (None: no folder, every file block answers ADSERR_DEVICE_NOTFOUND)."""
    global _root
    _root = None if path is None else Path(os.path.realpath(path))


def get_file_root() -> Path | None:
    """The sandbox folder the file blocks use, or None."""
    return _root


@contextlib.contextmanager
def file_root(path: str | os.PathLike[str]) -> Iterator[Path]:
    """``with file_root(path):`` the file blocks work in ``path``; leaving closes the files opened inside."""
    before, opened = _root, set(_files)
    set_file_root(path)
    try:
        assert _root is not None
        yield _root
    finally:
        for handle in set(_files) - opened:
            _files.pop(handle).close()
        set_file_root(before)


def close_files() -> None:
    """Close every file the file blocks opened (what a PLC restart does to them)."""
    for handle in list(_files):
        _files.pop(handle).close()


def sandbox_path(name: str) -> Path:
    """Where ``name`` (an sPathName) is in the sandbox; ``_AdsError`` when it is not allowed or no sandbox is set.

    Both ``/`` and ``\\`` separate folders. Absolute paths (``/x``, ``C:\\x``,
    ``\\\\server\\x``), ``..`` and symbolic links anywhere on the way are refused:
    nothing outside the folder is reached.
    """
    if _root is None:
        raise _AdsError(ADSERR_DEVICE_NOTFOUND)
    text = name.replace("\\", "/")
    if "\x00" in text:
        raise _AdsError(ADSERR_DEVICE_INVALIDPARM)
    if text.startswith("/") or (len(text) >= 2 and text[1] == ":"):
        raise _AdsError(ADSERR_DEVICE_INVALIDACCESS)
    parts = [part for part in text.split("/") if part not in ("", ".")]
    if not parts:
        raise _AdsError(ADSERR_DEVICE_NOTFOUND)
    if ".." in parts:
        raise _AdsError(ADSERR_DEVICE_INVALIDACCESS)
    path = _root
    for part in parts:
        path = path / part
        if path.is_symlink():
            raise _AdsError(ADSERR_DEVICE_INVALIDACCESS)
    if not os.path.realpath(path).startswith(str(_root) + os.sep):
        raise _AdsError(ADSERR_DEVICE_INVALIDACCESS)
    return path


def _os_error(exc: OSError) -> _AdsError:
    if isinstance(exc, FileNotFoundError | NotADirectoryError):
        return _AdsError(ADSERR_DEVICE_NOTFOUND)
    if isinstance(exc, FileExistsError):
        return _AdsError(ADSERR_DEVICE_EXISTS)
    if isinstance(exc, PermissionError | IsADirectoryError):
        return _AdsError(ADSERR_DEVICE_INVALIDACCESS)
    return _AdsError(ADSERR_DEVICE_ERROR)


_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_CHUNK = 65536
#: The most files the file blocks keep open at once; one more is refused with ADSERR_DEVICE_NOMEMORY.
MAX_OPEN_FILES = 256
_OPEN_FLAGS = {
    ("r", False): (os.O_RDONLY, "rb"),
    ("r", True): (os.O_RDWR, "r+b"),
    ("w", False): (os.O_WRONLY | os.O_CREAT | os.O_TRUNC, "wb"),
    ("w", True): (os.O_RDWR | os.O_CREAT | os.O_TRUNC, "w+b"),
    ("a", False): (os.O_WRONLY | os.O_CREAT | os.O_APPEND, "ab"),
    ("a", True): (os.O_RDWR | os.O_CREAT | os.O_APPEND, "a+b"),
}


def _open(name: str, mode: int) -> int:
    global _next_handle
    kinds = [letter for bit, letter in ((FOPEN_MODEREAD, "r"), (FOPEN_MODEWRITE, "w"), (FOPEN_MODEAPPEND, "a")) if mode & bit]
    if len(kinds) != 1:
        raise _AdsError(ADSERR_DEVICE_INVALIDPARM)
    flags, py_mode = _OPEN_FLAGS[(kinds[0], bool(mode & FOPEN_MODEPLUS))]
    path = sandbox_path(name)
    if len(_files) >= MAX_OPEN_FILES:
        raise _AdsError(ADSERR_DEVICE_NOMEMORY)
    try:
        # O_NOFOLLOW: a link put in place after the check is refused by the system, not followed.
        fd = os.open(path, flags | _NOFOLLOW, 0o666)
    except OSError as exc:
        raise _os_error(exc) from None
    if stat.S_ISDIR(os.fstat(fd).st_mode):
        os.close(fd)
        raise _AdsError(ADSERR_DEVICE_INVALIDACCESS)
    handle = _next_handle
    while True:
        handle = handle % 0xFFFF + 1  # hFile is a UINT and 0 is no file
        if handle not in _files:
            break
    _next_handle = handle
    _files[handle] = cast(BinaryIO, os.fdopen(fd, py_mode))
    return handle


def _file(handle: int) -> BinaryIO:
    found = _files.get(handle)
    if found is None:
        raise _AdsError(ADSERR_DEVICE_INVALIDPARM)
    return found


# --- files: the function blocks -----------------------------------------------------------------


class _FileRequest(FunctionBlock, abstract=True):
    """The ADS handshake the file blocks share.

    A rising edge of bExecute starts a request: bBusy is TRUE for that call.
    The next call carries it out (with the inputs of that call, as a PLC
    request is answered at a later cycle), sets bError / nErrId and drops
    bBusy. Edges while busy are ignored; the outputs stay until the next edge.
    No request takes longer than one cycle here, so tTimeout never expires.
    """

    sNetId: T_AmsNetId = VAR_INPUT("")
    bExecute: BOOL = VAR_INPUT(False)
    tTimeout: TIME = VAR_INPUT(DEFAULT_ADS_TIMEOUT)
    bBusy: BOOL = VAR_OUTPUT(False)
    bError: BOOL = VAR_OUTPUT(False)
    nErrId: UDINT = VAR_OUTPUT(0)
    PREV_EXECUTE: BOOL = VAR(False)

    def body(self) -> None:
        if self.bBusy:
            self.bBusy = False
            code = 0
            try:
                if self.sNetId not in ("", "127.0.0.1.1.1"):
                    raise _AdsError(ADSERR_TARGET_MACHINE_NOT_FOUND)
                self.run()
            except _AdsError as exc:
                code = exc.code
            except OSError as exc:
                code = _os_error(exc).code
            if code:
                self.failed()
            self.bError = code != 0
            self.nErrId = code
        elif self.bExecute and not self.PREV_EXECUTE:
            self.bBusy = True
            self.bError = False
            self.nErrId = 0
        self.PREV_EXECUTE = self.bExecute

    def run(self) -> None:
        """Carry the request out; raise ``_AdsError`` (or let an OSError through) on failure."""
        raise NotImplementedError

    def failed(self) -> None:
        """Put the block's own outputs in their state after an error."""


class FB_FileOpen(_FileRequest):
    """``FB_FileOpen``: open or create a file; hFile is its handle for the other file blocks.

    ST: ``VAR_INPUT sNetId : T_AmsNetId; sPathName : T_MaxString; nMode : DWORD;
    ePath : E_OpenPath := PATH_GENERIC; bExecute : BOOL; tTimeout : TIME; END_VAR
    VAR_OUTPUT bBusy, bError : BOOL; nErrId : UDINT; hFile : UINT; END_VAR``
    """

    sPathName: T_MaxString = VAR_INPUT("")
    nMode: DWORD = VAR_INPUT(0)
    ePath: E_OpenPath = VAR_INPUT(E_OpenPath.PATH_GENERIC)
    hFile: UINT = VAR_OUTPUT(0)

    def run(self) -> None:
        self.hFile = _open(self.sPathName, self.nMode)

    def failed(self) -> None:
        self.hFile = 0


class FB_FileClose(_FileRequest):
    """``FB_FileClose``: close the file hFile.

    ST: ``VAR_INPUT sNetId : T_AmsNetId; hFile : UINT; bExecute : BOOL; tTimeout : TIME; END_VAR``
    """

    hFile: UINT = VAR_INPUT(0)

    def run(self) -> None:
        _file(self.hFile)
        _files.pop(self.hFile).close()


class FB_FileDelete(_FileRequest):
    """``FB_FileDelete``: delete the file sPathName.

    ST: ``VAR_INPUT sNetId : T_AmsNetId; sPathName : T_MaxString; ePath : E_OpenPath; bExecute : BOOL; tTimeout : TIME; END_VAR``
    """

    sPathName: T_MaxString = VAR_INPUT("")
    ePath: E_OpenPath = VAR_INPUT(E_OpenPath.PATH_GENERIC)

    def run(self) -> None:
        path = sandbox_path(self.sPathName)
        if path.is_dir():
            raise _AdsError(ADSERR_DEVICE_INVALIDACCESS)
        path.unlink()


class E_SeekOrigin(IecEnum):  # noqa: N801 - the ST name
    """``E_SeekOrigin``: what FB_FileSeek's nSeekPos counts from."""

    SEEK_SET = 0
    SEEK_CUR = 1
    SEEK_END = 2


class FB_FileSeek(_FileRequest):
    """``FB_FileSeek``: set the file pointer of hFile to nSeekPos from eOrigin (start, current, end).

    ST: ``VAR_INPUT sNetId : T_AmsNetId; hFile : UINT; nSeekPos : DINT; eOrigin : E_SeekOrigin := SEEK_SET;
    bExecute : BOOL; tTimeout : TIME; END_VAR``; a position before the start is ADSERR_DEVICE_INVALIDPARM.
    """

    hFile: UINT = VAR_INPUT(0)
    nSeekPos: DINT = VAR_INPUT(0)
    eOrigin: E_SeekOrigin = VAR_INPUT(E_SeekOrigin.SEEK_SET)

    def run(self) -> None:
        file = _file(self.hFile)
        base = {E_SeekOrigin.SEEK_SET: 0, E_SeekOrigin.SEEK_CUR: file.tell(),
                E_SeekOrigin.SEEK_END: os.fstat(file.fileno()).st_size}.get(E_SeekOrigin(self.eOrigin))
        if base is None or base + self.nSeekPos < 0:
            raise _AdsError(ADSERR_DEVICE_INVALIDPARM)
        file.seek(base + self.nSeekPos)


class FB_FileTell(_FileRequest):
    """``FB_FileTell``: the file pointer of hFile, in nSeekPos (bytes from the start).

    ST: ``VAR_INPUT sNetId : T_AmsNetId; hFile : UINT; bExecute : BOOL; tTimeout : TIME; END_VAR
    VAR_OUTPUT ... nSeekPos : DINT; END_VAR``
    """

    hFile: UINT = VAR_INPUT(0)
    nSeekPos: DINT = VAR_OUTPUT(0)

    def run(self) -> None:
        self.nSeekPos = _file(self.hFile).tell()

    def failed(self) -> None:
        self.nSeekPos = -1


class FB_FileRename(_FileRequest):
    """``FB_FileRename``: rename the file sOldName to sNewName (both in the sandbox folder).

    ST: ``VAR_INPUT sNetId : T_AmsNetId; sOldName, sNewName : T_MaxString; ePath : E_OpenPath;
    bExecute : BOOL; tTimeout : TIME; END_VAR``; an existing sNewName is ADSERR_DEVICE_EXISTS.
    """

    sOldName: T_MaxString = VAR_INPUT("")
    sNewName: T_MaxString = VAR_INPUT("")
    ePath: E_OpenPath = VAR_INPUT(E_OpenPath.PATH_GENERIC)

    def run(self) -> None:
        old, new = sandbox_path(self.sOldName), sandbox_path(self.sNewName)
        if not old.is_file():
            raise _AdsError(ADSERR_DEVICE_NOTFOUND if not old.exists() else ADSERR_DEVICE_INVALIDACCESS)
        if os.path.lexists(new):
            raise _AdsError(ADSERR_DEVICE_EXISTS)
        old.rename(new)


class FB_CreateDir(_FileRequest):
    """``FB_CreateDir``: create the folder sPathName (its parent must exist).

    ST: ``VAR_INPUT sNetId : T_AmsNetId; sPathName : T_MaxString; ePath : E_OpenPath; bExecute : BOOL;
    tTimeout : TIME; END_VAR``
    """

    sPathName: T_MaxString = VAR_INPUT("")
    ePath: E_OpenPath = VAR_INPUT(E_OpenPath.PATH_GENERIC)

    def run(self) -> None:
        sandbox_path(self.sPathName).mkdir()


class FB_RemoveDir(_FileRequest):
    """``FB_RemoveDir``: remove the empty folder sPathName.

    ST: ``VAR_INPUT sNetId : T_AmsNetId; sPathName : T_MaxString; ePath : E_OpenPath; bExecute : BOOL;
    tTimeout : TIME; END_VAR``; a folder that is not empty is ADSERR_DEVICE_INVALIDACCESS.
    """

    sPathName: T_MaxString = VAR_INPUT("")
    ePath: E_OpenPath = VAR_INPUT(E_OpenPath.PATH_GENERIC)

    def run(self) -> None:
        path = sandbox_path(self.sPathName)
        if not path.is_dir():
            raise _AdsError(ADSERR_DEVICE_NOTFOUND if not path.exists() else ADSERR_DEVICE_INVALIDACCESS)
        try:
            path.rmdir()
        except OSError as exc:  # not empty
            raise _AdsError(ADSERR_DEVICE_INVALIDACCESS) from exc


class FB_FileRead(_FileRequest):
    """``FB_FileRead``: read up to cbReadLen bytes of hFile into the buffer at pReadBuff.

    ST: ``VAR_INPUT ... hFile : UINT; pReadBuff : PVOID; cbReadLen : UDINT; ... END_VAR
    VAR_OUTPUT ... cbRead : UDINT; bEOF : BOOL; END_VAR`` (bEOF: fewer bytes than asked were left).
    """

    hFile: UINT = VAR_INPUT(0)
    pReadBuff: Pointer[Any] = VAR_INPUT()
    cbReadLen: UDINT = VAR_INPUT(0)
    cbRead: UDINT = VAR_OUTPUT(0)
    bEOF: BOOL = VAR_OUTPUT(False)

    def run(self) -> None:
        file = _file(self.hFile)
        if not self.pReadBuff:
            raise _AdsError(ADSERR_DEVICE_INVALIDPARM)
        target = self.pReadBuff.typed(BYTE)
        done = 0
        # In chunks, so a huge cbReadLen costs no more memory than a chunk; a buffer
        # smaller than cbReadLen faults at its end (RTSEXCPT_ACCESS_VIOLATION), as on the PLC.
        while done < self.cbReadLen:
            data = file.read(min(self.cbReadLen - done, _CHUNK))
            if not data:
                break
            for i, value in enumerate(data, done):
                (target + i).deref = value
            done += len(data)
        self.cbRead = done
        self.bEOF = done < self.cbReadLen

    def failed(self) -> None:
        self.cbRead = 0


class FB_FileWrite(_FileRequest):
    """``FB_FileWrite``: write cbWriteLen bytes from the buffer at pWriteBuff to hFile.

    ST: ``VAR_INPUT ... hFile : UINT; pWriteBuff : PVOID; cbWriteLen : UDINT; ... END_VAR
    VAR_OUTPUT ... cbWrite : UDINT; END_VAR``
    """

    hFile: UINT = VAR_INPUT(0)
    pWriteBuff: Pointer[Any] = VAR_INPUT()
    cbWriteLen: UDINT = VAR_INPUT(0)
    cbWrite: UDINT = VAR_OUTPUT(0)

    def run(self) -> None:
        file = _file(self.hFile)
        if not self.pWriteBuff:
            raise _AdsError(ADSERR_DEVICE_INVALIDPARM)
        source = self.pWriteBuff.typed(BYTE)
        data = bytes((source + i).deref for i in range(self.cbWriteLen))
        self.cbWrite = file.write(data)
        file.flush()

    def failed(self) -> None:
        self.cbWrite = 0


class FB_FileGets(_FileRequest):
    """``FB_FileGets``: read one line of hFile, its line feed included (at most 255 characters).

    ST: ``VAR_INPUT sNetId; hFile : UINT; bExecute; tTimeout; END_VAR
    VAR_OUTPUT bBusy, bError; nErrId; sLine : T_MaxString; bEOF : BOOL; END_VAR``
    """

    hFile: UINT = VAR_INPUT(0)
    sLine: T_MaxString = VAR_OUTPUT("")
    bEOF: BOOL = VAR_OUTPUT(False)

    def run(self) -> None:
        data = _file(self.hFile).readline(MAX_STRING_LENGTH)
        self.sLine = data.decode("latin-1")
        self.bEOF = not data

    def failed(self) -> None:
        self.sLine = ""


class FB_FilePuts(_FileRequest):
    """``FB_FilePuts``: write sLine to hFile (without its terminating null; add '$N' for a line feed).

    ST: ``VAR_INPUT sNetId; hFile : UINT; sLine : T_MaxString; bExecute; tTimeout; END_VAR``
    """

    hFile: UINT = VAR_INPUT(0)
    sLine: T_MaxString = VAR_INPUT("")

    def run(self) -> None:
        file = _file(self.hFile)
        file.write(self.sLine.encode("latin-1"))
        file.flush()
