"""The AMS/TCP framing and the ADS commands, index groups and error codes iecoop's server speaks.

Beckhoff documents the protocol in the TwinCAT 3 ADS specification
(Infosys: *TC3 ADS Overview > Specification > ADS-TCP*, *ADS Commands*,
*ADS Return Codes*; *TE1000 > ADS symbol index groups*). All integers are
little-endian. A frame is a 6-byte AMS/TCP header (two reserved bytes, the
length of what follows) and a 32-byte AMS header:

=========  =====  ==========================================================
field      bytes
=========  =====  ==========================================================
target     6 + 2  AMS Net ID and port of the receiver
source     6 + 2  AMS Net ID and port of the sender
command    2      ``Command`` (Read = 2, ...)
flags      2      0x0004 a request, 0x0005 a response (ADS command, TCP)
length     4      the bytes of ADS data after the header
error      4      an AMS-level error (0); ADS results are in the data
invoke id  4      matches a response to its request
=========  =====  ==========================================================

>>> header = AmsHeader(b"\\x7f\\x00\\x00\\x01\\x01\\x01", 851, b"\\x0a\\x00\\x00\\x02\\x01\\x01", 32905,
...                    Command.READ_STATE, REQUEST, 0, 0, 7)
>>> frame = header.frame(b"")
>>> len(frame), AmsHeader.parse(frame[6:]).invoke_id
(38, 7)
"""

from __future__ import annotations

import dataclasses
import enum
import struct

__all__ = [
    "AMS_TCP_PORT", "AdsError", "AdsState", "AmsHeader", "Command", "IndexGroup", "REQUEST", "RESPONSE",
    "TransMode", "net_id_bytes", "net_id_text", "split_frames",
]

#: The TCP port of the AMS router (0xBF02): where pyads and TwinCAT look for a target.
AMS_TCP_PORT = 48898
#: AMS state flags: an ADS command over TCP, as a request and as its response.
REQUEST = 0x0004
RESPONSE = 0x0005

_HEADER = struct.Struct("<6sH6sHHHIII")
_TCP = struct.Struct("<HI")


class Command(enum.IntEnum):
    """ADS command ids (the AMS header's command field)."""

    READ_DEVICE_INFO = 1
    READ = 2
    WRITE = 3
    READ_STATE = 4
    WRITE_CONTROL = 5
    ADD_DEVICE_NOTIFICATION = 6
    DELETE_DEVICE_NOTIFICATION = 7
    DEVICE_NOTIFICATION = 8
    READ_WRITE = 9


class IndexGroup(enum.IntEnum):
    """The index groups the server answers (TwinCAT 3 PLC runtime, port 851)."""

    #: the PLC's data area: a symbol's index offset is its address in it
    PLC_DATA = 0x4040
    SYM_HNDBYNAME = 0xF003
    SYM_VALBYNAME = 0xF004
    SYM_VALBYHND = 0xF005
    SYM_RELEASEHND = 0xF006
    SYM_INFOBYNAMEEX = 0xF009
    SYM_UPLOAD = 0xF00B
    SYM_UPLOADINFO = 0xF00C
    SYM_UPLOADINFO2 = 0xF00F
    SUMUP_READ = 0xF080
    SUMUP_WRITE = 0xF081
    #: iecoop's own, with ``AdsServer(online=True)``: a write of a value to a handle forces the variable; a
    #: write of one byte to a handle releases it (1: and restores its value from before the force).
    #: TwinCAT's engineering forces through services of its own, not through a documented index group.
    FORCE_BYHND = 0x4F10
    RELEASE_BYHND = 0x4F11


class AdsError(enum.IntEnum):
    """ADS return codes (Infosys: *ADS Return Codes*) the server answers with."""

    NO_ERROR = 0
    #: AMS-level errors: no server on the target port; the command id is not known
    TARGET_PORT_NOT_FOUND = 0x6
    UNKNOWN_COMMAND = 0x8
    SRVNOTSUPP = 0x701
    INVALIDGRP = 0x702
    INVALIDOFFSET = 0x703
    INVALIDACCESS = 0x704
    INVALIDSIZE = 0x705
    INVALIDDATA = 0x706
    INVALIDPARM = 0x70B
    SYMBOLNOTFOUND = 0x710
    NOTIFYHNDINVALID = 0x714
    NOMOREHDLS = 0x716
    ABORTED = 0x71F
    ACCESSDENIED = 0x723


class AdsState(enum.IntEnum):
    """ADS states (``ADSSTATE_*``) a PLC reports."""

    RUN = 5
    STOP = 6
    ERROR = 11


class TransMode(enum.IntEnum):
    """When a device notification is sent (``ADSTRANS_*``)."""

    SERVERCYCLE = 3
    SERVERONCHA = 4


def net_id_bytes(text: str) -> bytes:
    """``"127.0.0.1.1.1"`` as the 6 bytes of an AMS Net ID; ValueError for anything else."""
    parts = text.split(".")
    try:
        numbers = [int(part) for part in parts]
    except ValueError:
        numbers = []
    if len(numbers) != 6 or not all(0 <= n <= 255 for n in numbers):
        raise ValueError(f"an AMS Net ID is six numbers 0..255 joined by dots (127.0.0.1.1.1), got {text!r}")
    return bytes(numbers)


def net_id_text(data: bytes) -> str:
    """The 6 bytes of an AMS Net ID as text."""
    return ".".join(map(str, data))


@dataclasses.dataclass(frozen=True)
class AmsHeader:
    """The 32-byte AMS header of one frame."""

    target_net_id: bytes
    target_port: int
    source_net_id: bytes
    source_port: int
    command: int
    flags: int
    length: int
    error: int
    invoke_id: int

    SIZE = _HEADER.size

    @classmethod
    def parse(cls, data: bytes) -> AmsHeader:
        """The header at the start of ``data`` (an AMS packet without its AMS/TCP header)."""
        return cls(*_HEADER.unpack_from(data))

    def reply(self, length: int) -> AmsHeader:
        """The header of the response to this request: the addresses swapped, the same command and invoke id."""
        return AmsHeader(self.source_net_id, self.source_port, self.target_net_id, self.target_port,
                         self.command, RESPONSE, length, 0, self.invoke_id)

    def frame(self, data: bytes) -> bytes:
        """The whole AMS/TCP frame of this header (its length set to ``data``'s) and ``data``."""
        header = _HEADER.pack(self.target_net_id, self.target_port, self.source_net_id, self.source_port,
                              self.command, self.flags, len(data), self.error, self.invoke_id)
        return _TCP.pack(0, len(header) + len(data)) + header + data


def split_frames(buffer: bytearray, limit: int) -> list[bytes]:
    """Take the complete AMS packets (header and data, without the AMS/TCP header) off the front of ``buffer``.

    ValueError for a frame longer than ``limit`` bytes or one too short to
    hold an AMS header: the stream cannot be trusted after it.
    """
    packets = []
    while len(buffer) >= _TCP.size:
        _reserved, length = _TCP.unpack_from(buffer)
        if length > limit or length < _HEADER.size:
            raise ValueError(f"an AMS/TCP frame of {length} bytes (an AMS packet is {_HEADER.size}..{limit})")
        end = _TCP.size + length
        if len(buffer) < end:
            break
        packets.append(bytes(buffer[_TCP.size : end]))
        del buffer[:end]
    return packets
