"""An ADS server for a running Runtime: pyads scripts, HMIs and SCADA talk to the simulated PLC as to TwinCAT.

TwinCAT 3's PLC runtime answers ADS on AMS port 851 behind the AMS router
(TCP port 48898). ``AdsServer`` is that endpoint for an iecoop ``Runtime``::

    with AdsServer(rt, port=48898):                 # pyads.Connection("127.0.0.1.1.1", 851, "127.0.0.1")
        rt.run(duration=T("1h"), realtime=True)

One thread serves every client. After every cycle the PLC thread copies the
served blocks in one go; reads, sum reads and notifications are answered
from the last copy, so what a client sees is always one whole cycle. A
write is checked at once (a refusal stores nothing and answers an ADS
error code), queued, and stored at the start of the next cycle; a sum write
is stored whole in one cycle or not at all.
"""

from __future__ import annotations

import collections
import contextlib
import ctypes
import dataclasses
import itertools
import logging
import operator
import selectors
import socket
import struct
import threading
import time
from collections.abc import Callable, Iterable
from types import TracebackType
from typing import Any

from iecoop.ads.protocol import (
    AMS_TCP_PORT, REQUEST, AdsError, AdsState, AmsHeader, Command, IndexGroup, TransMode, net_id_bytes, split_frames,
)
from iecoop.ads.symbols import AdsSymbol, Refused, SymbolTable
from iecoop.exceptions import AccessError
from iecoop.runtime import Runtime, Symbol

__all__ = ["AdsServer"]

_log = logging.getLogger(__name__)
_RAW = operator.attrgetter("raw")
_U32 = struct.Struct("<I")
_U32X2 = struct.Struct("<II")
_U32X3 = struct.Struct("<III")
_U32X4 = struct.Struct("<IIII")
_NOTE = struct.Struct("<IIIIII")
#: The largest AMS packet a client may send, and the most a client may leave unread before it is dropped.
_MAX_PACKET = 4 * 1024 * 1024
_MAX_BACKLOG = 16 * 1024 * 1024
#: Handles and notifications one connection may hold (TwinCAT answers NOMOREHDLS beyond its own limit).
_MAX_HANDLES = 100_000
#: 100 ns intervals between 1601-01-01 (FILETIME) and 1970-01-01.
_FILETIME_EPOCH = 116_444_736_000_000_000

Image = tuple[tuple[bytes, ...], int]  # the blocks' bytes, the FILETIME of the cycle's end
#: One change a request makes, done by the PLC's thread at the next cycle start: a store, a force, a release.
Change = tuple[Callable[[Symbol, Any], None], Symbol, Any]


def _store(symbol: Symbol, value: Any) -> None:
    symbol.info.store(symbol.block, symbol.offset, value, symbol.path)


@dataclasses.dataclass(eq=False)
class _Notification:
    client: _Client
    header: AmsHeader  # the AddDeviceNotification request: where samples go
    root: int
    offset: int
    size: int
    mode: int
    period_ns: int
    last: bytes | None = None
    due: float = 0.0  # when a cyclic sample is due (time.monotonic)
    seen: int = 0  # the stamp of the image last looked at for a change


@dataclasses.dataclass(eq=False)
class _Client:
    sock: socket.socket
    peer: str
    inbox: bytearray = dataclasses.field(default_factory=bytearray)
    outbox: bytearray = dataclasses.field(default_factory=bytearray)
    handles: dict[int, AdsSymbol] = dataclasses.field(default_factory=dict)
    notes: dict[int, _Notification] = dataclasses.field(default_factory=dict)


class AdsServer:
    """An ADS endpoint for ``runtime`` (TwinCAT 3's PLC on AMS port 851), in a background thread.

    ``port`` is the TCP port (48898, the AMS router's, by default; 0 picks a
    free one, which ``.port`` then names) on ``host`` (127.0.0.1: this
    machine only). ``net_id`` is the AMS Net ID a client addresses,
    ``ams_port`` the PLC's AMS port. ``writable`` adds variables a client
    may write, as symbol names or ``fnmatch`` patterns (``"MAIN.fbAxis.*"``);
    a program's VAR_INPUTs and the GVLs' variables are writable already.
    ``online=True`` gives clients TwinCAT's online write and force: every
    variable but a CONSTANT is writable, and ``IndexGroup.FORCE_BYHND`` /
    ``RELEASE_BYHND`` force and release by handle, as ``rt.force`` does.
    Use it as a context manager.
    """

    def __init__(
        self,
        runtime: Runtime,
        port: int = AMS_TCP_PORT,
        *,
        host: str = "127.0.0.1",
        net_id: str = "127.0.0.1.1.1",
        ams_port: int = 851,
        writable: Iterable[str] = (),
        online: bool = False,
        name: str = "iecoop",
    ) -> None:
        self.runtime = runtime
        self.online = online
        self.host = host
        self.port = port
        self.net_id = net_id
        self._net_id = net_id_bytes(net_id)
        self.ams_port = ams_port
        self._name = name.encode("latin-1", "replace")[:15]
        self.symbols = SymbolTable(runtime, writable, online)
        blocks = [root.block for root in self.symbols.roots]
        self._blocks = blocks
        # A byte view of each served block: `.raw` copies it in one C call (the whole per-cycle cost).
        self._views = [(ctypes.c_char * ctypes.sizeof(b)).from_buffer(b) for b in blocks]
        self._image: Image = (self._capture(), _filetime())
        self._pending: collections.deque[list[Change]] = collections.deque()
        self._notified = False  # a notification exists: the cycle end wakes the server
        self._fault: object = None  # the fault the image was last refreshed for
        self._handles = itertools.count(1)
        self._thread: threading.Thread | None = None
        self._selector: selectors.BaseSelector | None = None
        self._listener: socket.socket | None = None
        self._wake_r: socket.socket | None = None
        self._wake_w: socket.socket | None = None
        self._stopping = False
        self._clients: list[_Client] = []
        self._commands: dict[int, Callable[[_Client, AmsHeader, bytes], bytes]] = {
            Command.READ_DEVICE_INFO: self._device_info,
            Command.READ: self._read_command,
            Command.WRITE: self._write_command,
            Command.READ_STATE: self._read_state,
            Command.WRITE_CONTROL: self._write_control,
            Command.ADD_DEVICE_NOTIFICATION: self._add_notification,
            Command.DELETE_DEVICE_NOTIFICATION: self._delete_notification,
            Command.READ_WRITE: self._read_write_command,
        }

    # -- the PLC thread ----------------------------------------------------------

    def _capture(self) -> tuple[bytes, ...]:
        return tuple(map(_RAW, self._views))

    def _cycle_end(self) -> None:
        """After every cycle: one copy of the served blocks, the image every answer comes from."""
        self._image = (self._capture(), _filetime())
        if self._notified:
            self._wake()

    def _cycle_start(self) -> None:
        """Before every cycle: the writes taken since the last one, each request's whole, in the order they came."""
        pending = self._pending
        while pending:
            for change, symbol, value in pending.popleft():
                change(symbol, value)

    def _release(self, symbol: Symbol, restore: bool) -> None:
        with contextlib.suppress(AccessError):  # a member that is not forced: nothing to release
            self.runtime.release(symbol, restore=restore)

    # -- start and stop ----------------------------------------------------------

    def start(self) -> None:
        """Listen and serve (``__enter__`` calls it); OSError if the port is taken."""
        if self._thread is not None:
            raise RuntimeError("AdsServer: already started")
        listener = socket.create_server((self.host, self.port), reuse_port=False)
        listener.setblocking(False)
        self.port = listener.getsockname()[1]
        self._listener = listener
        self._wake_r, self._wake_w = socket.socketpair()
        self._wake_r.setblocking(False)
        self._selector = selectors.DefaultSelector()
        self._selector.register(listener, selectors.EVENT_READ, None)
        self._selector.register(self._wake_r, selectors.EVENT_READ, None)
        self._stopping = False
        self._image = (self._capture(), _filetime())
        self._thread = threading.Thread(target=self._serve, name=f"iecoop ADS {self.host}:{self.port}", daemon=True)
        self._thread.start()
        self.runtime.on_cycle_start.append(self._cycle_start)
        self.runtime.on_cycle_end.append(self._cycle_end)

    def stop(self) -> None:
        """Stop serving, close every connection and the port (``__exit__`` calls it); queued writes are dropped."""
        for hooks, hook in ((self.runtime.on_cycle_start, self._cycle_start), (self.runtime.on_cycle_end, self._cycle_end)):
            if hook in hooks:
                hooks.remove(hook)
        thread, self._thread = self._thread, None
        if thread is None:
            return
        self._stopping = True
        self._wake()
        thread.join()
        self._pending.clear()

    def __enter__(self) -> AdsServer:
        self.start()
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.stop()

    def __repr__(self) -> str:
        state = "serving" if self._thread is not None else "stopped"
        return f"<AdsServer {self.net_id}:{self.ams_port} on {self.host}:{self.port} {state}>"

    def _wake(self) -> None:
        wake = self._wake_w
        if wake is not None:
            try:
                wake.send(b"\x00")
            except (BlockingIOError, OSError):
                pass  # a wake-up is pending already, or the server is closing

    # -- the server thread ---------------------------------------------------------

    def _serve(self) -> None:
        selector = self._selector
        assert selector is not None
        try:
            while not self._stopping:
                for key, events in selector.select(self._timeout()):
                    if key.fileobj is self._listener:
                        self._accept()
                    elif key.fileobj is self._wake_r:
                        self._drain_wake()
                    else:
                        client: _Client = key.data
                        if events & selectors.EVENT_READ:
                            self._receive(client)
                        if events & selectors.EVENT_WRITE and client in self._clients:
                            self._flush(client)
                self._notify()
        except Exception:  # the server must never die silently: say why, then close down
            _log.exception("ADS server failed")
        finally:
            for client in list(self._clients):
                self._drop(client)
            for sock in (self._listener, self._wake_r, self._wake_w):
                if sock is not None:
                    sock.close()
            selector.close()
            self._listener = self._wake_r = self._wake_w = None
            self._selector = None

    def _timeout(self) -> float | None:
        dues = [note.due for client in self._clients for note in client.notes.values()
                if note.mode == TransMode.SERVERCYCLE]
        return max(0.0, min(dues) - time.monotonic()) if dues else None

    def _drain_wake(self) -> None:
        assert self._wake_r is not None
        try:
            while self._wake_r.recv(4096):
                pass
        except BlockingIOError:
            pass

    def _accept(self) -> None:
        assert self._listener is not None and self._selector is not None
        try:
            sock, address = self._listener.accept()
        except BlockingIOError:
            return
        sock.setblocking(False)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        client = _Client(sock, f"{address[0]}:{address[1]}")
        self._clients.append(client)
        self._selector.register(sock, selectors.EVENT_READ, client)

    def _drop(self, client: _Client) -> None:
        if client in self._clients:
            self._clients.remove(client)
        self._notified = any(c.notes for c in self._clients)
        if self._selector is not None:
            try:
                self._selector.unregister(client.sock)
            except (KeyError, ValueError):
                pass
        client.sock.close()

    def _receive(self, client: _Client) -> None:
        try:
            data = client.sock.recv(65536)
        except BlockingIOError:
            return
        except OSError:
            data = b""
        if not data:
            self._drop(client)
            return
        client.inbox += data
        try:
            packets = split_frames(client.inbox, _MAX_PACKET)
        except ValueError as exc:
            _log.warning("ADS client %s dropped: %s", client.peer, exc)
            self._drop(client)
            return
        for packet in packets:
            self._answer(client, packet)

    def _send(self, client: _Client, frame: bytes) -> None:
        if client not in self._clients:
            return
        client.outbox += frame
        if len(client.outbox) > _MAX_BACKLOG:
            _log.warning("ADS client %s dropped: it leaves its answers unread", client.peer)
            self._drop(client)
            return
        self._flush(client)

    def _flush(self, client: _Client) -> None:
        assert self._selector is not None
        try:
            sent = client.sock.send(client.outbox)
        except BlockingIOError:
            sent = 0
        except OSError:
            self._drop(client)
            return
        del client.outbox[:sent]
        self._selector.modify(client.sock, selectors.EVENT_READ | (selectors.EVENT_WRITE if client.outbox else 0), client)

    def _answer(self, client: _Client, packet: bytes) -> None:
        fault = self.runtime.fault
        if fault is not None and fault is not self._fault:
            # A faulted cycle has no cycle end: the PLC stands still where it stopped, which clients then read.
            self._fault, self._image = fault, (self._capture(), _filetime())
        header = AmsHeader.parse(packet)
        if header.flags & 0x0001:
            return  # a response: the server sends no requests that would have one
        data = packet[AmsHeader.SIZE : AmsHeader.SIZE + header.length]
        handler = self._commands.get(header.command)
        if header.target_port != self.ams_port:
            answer, error = b"", int(AdsError.TARGET_PORT_NOT_FOUND)
        elif handler is None:
            answer, error = b"", int(AdsError.UNKNOWN_COMMAND)
        else:
            try:
                answer, error = handler(client, header, data), 0
            except struct.error:
                answer, error = _U32.pack(AdsError.INVALIDSIZE) + b"\x00" * 4, 0
        reply = header.reply(len(answer))
        self._send(client, dataclasses.replace(reply, error=error).frame(answer))

    # -- the commands ----------------------------------------------------------------

    def _device_info(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        # TwinCAT 3.1 build 4024, the PLC's name
        return struct.pack("<IBBH16s", 0, 3, 1, 4024, self._name)

    def _read_state(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        state = AdsState.RUN if self.runtime.fault is None else AdsState.STOP
        return struct.pack("<IHH", 0, state, 0)

    def _write_control(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        # Starting and stopping the PLC is the runtime owner's: a client cannot.
        return _U32.pack(AdsError.SRVNOTSUPP)

    def _read_command(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        group, offset, length = _U32X3.unpack_from(data)
        try:
            value = self._read(client, group, offset, length, self._image[0])
        except Refused as refusal:
            return self._refuse(client, refusal)
        return _U32X2.pack(0, len(value)) + value

    def _write_command(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        group, offset, length = _U32X3.unpack_from(data)
        value = data[12 : 12 + length]
        try:
            if len(value) != length:
                raise Refused(AdsError.INVALIDSIZE, f"a write of {length} bytes carries {len(value)}")
            stores = self._write(client, group, offset, value)
        except Refused as refusal:
            return self._refuse(client, refusal, 4)
        if stores:
            self._pending.append(stores)
        return _U32.pack(0)

    def _read_write_command(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        group, offset, read_length, write_length = _U32X4.unpack_from(data)
        value = data[16 : 16 + write_length]
        try:
            if len(value) != write_length:
                raise Refused(AdsError.INVALIDSIZE, f"a request of {write_length} bytes carries {len(value)}")
            answer = self._read_write(client, group, offset, read_length, value)
        except Refused as refusal:
            return self._refuse(client, refusal)
        return _U32X2.pack(0, len(answer)) + answer

    @staticmethod
    def _refuse(client: _Client, refusal: Refused, size: int = 8) -> bytes:
        _log.info("ADS request of %s refused (%s): %s", client.peer, refusal.code.name, refusal)
        return _U32.pack(refusal.code) + b"\x00" * (size - 4)

    # -- reads and writes ---------------------------------------------------------------

    def _read(self, client: _Client, group: int, offset: int, length: int, image: tuple[bytes, ...]) -> bytes:
        if group == IndexGroup.SYM_VALBYHND:
            return self._value(self._handle(client, offset), length, image)
        if group == IndexGroup.PLC_DATA:
            root, inner = self.symbols.locate(offset, length)
            return image[root][inner : inner + length]
        if group == IndexGroup.SYM_UPLOADINFO2:
            info = struct.pack("<IIIIII", len(self.symbols.top), len(self.symbols.upload()), 0, 0, 0, 0)
            return info[:length]
        if group == IndexGroup.SYM_UPLOADINFO:
            return _U32X2.pack(len(self.symbols.top), len(self.symbols.upload()))[:length]
        if group == IndexGroup.SYM_UPLOAD:
            return self.symbols.upload()[:length]
        raise Refused(AdsError.INVALIDGRP, f"index group {group:#x} cannot be read")

    @staticmethod
    def _value(symbol: AdsSymbol, length: int, image: tuple[bytes, ...]) -> bytes:
        # As TwinCAT does: a read asking for more than the variable holds gets the variable (pyads reads a
        # STRING into a 1 kB buffer).
        size = min(length, symbol.size)
        return image[symbol.root][symbol.block_offset : symbol.block_offset + size]

    def _write(self, client: _Client, group: int, offset: int, value: bytes) -> list[Change]:
        """The checked changes of one write (none for a handle's release); Refused if the PLC does not take it."""
        if group in (IndexGroup.FORCE_BYHND, IndexGroup.RELEASE_BYHND):
            return self._force(client, group, offset, value)
        if group == IndexGroup.SYM_VALBYHND:
            symbol = self._handle(client, offset)
        elif group == IndexGroup.PLC_DATA:
            symbol = self.symbols.at(offset, len(value))
        elif group == IndexGroup.SYM_RELEASEHND:
            handle = _U32.unpack(value)[0] if len(value) == 4 else offset
            if client.handles.pop(handle, None) is None:
                raise Refused(AdsError.SYMBOLNOTFOUND, f"handle {handle} is not one of this connection's")
            return []
        else:
            raise Refused(AdsError.INVALIDGRP, f"index group {group:#x} cannot be written")
        return [(_store, leaf, data) for leaf, data in symbol.decode(value, self._blocks[symbol.root])]

    def _force(self, client: _Client, group: int, handle: int, value: bytes) -> list[Change]:
        """A force (the value's bytes) or a release (one byte: 1 restores) of the variable of ``handle``."""
        if not self.online:
            raise Refused(AdsError.ACCESSDENIED, "forcing over ADS is off; AdsServer(..., online=True) turns it on")
        symbol = self._handle(client, handle)
        block = self._blocks[symbol.root]
        if group == IndexGroup.FORCE_BYHND:
            return [(self.runtime.force, leaf, data) for leaf, data in symbol.decode(value, block)]
        if len(value) != 1 or value[0] > 1:
            raise Refused(AdsError.INVALIDDATA, "a release is one byte: 0 keeps the forced value, 1 restores the old one")
        restore = value == b"\x01"
        return [(self._release, leaf, restore) for leaf in symbol.leaves(block)]

    def _handle(self, client: _Client, handle: int) -> AdsSymbol:
        symbol = client.handles.get(handle)
        if symbol is None:
            raise Refused(AdsError.SYMBOLNOTFOUND, f"handle {handle} is not one of this connection's")
        return symbol

    def _read_write(self, client: _Client, group: int, offset: int, length: int, value: bytes) -> bytes:
        if group in (IndexGroup.SYM_HNDBYNAME, IndexGroup.SYM_INFOBYNAMEEX, IndexGroup.SYM_VALBYNAME):
            symbol = self.symbols.find(value.split(b"\x00", 1)[0].decode("latin-1"))
            if group == IndexGroup.SYM_INFOBYNAMEEX:
                return symbol.entry()[:length]
            if group == IndexGroup.SYM_VALBYNAME:
                return self._value(symbol, min(length, symbol.size), self._image[0])
            if len(client.handles) >= _MAX_HANDLES:
                raise Refused(AdsError.NOMOREHDLS, f"this connection holds {_MAX_HANDLES} handles already")
            handle = next(self._handles)
            client.handles[handle] = symbol
            return _U32.pack(handle)
        if group == IndexGroup.SUMUP_READ:
            return self._sum_read(client, offset, value)
        if group == IndexGroup.SUMUP_WRITE:
            return self._sum_write(client, offset, value)
        raise Refused(AdsError.INVALIDGRP, f"index group {group:#x} takes no read-write request")

    def _requests(self, count: int, value: bytes) -> list[tuple[int, int, int]]:
        if len(value) < 12 * count:
            raise Refused(AdsError.INVALIDSIZE, f"a sum request of {count} sub-requests carries {len(value)} bytes")
        return [_U32X3.unpack_from(value, 12 * i) for i in range(count)]

    def _sum_read(self, client: _Client, count: int, value: bytes) -> bytes:
        image = self._image[0]  # one cycle's values for every sub-read
        codes, parts = [], []
        for group, offset, length in self._requests(count, value):
            try:
                data = self._read(client, group, offset, length, image)
                codes.append(0)
                parts.append(data + b"\x00" * (length - len(data)))
            except Refused as refusal:
                codes.append(int(refusal.code))
                parts.append(b"\x00" * length)
        return struct.pack(f"<{count}I", *codes) + b"".join(parts)

    def _sum_write(self, client: _Client, count: int, value: bytes) -> bytes:
        requests = self._requests(count, value)
        position = 12 * count
        codes: list[int] = []
        batch: list[Change] = []
        for group, offset, length in requests:
            data = value[position : position + length]
            position += length
            try:
                if len(data) != length:
                    raise Refused(AdsError.INVALIDSIZE, f"a sub-write of {length} bytes carries {len(data)}")
                if group == IndexGroup.SYM_RELEASEHND:
                    self._write(client, group, offset, data)
                else:
                    batch += self._write(client, group, offset, data)
                codes.append(0)
            except Refused as refusal:
                _log.info("ADS sum write of %s: a sub-write refused (%s): %s", client.peer, refusal.code.name, refusal)
                codes.append(int(refusal.code))
        if any(codes):
            # Nothing half-written: the sub-writes that were fine are not stored either, and say so.
            codes = [code or int(AdsError.ABORTED) for code in codes]
        elif batch:
            self._pending.append(batch)
        return struct.pack(f"<{count}I", *codes)

    # -- notifications ------------------------------------------------------------------

    def _add_notification(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        group, offset, length, mode, _max_delay, cycle = _NOTE.unpack_from(data)
        try:
            if mode not in (TransMode.SERVERCYCLE, TransMode.SERVERONCHA):
                raise Refused(AdsError.INVALIDPARM, f"transmission mode {mode} (the server sends on change, 4, "
                                                    "or cyclically, 3)")
            if group == IndexGroup.SYM_VALBYHND:
                symbol = self._handle(client, offset)
                self._value(symbol, length, self._image[0])
                root, inner = symbol.root, symbol.block_offset
            elif group == IndexGroup.PLC_DATA:
                root, inner = self.symbols.locate(offset, length)
            else:
                raise Refused(AdsError.INVALIDGRP, f"index group {group:#x} sends no notifications")
            if len(client.notes) >= _MAX_HANDLES:
                raise Refused(AdsError.NOMOREHDLS, f"this connection holds {_MAX_HANDLES} notifications already")
        except Refused as refusal:
            return self._refuse(client, refusal)
        handle = next(self._handles)
        # The cycle time is in 100 ns units; a cyclic notification is sent at most once a millisecond.
        period = max(cycle * 100, 1_000_000)
        due = time.monotonic() + period / 1e9
        client.notes[handle] = _Notification(client, header, root, inner, length, mode, period, due=due,
                                             seen=self._image[1])
        self._notified = True
        return _U32X2.pack(0, handle)

    def _delete_notification(self, client: _Client, header: AmsHeader, data: bytes) -> bytes:
        handle = _U32.unpack_from(data)[0]
        if client.notes.pop(handle, None) is None:
            return self._refuse(client, Refused(AdsError.NOTIFYHNDINVALID, f"no notification {handle}"), 4)
        self._notified = any(c.notes for c in self._clients)
        return _U32.pack(0)

    def _notify(self) -> None:
        """Send the samples that are due: changed values, cyclic ones whose period is up (the first one at once)."""
        if not self._notified:
            return
        blocks, stamp = self._image
        now = time.monotonic()
        for client in list(self._clients):
            samples: dict[tuple[bytes, int, bytes, int], list[bytes]] = {}
            for handle, note in client.notes.items():
                value = blocks[note.root][note.offset : note.offset + note.size]
                if note.mode == TransMode.SERVERCYCLE:
                    if now < note.due:
                        continue
                    note.due = max(note.due + note.period_ns / 1e9, now)
                else:
                    # Changes are looked for once per cycle image: the first sample of a new notification
                    # goes with the next cycle, by when the client has its handle and listens for it.
                    fresh, note.seen = stamp != note.seen, stamp
                    if not fresh or value == note.last:
                        continue
                note.last = value
                h = note.header
                key = (h.source_net_id, h.source_port, h.target_net_id, h.target_port)
                samples.setdefault(key, []).append(_U32X2.pack(handle, len(value)) + value)
            for (net_id, port, source_id, source_port), found in samples.items():
                stamp_header = struct.pack("<QI", stamp, len(found)) + b"".join(found)
                stream = _U32X2.pack(len(stamp_header) + 4, 1) + stamp_header
                header = AmsHeader(net_id, port, source_id, source_port, Command.DEVICE_NOTIFICATION, REQUEST, 0, 0, 0)
                self._send(client, header.frame(stream))


def _filetime() -> int:
    """Now as a Windows FILETIME (100 ns since 1601), the time stamp of ADS notifications."""
    return time.time_ns() // 100 + _FILETIME_EPOCH
