r"""The remanent-data store: RETAIN and PERSISTENT images that survive a crash.

A PLC keeps two kinds of remanent data (Beckhoff InfoSys, TwinCAT 3 "Remanent
data"; CODESYS Online Help "Remanent Variables - RETAIN, PERSISTENT"): the
RETAIN image, written at the end of **every** cycle (TwinCAT's retain handler
on NOV-RAM), and the PERSISTENT image, written on stop or on demand (TwinCAT's
``Port_851.bootdata`` with ``.bootdata-old``, ``FB_WritePersistentData``).
``RemanentStore`` keeps both in one directory so that a ``kill -9`` at any
instant leaves the image of the last write that returned; with
``durability="power"`` every write is also fsynced, so the same holds for a
power loss. A damaged file is found by its checksums, reported in
``problems`` and through a ``StoreWarning``, and never loaded.

An image is a list of ``(path, signature, data)`` entries. It is split into an
immutable ``ImageLayout`` (paths, type texts and sizes, serialised once) and a
bytes blob, the entries' data concatenated in layout order.

Files in the store directory
----------------------------
==========================  ==================================================
``retain.dat``              two slots, A at offset 0 and B at offset
                            ``slot_size``; the writes alternate between them,
                            so the slot not being written always holds the
                            previous image. ``slot_size`` is a multiple of
                            4096, so a write into one slot never touches a
                            page of the other.
``persistent.dat``          the newest PERSISTENT record (like ``.bootdata``)
``persistent.dat.bak``      the generation before it (like ``.bootdata-old``)
``*.tmp``                   a file being written; never read
``lock``                    empty; an open store holds an exclusive lock on it
                            (``fcntl.flock``, ``msvcrt.locking`` on Windows),
                            so a second store on the directory is refused
==========================  ==================================================

Every slot or file starts with one record; all integers are little-endian.

======  ====  ===========  =====================================================
offset  size  type         field
======  ====  ===========  =====================================================
0       8     bytes        magic ``b"IECOOPRM"``
8       2     u16          format version, 1
10      1     u8           kind: 1 RETAIN slot, 2 PERSISTENT file
11      1     u8           slot: 0 = A, 1 = B (always 0 for PERSISTENT)
12      4     u32          flags: bit 0 (RETAIN only) = the file was created
                           with both slots written, so a slot whose header is
                           all zero bytes was erased, not never written; every
                           other bit 0
16      8     u64          sequence, +1 on every write
24      8     u64          slot size in bytes (0 for PERSISTENT)
32      32    bytes        SHA-256 of the serialised layout
64      4     u32          layout length L
68      4     u32          data length D
72      4     u32          record CRC-32 of layout, then data, then bytes 0..71
76      4     u32          header CRC-32 of bytes 0..75
80      L     layout       u32 entry count, then per entry: u16 length and
                           UTF-8 path, u16 length and UTF-8 signature, u32 size
80+L    D     data         the entries' bytes, concatenated in layout order
======  ====  ===========  =====================================================

A PERSISTENT file is exactly one record long. A RETAIN slot holds one record
followed by padding. A slot whose 80 header bytes are all zero is empty (never
written), unless the record in the other slot has flag bit 0: this writer
fills the other slot of a new file with an empty record (sequence 0), so an
all-zero header there means a written slot was erased, and that is reported
like any other damage rather than silently loading the older slot. The header
checksum makes the sequence of a damaged record trustworthy, which tells an
interrupted newer write from an older damaged one.

Loading takes the valid RETAIN slot with the higher sequence (the empty
record of sequence 0 is never an image), and
``persistent.dat`` before ``persistent.dat.bak``. ``from_backup`` is set when
a newer generation may have been lost: the other slot is damaged and its
sequence is higher or unreadable, or ``persistent.dat`` is damaged or missing.
A write torn by a kill looks exactly like that, and what loads is then the
last write that completed. POSIX only (``os.pwrite``).

>>> import tempfile
>>> layout = ImageLayout((("PlcTask.Main.count", "INT", 2), ("PlcTask.Main.name", "STRING(5)", 6)))
>>> with tempfile.TemporaryDirectory() as folder, RemanentStore(folder) as store:
...     store.write_retain(layout, b"\x07\x00hello\x00")
...     store.write_retain(layout, b"\x08\x00hello\x00")
...     image = store.load_retain()
>>> image.values()["PlcTask.Main.count"]
('INT', b'\x08\x00')
>>> image.sequence, image.from_backup
(2, False)
"""

from __future__ import annotations

import errno
import hashlib
import os
import struct
import sys
import threading
import warnings
import weakref
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from collections.abc import Iterable
from typing import Literal, NamedTuple

if sys.platform == "win32":  # pragma: no cover - Windows
    import msvcrt

    def _try_lock(fd: int) -> None:
        msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
else:
    import fcntl

    def _try_lock(fd: int) -> None:
        # flock, not lockf: a second open of the file conflicts even in the same process.
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)

__all__ = ["ImageLayout", "LoadedImage", "RemanentStore", "StoreLockedError", "StoreWarning", "pack_image"]

_MAGIC = b"IECOOPRM"
_VERSION = 1
_RETAIN = 1
_PERSISTENT = 2
# Header flag: the file was created with both slots written (an all-zero slot is damage).
_BOTH_SLOTS = 1
_KIND_NAMES = {_RETAIN: "RETAIN", _PERSISTENT: "PERSISTENT"}
_PAGE = 4096

# The record CRC cannot cover its own field, so the header is packed in two
# steps: the first 72 bytes, then the two checksums.
_HEAD = struct.Struct("<8sHBBIQQ32sII")
_HEADER = struct.Struct("<8sHBBIQQ32sIIII")
_HEADER_SIZE = _HEADER.size
_CRC_SPAN = _HEAD.size
_ZERO_HEADER = bytes(_HEADER_SIZE)
_U16 = struct.Struct("<H")
_U32 = struct.Struct("<I")
_U16_MAX = 0xFFFF
_U32_MAX = 0xFFFF_FFFF
# count + empty path + empty signature + size: bounds a hostile entry count.
_MIN_ENTRY = _U16.size * 2 + _U32.size
_SLOT_NAMES = ("A", "B")
_LOCK_FILE = "lock"

_Durability = Literal["process", "power"]
_Data = bytes | bytearray | memoryview


class StoreWarning(UserWarning):
    """A remanent file was damaged or missing; what was loaded instead is in the message."""


class StoreLockedError(RuntimeError):
    """The store directory is open in another ``RemanentStore`` (another Runtime, or another process)."""


@dataclass(frozen=True, slots=True)
class ImageLayout:
    """The shape of an image: ``(path, signature, size)`` per entry, in data order.

    Serialised and hashed once, at construction, so a cyclic write only packs a
    header and the data.

    >>> layout = ImageLayout((("Main.a", "INT", 2), ("Main.b", "LREAL", 8)))
    >>> layout.size, len(layout.digest)
    (10, 32)
    """

    entries: tuple[tuple[str, str, int], ...]
    serialised: bytes = field(init=False, repr=False, compare=False)
    digest: bytes = field(init=False, repr=False, compare=False)
    size: int = field(init=False, repr=False, compare=False)
    crc: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        entries = tuple(tuple(entry) for entry in self.entries)
        parts = [_U32.pack(len(entries))]
        seen: set[str] = set()
        total = 0
        for index, entry in enumerate(entries):
            if len(entry) != 3:
                raise ValueError(f"ImageLayout entry {index} {entry!r}: expected (path, signature, size)")
            path, signature, size = entry
            where = f"ImageLayout entry {index} {entry!r}"
            if not isinstance(path, str) or not path:
                raise ValueError(f"{where}: the path must be a non-empty str")
            if not isinstance(signature, str):
                raise ValueError(f"{where}: the signature must be a str")
            if not isinstance(size, int) or isinstance(size, bool) or not 0 <= size <= _U32_MAX:
                raise ValueError(f"{where}: the size must be an int in 0..{_U32_MAX}")
            if path in seen:
                raise ValueError(f"{where}: the path {path!r} occurs twice")
            seen.add(path)
            try:
                path_bytes = path.encode("utf-8")
                signature_bytes = signature.encode("utf-8")
            except UnicodeEncodeError as exc:
                raise ValueError(f"{where}: not encodable as UTF-8 ({exc.reason})") from None
            if len(path_bytes) > _U16_MAX or len(signature_bytes) > _U16_MAX:
                raise ValueError(f"{where}: path and signature are limited to {_U16_MAX} UTF-8 bytes")
            parts += (_U16.pack(len(path_bytes)), path_bytes, _U16.pack(len(signature_bytes)),
                      signature_bytes, _U32.pack(size))
            total += size
        serialised = b"".join(parts)
        if len(serialised) > _U32_MAX or total > _U32_MAX:
            raise ValueError(f"ImageLayout: layout and data are limited to {_U32_MAX} bytes each")
        object.__setattr__(self, "entries", entries)
        object.__setattr__(self, "serialised", serialised)
        object.__setattr__(self, "digest", hashlib.sha256(serialised).digest())
        object.__setattr__(self, "size", total)
        object.__setattr__(self, "crc", zlib.crc32(serialised))


_EMPTY_LAYOUT = ImageLayout(())


def pack_image(entries: Iterable[tuple[str, str, bytes]]) -> tuple[ImageLayout, bytes]:
    """Split ``(path, signature, data)`` entries into a layout and the concatenated data.

    >>> layout, data = pack_image([("Main.a", "INT", b"\\x01\\x00"), ("Main.b", "BOOL", b"\\x01")])
    >>> layout.entries, data
    ((('Main.a', 'INT', 2), ('Main.b', 'BOOL', 1)), b'\\x01\\x00\\x01')
    """
    items = tuple(entries)
    layout = ImageLayout(tuple((path, signature, len(data)) for path, signature, data in items))
    return layout, b"".join(data for _, _, data in items)


@dataclass(frozen=True, slots=True)
class LoadedImage:
    """An image read back from the store.

    ``from_backup`` is TwinCAT's ``_AppInfo.OldBootData``: the newest generation
    was damaged or missing and an older one was used.
    """

    layout: ImageLayout
    data: bytes
    sequence: int
    from_backup: bool

    def __post_init__(self) -> None:
        if len(self.data) != self.layout.size:
            raise ValueError(f"LoadedImage: the layout needs {self.layout.size} bytes, data has {len(self.data)}")

    def values(self) -> dict[str, tuple[str, bytes]]:
        """``path -> (signature, bytes)`` for every entry."""
        result: dict[str, tuple[str, bytes]] = {}
        position = 0
        for path, signature, size in self.layout.entries:
            result[path] = (signature, self.data[position:position + size])
            position += size
        return result


class _Record(NamedTuple):
    sequence: int
    slot: int
    slot_size: int
    layout: ImageLayout
    data: bytes
    both_slots: bool = False


class _Damage(NamedTuple):
    reason: str
    # Known only when the header checksum held, so the number can be trusted.
    sequence: int | None = None
    slot_size: int = 0


class _Corrupt(Exception):
    pass


def _parse_layout(raw: bytes) -> ImageLayout:
    size = len(raw)
    if size < _U32.size:
        raise _Corrupt(f"layout of {size} bytes is shorter than its entry count")
    (count,) = _U32.unpack_from(raw, 0)
    room = (size - _U32.size) // _MIN_ENTRY
    if count > room:
        raise _Corrupt(f"layout claims {count} entries but {size} bytes hold at most {room}")
    position = _U32.size
    entries: list[tuple[str, str, int]] = []
    for index in range(count):
        texts: list[str] = []
        for what in ("path", "signature"):
            if position + _U16.size > size:
                raise _Corrupt(f"layout entry {index}: {what} length beyond the end of the layout")
            (length,) = _U16.unpack_from(raw, position)
            position += _U16.size
            if position + length > size:
                raise _Corrupt(f"layout entry {index}: {what} of {length} bytes beyond the end of the layout")
            try:
                texts.append(raw[position:position + length].decode("utf-8"))
            except UnicodeDecodeError:
                raise _Corrupt(f"layout entry {index}: {what} is not valid UTF-8") from None
            position += length
        if position + _U32.size > size:
            raise _Corrupt(f"layout entry {index}: size beyond the end of the layout")
        (entry_size,) = _U32.unpack_from(raw, position)
        position += _U32.size
        entries.append((texts[0], texts[1], entry_size))
    if position != size:
        raise _Corrupt(f"layout has {size - position} bytes after its last entry")
    try:
        layout = ImageLayout(tuple(entries))
    except ValueError as exc:
        raise _Corrupt(str(exc)) from None
    if layout.serialised != raw:
        raise _Corrupt("layout is not in canonical form")
    return layout


def _parse_record(buf: bytes, offset: int, kind: int, slot: int) -> _Record | _Damage | None:
    """The record at ``offset``, the damage found there, or None for a never-written slot."""
    try:
        return _parse_record_unchecked(buf, offset, kind, slot)
    except _Corrupt as exc:
        return _Damage(str(exc))
    except (struct.error, ValueError, IndexError, OverflowError) as exc:
        # Every length is checked before use; this only keeps an oversight
        # from turning damaged data into an exception at start-up.
        return _Damage(f"unparseable ({type(exc).__name__}: {exc})")


def _parse_record_unchecked(buf: bytes, offset: int, kind: int, slot: int) -> _Record | _Damage | None:
    available = len(buf) - offset
    if available < _HEADER_SIZE:
        return _Damage(f"truncated: {max(available, 0)} of {_HEADER_SIZE} header bytes present")
    header = buf[offset:offset + _HEADER_SIZE]
    if header == _ZERO_HEADER:
        return None
    (magic, version, record_kind, record_slot, reserved, sequence, slot_size, digest,
     layout_length, data_length, record_crc, header_crc) = _HEADER.unpack(header)
    if magic != _MAGIC:
        return _Damage(f"bad magic {magic!r}")
    if zlib.crc32(header[:_HEADER_SIZE - 4]) != header_crc:
        return _Damage("header checksum mismatch")

    def damage(reason: str) -> _Damage:
        return _Damage(reason, sequence, slot_size if kind == _RETAIN else 0)

    if version != _VERSION:
        return damage(f"unsupported format version {version}")
    if record_kind != kind:
        name = _KIND_NAMES.get(record_kind, f"kind {record_kind}")
        return damage(f"holds a {name} record where a {_KIND_NAMES[kind]} record belongs")
    if reserved & ~(_BOTH_SLOTS if kind == _RETAIN else 0):
        return damage("reserved header field is not zero")
    if record_slot != slot:
        return damage(f"record belongs to slot {record_slot}, found in slot {slot}")
    total = _HEADER_SIZE + layout_length + data_length
    if kind == _RETAIN:
        if slot_size < _PAGE or slot_size % _PAGE:
            return damage(f"slot size {slot_size} is not a positive multiple of {_PAGE}")
        if offset != slot * slot_size:
            return damage(f"slot size {slot_size} does not match the slot's offset {offset}")
        if total > slot_size:
            return damage(f"lengths (layout {layout_length}, data {data_length}) exceed the slot size {slot_size}")
    elif slot_size:
        return damage("slot size is set in a PERSISTENT record")
    if total > available:
        return damage(f"truncated: record needs {total} bytes, {available} present")
    if kind == _PERSISTENT and total != available:
        return damage(f"{available - total} unexpected bytes after the record")
    view = memoryview(buf)
    start = offset + _HEADER_SIZE
    layout_bytes = view[start:start + layout_length]
    data_bytes = view[start + layout_length:start + layout_length + data_length]
    crc = zlib.crc32(header[:_CRC_SPAN], zlib.crc32(data_bytes, zlib.crc32(layout_bytes)))
    if crc != record_crc:
        return damage("record checksum mismatch (damaged, or a write that was interrupted)")
    raw_layout = bytes(layout_bytes)
    if hashlib.sha256(raw_layout).digest() != digest:
        return damage("layout digest mismatch")
    try:
        layout = _parse_layout(raw_layout)
    except _Corrupt as exc:
        return damage(str(exc))
    if layout.size != data_length:
        return damage(f"entry sizes add up to {layout.size} bytes, the data has {data_length}")
    return _Record(sequence, record_slot, slot_size if kind == _RETAIN else 0, layout, bytes(data_bytes),
                   bool(reserved & _BOTH_SLOTS))


def _seal(buf: bytearray, kind: int, slot: int, sequence: int, slot_size: int, layout: ImageLayout) -> None:
    """Fill in the header of the record in ``buf`` (layout and data already in place)."""
    layout_length = len(layout.serialised)
    data_length = len(buf) - _HEADER_SIZE - layout_length
    flags = _BOTH_SLOTS if kind == _RETAIN else 0
    _HEAD.pack_into(buf, 0, _MAGIC, _VERSION, kind, slot, flags, sequence, slot_size, layout.digest,
                    layout_length, data_length)
    with memoryview(buf) as view:
        record_crc = zlib.crc32(view[:_CRC_SPAN],
                                zlib.crc32(view[_HEADER_SIZE + layout_length:], layout.crc))
        _U32.pack_into(buf, _CRC_SPAN, record_crc)
        header_crc = zlib.crc32(view[:_CRC_SPAN + 4])
    _U32.pack_into(buf, _CRC_SPAN + 4, header_crc)


def _new_record(layout: ImageLayout, data: _Data | None = None) -> bytearray:
    """A record buffer with the layout in place; the header is filled in by ``_seal``."""
    buf = bytearray(_HEADER_SIZE + len(layout.serialised) + layout.size)
    buf[_HEADER_SIZE:_HEADER_SIZE + len(layout.serialised)] = layout.serialised
    if data is not None:
        buf[_HEADER_SIZE + len(layout.serialised):] = data
    return buf


def _as_bytes(data: _Data, layout: ImageLayout, operation: str) -> _Data:
    if isinstance(data, memoryview) and data.format != "B":
        data = data.cast("B")
    if len(data) != layout.size:
        raise ValueError(f"RemanentStore.{operation}: the layout needs {layout.size} bytes, data has {len(data)}")
    return data


def _write_all(fd: int, data: bytes | bytearray, offset: int) -> None:
    with memoryview(data) as view:
        done = 0
        while done < len(view):
            written = os.pwrite(fd, view[done:], offset + done)
            if written <= 0:
                raise OSError(f"pwrite wrote nothing at offset {offset + done}")
            done += written


def _read_file(path: Path) -> bytes | None:
    try:
        return path.read_bytes()
    except FileNotFoundError:
        return None


def _unlink(path: Path) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass


def _slot_size_for(record_length: int, current: int) -> int:
    # Headroom so a layout that grows a little does not rewrite the file each
    # time; doubling keeps a steadily growing layout at few rewrites.
    wanted = max(record_length + record_length // 4, 2 * current, _PAGE)
    return -(-wanted // _PAGE) * _PAGE


class _RetainScan(NamedTuple):
    best: _Record | None
    slots: tuple[_Record | _Damage | None, _Record | _Damage | None]
    problems: list[str]
    from_backup: bool
    top_sequence: int


def _scan_retain(buf: bytes, name: str) -> _RetainScan:
    first = _parse_record(buf, 0, _RETAIN, 0)
    # Slot B starts at the slot size, which a header with a valid checksum
    # states; otherwise the file is assumed to have its usual two-slot size.
    stated = 0 if first is None else first.slot_size
    if stated >= _PAGE and stated % _PAGE == 0:
        offset = stated
    else:
        offset = len(buf) // 2
    second: _Record | _Damage | None
    if offset < _HEADER_SIZE:
        second = _Damage(f"not found in a file of {len(buf)} bytes")
    else:
        second = _parse_record(buf, offset, _RETAIN, 1)
    valid = [record for record in (first, second) if isinstance(record, _Record)]
    # Sequence 0 is the empty record that fills the unused slot of a new file: never an image.
    best = max((record for record in valid if record.sequence), key=lambda record: record.sequence, default=None)
    if any(record.both_slots for record in valid):
        # Both slots were written when the file was made: a blank one was erased.
        erased = _Damage("header is all zero bytes (a written slot was erased)")
        first = erased if first is None else first
        second = erased if second is None else second
    slots = (first, second)
    problems: list[str] = []
    from_backup = False
    sequences = [record.sequence for record in slots if record is not None and record.sequence is not None]
    for letter, record in zip(_SLOT_NAMES, slots):
        if isinstance(record, _Damage):
            known = "" if record.sequence is None else f" [sequence {record.sequence}]"
            problems.append(f"{name} slot {letter}: {record.reason}{known}")
            if best is not None and (record.sequence is None or record.sequence > best.sequence):
                from_backup = True
    return _RetainScan(best, slots, problems, from_backup, max(sequences, default=0))


class RemanentStore:
    """RETAIN and PERSISTENT images in one directory, safe against ``kill -9``.

    ``durability="process"`` survives the death of the process (the data is in
    the page cache once a write returns); ``"power"`` also fsyncs every write
    and the directory after every rename, so it survives a power loss, at the
    price of a disk flush per cycle. Calls are serialised by a lock, so tasks
    on several threads may share a store. One store writes a directory at a
    time: opening a second one on the same directory, in this process or
    another, raises ``StoreLockedError`` naming the lock file until the first
    is closed (or its process ends).
    """

    RETAIN_FILE = "retain.dat"
    PERSISTENT_FILE = "persistent.dat"
    BACKUP_SUFFIX = ".bak"
    TEMP_SUFFIX = ".tmp"

    def __init__(self, path: str | os.PathLike[str], *, durability: _Durability = "process") -> None:
        if durability not in ("process", "power"):
            raise ValueError(f"RemanentStore: durability must be 'process' or 'power', not {durability!r}")
        self.path = Path(path)
        self.path.mkdir(parents=True, exist_ok=True)
        self._lock_path = self.path / _LOCK_FILE
        self._lock_fd = _lock_store(self._lock_path, self.path)
        # A store dropped without close() (a Runtime never stopped) still releases the directory.
        self._release = weakref.finalize(self, os.close, self._lock_fd)
        self.durability: _Durability = durability
        self._sync = durability == "power"
        self._retain_path = self.path / self.RETAIN_FILE
        self._persistent_path = self.path / self.PERSISTENT_FILE
        self._backup_path = self.path / (self.PERSISTENT_FILE + self.BACKUP_SUFFIX)
        self._lock = threading.Lock()
        self._closed = False
        self._retain_problems: list[str] = []
        self._persistent_problems: list[str] = []
        # The RETAIN writer is set up by the first write, from the file on disk.
        self._writer_ready = False
        self._fd = -1
        self._slot_size = 0
        self._live = -1
        self._live_record: _Record | None = None
        self._retain_sequence = 0
        self._buffer = bytearray()
        self._buffer_layout: ImageLayout | None = None
        self._persistent_sequence: int | None = None

    @property
    def problems(self) -> list[str]:
        """Damage found by the most recent ``load_retain`` and ``load_persistent``."""
        return self._retain_problems + self._persistent_problems

    # -- RETAIN -------------------------------------------------------------------

    def write_retain(self, layout: ImageLayout, data: _Data) -> None:
        """Store the RETAIN image of the cycle that just ended: one ``pwrite`` into the older slot."""
        data = _as_bytes(data, layout, "write_retain")
        with self._lock:
            self._check_open("write_retain")
            if not self._writer_ready:
                self._open_retain()
            if layout is not self._buffer_layout:
                # An equal layout built anew (same digest) keeps the buffer.
                if self._buffer_layout is None or layout.digest != self._buffer_layout.digest:
                    self._buffer = _new_record(layout)
                self._buffer_layout = layout
            buf = self._buffer
            buf[_HEADER_SIZE + len(layout.serialised):] = data
            sequence = self._retain_sequence + 1
            slot = 1 - self._live if self._live >= 0 else 0
            if self._fd < 0 or len(buf) > self._slot_size:
                self._rebuild_retain(buf, layout, slot, sequence)
            else:
                _seal(buf, _RETAIN, slot, sequence, self._slot_size, layout)
                _write_all(self._fd, buf, slot * self._slot_size)
                if self._sync:
                    os.fdatasync(self._fd)
                self._live_record = None
            self._live = slot
            self._retain_sequence = sequence

    def load_retain(self) -> LoadedImage | None:
        """The newest valid RETAIN image, or None if there is none."""
        with self._lock:
            self._check_open("load_retain")
            buf = _read_file(self._retain_path)
            if buf is None:
                self._retain_problems = []
                return None
            scan = _scan_retain(buf, self.RETAIN_FILE)
            problems = scan.problems
            if scan.best is None:
                problems.append("no valid RETAIN image")
                outcome = "RETAIN variables start from their initial values"
                image = None
            else:
                outcome = f"using slot {_SLOT_NAMES[scan.best.slot]} (sequence {scan.best.sequence})"
                image = LoadedImage(scan.best.layout, scan.best.data, scan.best.sequence, scan.from_backup)
            self._retain_problems = problems
            # The file may have changed behind the writer's back (a damaged
            # slot it believes current): it starts again from what is on disk.
            self._reset_writer()
        if problems:
            warnings.warn(f"{self._retain_path}: {'; '.join(problems)}; {outcome}", StoreWarning, stacklevel=2)
        return image

    def clear_retain(self) -> None:
        """Delete the RETAIN image (reset cold / origin, download)."""
        with self._lock:
            self._check_open("clear_retain")
            self._reset_writer()
            _unlink(self._retain_path)
            _unlink(self._retain_path.with_name(self.RETAIN_FILE + self.TEMP_SUFFIX))
            if self._sync:
                self._sync_directory()
            self._retain_problems = []

    def _reset_writer(self) -> None:
        self._close_fd()
        self._writer_ready = False
        self._live = -1
        self._live_record = None
        self._slot_size = 0

    def _open_retain(self) -> None:
        try:
            fd = os.open(self._retain_path, os.O_RDWR)
        except FileNotFoundError:
            self._writer_ready = True
            return
        try:
            buf = _read_fd(fd)
        except BaseException:
            os.close(fd)
            raise
        self._writer_ready = True
        scan = _scan_retain(buf, self.RETAIN_FILE)
        self._retain_sequence = max(self._retain_sequence, scan.top_sequence)
        best = scan.best
        if best is None:
            os.close(fd)
            return
        self._live = best.slot
        self._live_record = best
        if len(buf) == 2 * best.slot_size:
            self._fd = fd
            self._slot_size = best.slot_size
        else:
            # Not the two-slot file this class writes: rewrite it whole on the
            # first write, carrying the valid record over.
            os.close(fd)

    def _rebuild_retain(self, buf: bytearray, layout: ImageLayout, slot: int, sequence: int) -> None:
        """Write a new retain file with room for ``buf`` and switch to it in one rename."""
        # The newest image so far goes into the new file too, so that it still
        # has a previous generation to fall back on.
        previous = self._live_record
        if previous is None and self._fd >= 0 and self._live >= 0:
            found = _scan_retain(_read_fd(self._fd), self.RETAIN_FILE).slots[self._live]
            previous = found if isinstance(found, _Record) else None
        if previous is None or previous.slot == slot:
            # No generation to carry over: an empty record (sequence 0) fills
            # the other slot, so that slot can never be blank in a sound file.
            previous = _Record(0, 1 - slot, 0, _EMPTY_LAYOUT, b"")
        old = _new_record(previous.layout, previous.data)
        # Both records must fit: the previous one may be the larger.
        slot_size = _slot_size_for(max(len(buf), len(old)), self._slot_size)
        image = bytearray(2 * slot_size)
        _seal(buf, _RETAIN, slot, sequence, slot_size, layout)
        image[slot * slot_size:slot * slot_size + len(buf)] = buf
        _seal(old, _RETAIN, previous.slot, previous.sequence, slot_size, previous.layout)
        image[previous.slot * slot_size:previous.slot * slot_size + len(old)] = old
        if len(image) != 2 * slot_size:
            raise AssertionError("RemanentStore: a record overflowed its slot")
        temporary = self._retain_path.with_name(self.RETAIN_FILE + self.TEMP_SUFFIX)
        fd = os.open(temporary, os.O_RDWR | os.O_CREAT | os.O_TRUNC, 0o644)
        try:
            _write_all(fd, image, 0)
            if self._sync:
                os.fsync(fd)
            os.replace(temporary, self._retain_path)
        except BaseException:
            os.close(fd)
            raise
        # From the rename on, the new file is the store: switch before anything
        # else can fail, or later writes would go to the unlinked old file.
        self._close_fd()
        self._fd = fd
        self._slot_size = slot_size
        self._live_record = None
        if self._sync:
            self._sync_directory()

    # -- PERSISTENT ---------------------------------------------------------------

    def write_persistent(self, layout: ImageLayout, data: _Data) -> None:
        """Save the PERSISTENT image; the previous one becomes ``persistent.dat.bak``."""
        data = _as_bytes(data, layout, "write_persistent")
        with self._lock:
            self._check_open("write_persistent")
            current = _read_file(self._persistent_path)
            current_record = None if current is None else _parse_record(current, 0, _PERSISTENT, 0)
            if self._persistent_sequence is None:
                self._persistent_sequence = self._persistent_top(current_record)
            sequence = self._persistent_sequence + 1
            buf = _new_record(layout, data)
            _seal(buf, _PERSISTENT, 0, sequence, 0, layout)
            temporary = self._persistent_path.with_name(self.PERSISTENT_FILE + self.TEMP_SUFFIX)
            self._write_new_file(temporary, buf)
            # Rotate only a valid generation: a damaged persistent.dat must not
            # push out a backup that may be the only good image left.
            if current is not None and isinstance(current_record, _Record):
                self._keep_backup(current)
            os.replace(temporary, self._persistent_path)
            if self._sync:
                self._sync_directory()
            self._persistent_sequence = sequence

    def load_persistent(self) -> LoadedImage | None:
        """The newest valid PERSISTENT image, falling back to ``persistent.dat.bak``."""
        with self._lock:
            self._check_open("load_persistent")
            problems: list[str] = []
            found: list[_Record | None] = []
            present: list[bool] = []
            for path in (self._persistent_path, self._backup_path):
                buf = _read_file(path)
                present.append(buf is not None)
                record = None if buf is None else _parse_record(buf, 0, _PERSISTENT, 0)
                found.append(record if isinstance(record, _Record) else None)
                if buf is not None and not isinstance(record, _Record):
                    problems.append(f"{path.name}: {'header is all zero bytes' if record is None else record.reason}")
            main, backup = found
            image = None
            if main is not None:
                image = LoadedImage(main.layout, main.data, main.sequence, False)
                outcome = f"using {self._persistent_path.name} (sequence {main.sequence})"
            elif backup is not None:
                if not present[0]:
                    problems.insert(0, f"{self._persistent_path.name}: missing")
                image = LoadedImage(backup.layout, backup.data, backup.sequence, True)
                outcome = f"using the older generation {self._backup_path.name} (sequence {backup.sequence})"
            else:
                if any(present):
                    problems.append("no valid PERSISTENT image")
                outcome = "PERSISTENT variables start from their initial values"
            self._persistent_problems = problems
        if problems:
            warnings.warn(f"{self.path}: {'; '.join(problems)}; {outcome}", StoreWarning, stacklevel=2)
        return image

    def clear_persistent(self) -> None:
        """Delete both PERSISTENT generations (reset origin)."""
        with self._lock:
            self._check_open("clear_persistent")
            # The backup goes first: interrupted half way, the newest image
            # survives rather than an older one.
            for path in (self._backup_path.with_name(self._backup_path.name + self.TEMP_SUFFIX), self._backup_path,
                         self._persistent_path.with_name(self.PERSISTENT_FILE + self.TEMP_SUFFIX),
                         self._persistent_path):
                _unlink(path)
            if self._sync:
                self._sync_directory()
            self._persistent_problems = []

    def _persistent_top(self, current: _Record | _Damage | None) -> int:
        sequences = [0]
        backup = _read_file(self._backup_path)
        for record in (current, None if backup is None else _parse_record(backup, 0, _PERSISTENT, 0)):
            if record is not None and record.sequence is not None:
                sequences.append(record.sequence)
        return max(sequences)

    def _keep_backup(self, current: bytes) -> None:
        temporary = self._backup_path.with_name(self._backup_path.name + self.TEMP_SUFFIX)
        _unlink(temporary)
        try:
            # A second name for the same inode: nothing to copy, already synced.
            os.link(self._persistent_path, temporary)
        except OSError:
            self._write_new_file(temporary, current)
        os.replace(temporary, self._backup_path)

    # -- common -------------------------------------------------------------------

    def _write_new_file(self, path: Path, data: bytes | bytearray) -> None:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        try:
            _write_all(fd, data, 0)
            if self._sync:
                os.fsync(fd)
        finally:
            os.close(fd)

    def _sync_directory(self) -> None:
        fd = os.open(self.path, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
        try:
            os.fsync(fd)
        finally:
            os.close(fd)

    def _close_fd(self) -> None:
        if self._fd >= 0:
            fd, self._fd = self._fd, -1
            os.close(fd)

    def _check_open(self, operation: str) -> None:
        if self._closed:
            raise ValueError(f"RemanentStore.{operation}: the store {self.path} is closed")

    def close(self) -> None:
        """Release the RETAIN file and the directory's lock; further calls raise ValueError."""
        with self._lock:
            self._close_fd()
            self._closed = True
            self._release()

    def __enter__(self) -> RemanentStore:
        return self

    def __exit__(self, kind: type[BaseException] | None, value: BaseException | None,
                 traceback: TracebackType | None) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"RemanentStore({str(self.path)!r}, durability={self.durability!r})"


def _lock_store(lock_path: Path, folder: Path) -> int:
    """Open ``lock_path`` and take an exclusive, non-blocking lock on it; the open descriptor holds it."""
    fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        _try_lock(fd)
    except OSError as exc:
        os.close(fd)
        if exc.errno not in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK, errno.EDEADLK):
            raise
        raise StoreLockedError(
            f"the remanent store {folder} is in use: another Runtime (in this or another process) holds "
            f"the lock on {lock_path}; stop it first, or give this Runtime another store"
        ) from None
    except BaseException:
        os.close(fd)
        raise
    return fd


def _read_fd(fd: int) -> bytes:
    size = os.fstat(fd).st_size
    chunks = []
    offset = 0
    while offset < size:
        chunk = os.pread(fd, size - offset, offset)
        if not chunk:
            break
        chunks.append(chunk)
        offset += len(chunk)
    return b"".join(chunks)
