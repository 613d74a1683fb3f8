"""The remanent store: round trips, slots, generations, and damaged or hostile files."""

from __future__ import annotations

import array
import hashlib
import os
import random
import struct
import tempfile
import warnings
import zlib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from iecoop.runtime import store as store_module
from iecoop.runtime.store import ImageLayout, LoadedImage, RemanentStore, StoreWarning, pack_image

# The record table of the module docstring, written out independently so the
# documentation is checked against the files.
DOC_HEAD = struct.Struct("<8sHBBIQQ32sII")
DOC_HEADER = struct.Struct("<8sHBBIQQ32sIIII")
FIELDS = ("magic", "version", "kind", "slot", "reserved", "sequence", "slot_size", "digest",
          "layout_length", "data_length", "record_crc", "header_crc")
MAGIC = b"IECOOPRM"
RETAIN, PERSISTENT = 1, 2
PAGE = 4096

Image = tuple[ImageLayout, bytes]


def image(*entries: tuple[str, str, bytes]) -> Image:
    return pack_image(entries)


def ints(prefix: str, values: list[int]) -> Image:
    """An image of INT variables ``prefix[i]``."""
    return pack_image([(f"{prefix}[{index}]", "INT", struct.pack("<h", value)) for index, value in enumerate(values)])


SMALL = image(("PlcTask.Main.count", "INT", b"\x07\x00"), ("PlcTask.Main.name", "STRING(5)", b"hello\x00"))
OTHER = image(("PlcTask.Main.count", "INT", b"\x08\x00"), ("PlcTask.Main.speed", "LREAL", struct.pack("<d", 1.5)))
EMPTY = image()
BIG = pack_image([(f"PlcTask.Main.station[{index}].recipe", "ARRAY[0..63] OF BYTE", bytes([index % 256]) * 64)
                  for index in range(200)])


def header_at(buf: bytes, offset: int = 0) -> dict[str, Any]:
    return dict(zip(FIELDS, DOC_HEADER.unpack_from(buf, offset)))


def forge(layout: bytes, data: bytes, **fields: Any) -> bytes:
    """A record per the documented table, checksums made to match unless given."""
    values: dict[str, Any] = {
        "magic": MAGIC, "version": 1, "kind": PERSISTENT, "slot": 0, "reserved": 0, "sequence": 1,
        "slot_size": 0, "digest": hashlib.sha256(layout).digest(), "layout_length": len(layout),
        "data_length": len(data),
    }
    values.update({name: value for name, value in fields.items() if name in values})
    head = DOC_HEAD.pack(*(values[name] for name in FIELDS[:10]))
    record_crc = fields.get("record_crc", zlib.crc32(head, zlib.crc32(data, zlib.crc32(layout))))
    header_crc = fields.get("header_crc", zlib.crc32(head + struct.pack("<I", record_crc)))
    return head + struct.pack("<II", record_crc, header_crc) + layout + data


def forge_retain(layout: bytes, data: bytes, slot_size: int = PAGE, **fields: Any) -> bytes:
    """A two-page retain file whose slot A holds the forged record (whatever slot size it states)."""
    record = forge(layout, data, **{"kind": RETAIN, "slot_size": slot_size, **fields})
    return record + bytes(max(2 * PAGE - len(record), 0))


def written_retain(layout: bytes, data: bytes) -> bytes:
    """The retain file a first write makes: the record in slot A, the empty record (sequence 0) in slot B."""
    first = forge(layout, data, kind=RETAIN, slot_size=PAGE, reserved=1)
    empty = forge(layout_bytes(), b"", kind=RETAIN, slot=1, slot_size=PAGE, reserved=1, sequence=0)
    return first + bytes(PAGE - len(first)) + empty + bytes(PAGE - len(empty))


def layout_bytes(*entries: tuple[bytes, bytes, int], count: int | None = None) -> bytes:
    """A serialised layout, possibly a wrong one."""
    parts = [struct.pack("<I", len(entries) if count is None else count)]
    for path, signature, size in entries:
        parts += [struct.pack("<H", len(path)), path, struct.pack("<H", len(signature)), signature,
                  struct.pack("<I", size)]
    return b"".join(parts)


def same(loaded: LoadedImage | None, expected: Image) -> bool:
    return loaded is not None and (loaded.layout, loaded.data) == expected


@contextmanager
def quiet() -> Iterator[list[warnings.WarningMessage]]:
    """Collect warnings instead of failing on them (pytest turns them into errors)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield caught


def data_files(folder: Path) -> list[str]:
    """The files of a store folder but its lock file."""
    return sorted(name for name in os.listdir(folder) if name != "lock")


def flip(path: Path, offset: int) -> None:
    raw = bytearray(path.read_bytes())
    raw[offset] ^= 0x40
    path.write_bytes(bytes(raw))


# -- layouts and images -------------------------------------------------------------


def test_layout_serialises_once_and_compares_by_entries() -> None:
    layout, data = SMALL
    assert layout.size == len(data) == 8
    assert layout.digest == hashlib.sha256(layout.serialised).digest()
    assert layout.serialised == layout_bytes((b"PlcTask.Main.count", b"INT", 2),
                                             (b"PlcTask.Main.name", b"STRING(5)", 6))
    again = ImageLayout([list(entry) for entry in layout.entries])  # type: ignore[arg-type]
    assert again == layout and hash(again) == hash(layout) and again.entries == layout.entries


@pytest.mark.parametrize(("entries", "message"), [
    ((("a", "INT", 2), ("a", "INT", 2)), "occurs twice"),
    ((("", "INT", 2),), "non-empty str"),
    ((("a", "INT", -1),), "size must be"),
    ((("a", "INT", 1 << 32),), "size must be"),
    ((("a", "INT", True),), "size must be"),
    ((("a", 7, 2),), "signature must be a str"),
    ((("a\udc80", "INT", 2),), "UTF-8"),
    ((("a" * 70000, "INT", 2),), "limited to 65535"),
    ((("a", "INT"),), "expected \\(path, signature, size\\)"),
])
def test_layout_rejects_bad_entries(entries: Any, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        ImageLayout(entries)


def test_values_maps_paths_to_signature_and_bytes(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        loaded = store.load_retain()
    assert loaded is not None
    assert loaded.values() == {"PlcTask.Main.count": ("INT", b"\x07\x00"),
                               "PlcTask.Main.name": ("STRING(5)", b"hello\x00")}
    with pytest.raises(ValueError, match="needs 8 bytes"):
        LoadedImage(SMALL[0], b"", 1, False)


# -- round trips --------------------------------------------------------------------


def test_empty_store_loads_nothing_and_reports_nothing(tmp_path: Path) -> None:
    with RemanentStore(tmp_path / "new" / "store") as store:
        assert store.load_retain() is None
        assert store.load_persistent() is None
        assert store.problems == []
    assert (tmp_path / "new" / "store").is_dir()


@pytest.mark.parametrize("durability", ["process", "power"])
def test_retain_round_trip(tmp_path: Path, durability: str) -> None:
    with RemanentStore(tmp_path, durability=durability) as store:  # type: ignore[arg-type]
        store.write_retain(*SMALL)
        assert same(store.load_retain(), SMALL)
    with RemanentStore(tmp_path) as store:
        loaded = store.load_retain()
        assert same(loaded, SMALL)
        assert loaded is not None and loaded.sequence == 1 and not loaded.from_backup
        assert store.problems == []
    assert data_files(tmp_path) == ["retain.dat"]


@pytest.mark.parametrize("durability", ["process", "power"])
def test_persistent_round_trip_keeps_the_previous_generation(tmp_path: Path, durability: str) -> None:
    with RemanentStore(tmp_path, durability=durability) as store:  # type: ignore[arg-type]
        store.write_persistent(*SMALL)
        assert data_files(tmp_path) == ["persistent.dat"]
        store.write_persistent(*OTHER)
    assert data_files(tmp_path) == ["persistent.dat", "persistent.dat.bak"]
    with RemanentStore(tmp_path) as store:
        loaded = store.load_persistent()
        assert same(loaded, OTHER)
        assert loaded is not None and loaded.sequence == 2 and not loaded.from_backup
    assert header_at((tmp_path / "persistent.dat.bak").read_bytes())["sequence"] == 1


def test_empty_image_round_trips(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*EMPTY)
        store.write_persistent(*EMPTY)
        assert same(store.load_retain(), EMPTY)
        assert same(store.load_persistent(), EMPTY)


def test_retain_and_persistent_are_independent(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_persistent(*OTHER)
        assert same(store.load_retain(), SMALL)
        assert same(store.load_persistent(), OTHER)


def test_buffers_are_accepted_as_data(tmp_path: Path) -> None:
    layout = ImageLayout((("Main.a", "ARRAY[0..1] OF INT", 4),))
    with RemanentStore(tmp_path) as store:
        store.write_retain(layout, memoryview(array.array("h", [1, 2])))
        store.write_persistent(layout, bytearray(b"\x01\x00\x02\x00"))
        assert same(store.load_retain(), (layout, b"\x01\x00\x02\x00"))
        assert same(store.load_persistent(), (layout, b"\x01\x00\x02\x00"))


def test_data_must_match_the_layout(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        with pytest.raises(ValueError, match="write_retain: the layout needs 8 bytes, data has 3"):
            store.write_retain(SMALL[0], b"abc")
        with pytest.raises(ValueError, match="write_persistent"):
            store.write_persistent(SMALL[0], b"")


def test_layout_change_between_writes(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        for expected in (SMALL, OTHER, SMALL, EMPTY, OTHER):
            store.write_retain(*expected)
            store.write_persistent(*expected)
            assert same(store.load_retain(), expected)
            assert same(store.load_persistent(), expected)
    # An equal layout built anew is a layout change the store need not notice.
    rebuilt = ImageLayout(OTHER[0].entries)
    with RemanentStore(tmp_path) as store:
        store.write_retain(rebuilt, OTHER[1][::-1])
        assert same(store.load_retain(), (OTHER[0], OTHER[1][::-1]))


def test_sequence_increases_across_writes_and_stores(tmp_path: Path) -> None:
    seen: list[int] = []
    for _ in range(3):
        with RemanentStore(tmp_path) as store:
            for _ in range(3):
                store.write_retain(*SMALL)
                store.write_persistent(*SMALL)
                retained, persisted = store.load_retain(), store.load_persistent()
                assert retained is not None and persisted is not None
                assert retained.sequence == persisted.sequence
                seen.append(retained.sequence)
    assert seen == list(range(1, 10))


def test_retain_writes_alternate_between_two_slots(tmp_path: Path) -> None:
    first, second, third = ints("Main.a", [1]), ints("Main.a", [2]), ints("Main.a", [3])
    with RemanentStore(tmp_path) as store:
        store.write_retain(*first)
        store.write_retain(*second)
        raw = (tmp_path / "retain.dat").read_bytes()
        assert len(raw) == 2 * PAGE
        a, b = header_at(raw, 0), header_at(raw, PAGE)
        assert (a["slot"], a["sequence"], b["slot"], b["sequence"]) == (0, 1, 1, 2)
        assert a["slot_size"] == b["slot_size"] == PAGE
        assert same(store.load_retain(), second)
        store.write_retain(*third)
        raw = (tmp_path / "retain.dat").read_bytes()
        assert (header_at(raw, 0)["sequence"], header_at(raw, PAGE)["sequence"]) == (3, 2)
        assert same(store.load_retain(), third)
        # Both slots hold a complete image: hiding the newest shows the other.
        flip(tmp_path / "retain.dat", 100)
        with pytest.warns(StoreWarning):
            assert same(store.load_retain(), second)


@pytest.mark.parametrize("writes", [1, 2, 3])
def test_an_erased_retain_slot_is_damage_not_an_empty_slot(tmp_path: Path, writes: int) -> None:
    images = [SMALL, OTHER, SMALL][:writes]
    with RemanentStore(tmp_path) as store:
        for written in images:
            store.write_retain(*written)
    raw = bytearray((tmp_path / "retain.dat").read_bytes())
    newest = max((0, 1), key=lambda slot: header_at(bytes(raw), slot * PAGE)["sequence"])
    raw[newest * PAGE:newest * PAGE + 80] = bytes(80)
    (tmp_path / "retain.dat").write_bytes(bytes(raw))
    with RemanentStore(tmp_path) as store:
        letter = "AB"[newest]
        outcome = "no valid RETAIN image" if writes == 1 else "using slot"
        with pytest.warns(StoreWarning, match=rf"slot {letter}: header is all zero bytes \(a written slot was erased\)"
                                              rf".*{outcome}"):
            loaded = store.load_retain()
        if writes == 1:
            assert loaded is None  # the other slot holds only the empty filler record
        else:
            assert same(loaded, images[-2]) and loaded is not None and loaded.from_backup


def test_one_store_per_directory(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        with pytest.raises(store_module.StoreLockedError, match=rf"{tmp_path} is in use.*{tmp_path / 'lock'}"):
            RemanentStore(tmp_path)
        assert same(store.load_retain(), SMALL), "the refused store disturbed the open one"
    with RemanentStore(tmp_path) as again:
        assert same(again.load_retain(), SMALL)


def test_documented_record_layout(tmp_path: Path) -> None:
    layout, data = SMALL
    with RemanentStore(tmp_path) as store:
        store.write_persistent(layout, data)
        store.write_retain(layout, data)
    raw = (tmp_path / "persistent.dat").read_bytes()
    header = header_at(raw)
    assert header == {
        "magic": MAGIC, "version": 1, "kind": PERSISTENT, "slot": 0, "reserved": 0, "sequence": 1,
        "slot_size": 0, "digest": layout.digest, "layout_length": len(layout.serialised), "data_length": len(data),
        "record_crc": header["record_crc"], "header_crc": header["header_crc"],
    }
    assert raw[80:] == layout.serialised + data
    assert raw == forge(layout.serialised, data)
    retain = (tmp_path / "retain.dat").read_bytes()
    assert retain == written_retain(layout.serialised, data)


def test_growing_record_rewrites_the_file_and_keeps_the_previous_image(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        store.write_retain(*BIG)
        raw = (tmp_path / "retain.dat").read_bytes()
        slot_size = header_at(raw)["slot_size"]
        assert slot_size > PAGE and slot_size % PAGE == 0 and len(raw) == 2 * slot_size
        assert same(store.load_retain(), BIG)
        store.write_retain(*SMALL)
        store.write_retain(*BIG)
        assert len((tmp_path / "retain.dat").read_bytes()) == len(raw), "it fits now: no new file"
        assert same(store.load_retain(), BIG)
    assert not (tmp_path / "retain.dat.tmp").exists()
    # The grown file still holds the image before the growth in its other slot.
    with RemanentStore(tmp_path) as store:
        bigger = pack_image([(f"x{index}", "LWORD", b"\x01" * 8) for index in range(2000)])
        store.write_retain(*bigger)
        assert len((tmp_path / "retain.dat").read_bytes()) > len(raw)
        newest = (tmp_path / "retain.dat").read_bytes()
        slot_size = header_at(newest)["slot_size"]
        newest_slot = 0 if header_at(newest, 0)["sequence"] > header_at(newest, slot_size)["sequence"] else 1
        flip(tmp_path / "retain.dat", newest_slot * slot_size + 90)
        with pytest.warns(StoreWarning, match="checksum mismatch"):
            loaded = store.load_retain()
        assert same(loaded, BIG) and loaded is not None and loaded.from_backup


def test_rewrite_after_damage_makes_room_for_a_larger_previous_image(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        store.write_retain(*BIG)        # grows the file; BIG in slot A
    path = tmp_path / "retain.dat"
    path.write_bytes(path.read_bytes()[:len(path.read_bytes()) // 2])
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="slot B: truncated"):
            assert same(store.load_retain(), BIG)
        store.write_retain(*SMALL)      # a new file, BIG kept in slot A
        assert same(store.load_retain(), SMALL) and not store.problems
        raw = path.read_bytes()
        assert header_at(raw)["slot_size"] >= 80 + len(BIG[0].serialised) + len(BIG[1])
        flip(path, header_at(raw)["slot_size"] + 90)
        with pytest.warns(StoreWarning):
            assert same(store.load_retain(), BIG)


def test_clear_retain(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        store.clear_retain()
        assert store.load_retain() is None and store.problems == []
        assert not (tmp_path / "retain.dat").exists()
        store.write_retain(*SMALL)
        loaded = store.load_retain()
        assert same(loaded, SMALL) and loaded is not None and loaded.sequence == 3
    with RemanentStore(tmp_path) as store:
        store.clear_retain()
        assert store.load_retain() is None


def test_clear_persistent(tmp_path: Path) -> None:
    with RemanentStore(tmp_path, durability="power") as store:
        store.write_persistent(*SMALL)
        store.write_persistent(*OTHER)
        (tmp_path / "persistent.dat.tmp").write_bytes(b"left over by a kill")
        store.clear_persistent()
        assert data_files(tmp_path) == []
        assert store.load_persistent() is None and store.problems == []
        store.write_persistent(*SMALL)
        assert same(store.load_persistent(), SMALL)


def test_closed_store_refuses_work(tmp_path: Path) -> None:
    store = RemanentStore(tmp_path)
    store.write_retain(*SMALL)
    store.close()
    store.close()
    for call in (lambda: store.write_retain(*SMALL), store.load_retain, store.clear_retain,
                 lambda: store.write_persistent(*SMALL), store.load_persistent, store.clear_persistent):
        with pytest.raises(ValueError, match="is closed"):
            call()
    assert "durability='process'" in repr(store)


def test_unknown_durability_is_rejected(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="durability must be"):
        RemanentStore(tmp_path, durability="disk")  # type: ignore[arg-type]


def test_power_durability_syncs_and_process_does_not(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[str] = []
    for name in ("fsync", "fdatasync"):
        original = getattr(os, name)

        def counting(fd: int, name: str = name, original: Callable[[int], None] = original) -> None:
            calls.append(name)
            original(fd)
        monkeypatch.setattr(os, name, counting)
    with RemanentStore(tmp_path / "process") as store:
        for _ in range(3):
            store.write_retain(*SMALL)
            store.write_persistent(*SMALL)
    assert calls == []
    with RemanentStore(tmp_path / "power", durability="power") as store:
        store.write_retain(*SMALL)       # new file: file and directory
        assert calls == ["fsync", "fsync"]
        store.write_retain(*SMALL)       # in place: the data only
        assert calls[2:] == ["fdatasync"]
        del calls[:]
        store.write_persistent(*SMALL)
        assert calls == ["fsync", "fsync"]


# -- damage -------------------------------------------------------------------------


def test_only_the_newest_slot_damaged_gives_the_previous_image(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        flip(tmp_path / "retain.dat", PAGE + 80 + 3)
        with pytest.warns(StoreWarning, match=r"slot B: record checksum mismatch.*\[sequence 2\].*using slot A"):
            loaded = store.load_retain()
        assert same(loaded, SMALL) and loaded is not None and loaded.from_backup
        assert store.problems and "slot B" in store.problems[0]
        # The next write replaces the damaged slot; the store is clean again.
        store.write_retain(*OTHER)
        loaded = store.load_retain()
        assert same(loaded, OTHER) and loaded is not None and loaded.sequence == 3 and not loaded.from_backup
        assert store.problems == []


def test_damaged_older_slot_is_reported_but_the_newest_image_is_not_a_backup(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        flip(tmp_path / "retain.dat", 90)
        with pytest.warns(StoreWarning, match=r"slot A: record checksum mismatch \(damaged.*\[sequence 1\]"):
            loaded = store.load_retain()
        assert same(loaded, OTHER) and loaded is not None and not loaded.from_backup


def test_unreadable_header_counts_as_a_possibly_newer_image(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        flip(tmp_path / "retain.dat", 20)
        with pytest.warns(StoreWarning, match="slot A: header checksum mismatch"):
            loaded = store.load_retain()
        assert same(loaded, OTHER) and loaded is not None and loaded.from_backup


def test_slot_b_is_found_when_slot_a_is_unreadable(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
    flip(tmp_path / "retain.dat", 0)
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="slot A: bad magic"):
            assert same(store.load_retain(), OTHER)
        # The writer goes on in the damaged slot.
        store.write_retain(*SMALL)
        assert same(store.load_retain(), SMALL) and store.problems == []


def test_no_valid_slot_loads_nothing_and_says_so(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        flip(tmp_path / "retain.dat", 90)
        flip(tmp_path / "retain.dat", PAGE + 90)
        with pytest.warns(StoreWarning, match="no valid RETAIN image; RETAIN variables start from their initial"):
            assert store.load_retain() is None
        assert len(store.problems) == 3


def test_truncated_retain_file(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
    path = tmp_path / "retain.dat"
    path.write_bytes(path.read_bytes()[:PAGE + 50])
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match=r"slot B: truncated: 50 of 80 header bytes"):
            loaded = store.load_retain()
        assert same(loaded, SMALL) and loaded is not None and loaded.from_backup
        # Not the shape the writer keeps: the first write makes a whole new file.
        store.write_retain(*OTHER)
        assert len(path.read_bytes()) == 2 * PAGE
        assert same(store.load_retain(), OTHER)
        store.write_retain(*SMALL)
        assert same(store.load_retain(), SMALL) and store.problems == []
    path.write_bytes(b"")
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="no valid RETAIN image"):
            assert store.load_retain() is None


def test_damaged_persistent_file_falls_back_to_the_older_generation(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_persistent(*SMALL)
        store.write_persistent(*OTHER)
        flip(tmp_path / "persistent.dat", 85)
        with pytest.warns(StoreWarning, match=r"persistent.dat: record checksum.*using the older generation "
                                              r"persistent.dat.bak \(sequence 1\)"):
            loaded = store.load_persistent()
        assert same(loaded, SMALL) and loaded is not None and loaded.from_backup
        # A save must not rotate the damaged file over the good backup.
        store.write_persistent(*OTHER)
        assert header_at((tmp_path / "persistent.dat.bak").read_bytes())["sequence"] == 1
        loaded = store.load_persistent()
        assert same(loaded, OTHER) and loaded is not None and loaded.sequence == 3


def test_missing_persistent_file_falls_back_to_the_older_generation(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_persistent(*SMALL)
        store.write_persistent(*OTHER)
    (tmp_path / "persistent.dat").unlink()
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="persistent.dat: missing"):
            loaded = store.load_persistent()
        assert same(loaded, SMALL) and loaded is not None and loaded.from_backup


def test_damaged_backup_is_reported_while_the_newest_loads(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_persistent(*SMALL)
        store.write_persistent(*OTHER)
        (tmp_path / "persistent.dat.bak").write_bytes(b"junk")
        with pytest.warns(StoreWarning, match=r"persistent.dat.bak: truncated.*; using persistent.dat"):
            loaded = store.load_persistent()
        assert same(loaded, OTHER) and loaded is not None and not loaded.from_backup


def test_no_valid_persistent_generation(tmp_path: Path) -> None:
    (tmp_path / "persistent.dat").write_bytes(bytes(200))
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="header is all zero bytes; no valid PERSISTENT image"):
            assert store.load_persistent() is None
        assert store.problems == ["persistent.dat: header is all zero bytes", "no valid PERSISTENT image"]


def test_problems_hold_the_reports_of_the_last_loads(tmp_path: Path) -> None:
    with RemanentStore(tmp_path) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        store.write_persistent(*SMALL)
        flip(tmp_path / "retain.dat", 90)
        (tmp_path / "persistent.dat.bak").write_bytes(b"")
        with pytest.warns(StoreWarning):
            store.load_retain()
        with pytest.warns(StoreWarning):
            store.load_persistent()
        assert [problem.split(":")[0] for problem in store.problems] == ["retain.dat slot A", "persistent.dat.bak"]
        store.clear_persistent()
        assert store.load_persistent() is None
        assert len(store.problems) == 1


# -- hostile files ------------------------------------------------------------------

GOOD_LAYOUT = layout_bytes((b"Main.a", b"INT", 2))


@pytest.mark.parametrize(("layout", "data", "fields", "message"), [
    (GOOD_LAYOUT, b"\x01\x00", {"layout_length": 0xFFFF_FFFF}, "truncated: record needs 4294967377 bytes"),
    (GOOD_LAYOUT, b"\x01\x00", {"data_length": 0xFFFF_FFFF}, "truncated: record needs"),
    (GOOD_LAYOUT, b"\x01\x00", {"layout_length": 3, "data_length": 0}, "unexpected bytes after the record"),
    (GOOD_LAYOUT, b"\x01\x00", {"header_crc": 0}, "header checksum mismatch"),
    (GOOD_LAYOUT, b"\x01\x00", {"record_crc": 0}, "record checksum mismatch"),
    (GOOD_LAYOUT, b"\x01\x00", {"magic": b"IECOOPRX"}, "bad magic"),
    (GOOD_LAYOUT, b"\x01\x00", {"version": 2}, "unsupported format version 2"),
    (GOOD_LAYOUT, b"\x01\x00", {"kind": RETAIN}, "holds a RETAIN record where a PERSISTENT record belongs"),
    (GOOD_LAYOUT, b"\x01\x00", {"kind": 9}, "holds a kind 9 record"),
    (GOOD_LAYOUT, b"\x01\x00", {"reserved": 1}, "reserved header field"),
    (GOOD_LAYOUT, b"\x01\x00", {"slot": 1}, "belongs to slot 1"),
    (GOOD_LAYOUT, b"\x01\x00", {"slot_size": PAGE}, "slot size is set in a PERSISTENT record"),
    (GOOD_LAYOUT, b"\x01\x00", {"digest": bytes(32)}, "layout digest mismatch"),
    (GOOD_LAYOUT, b"\x01\x00\x02", {}, "entry sizes add up to 2 bytes, the data has 3"),
    (layout_bytes(count=0xFFFF_FFFF), b"", {}, "claims 4294967295 entries"),
    (layout_bytes((b"Main.a", b"INT", 2), count=2), b"\x01\x00", {}, "entry 1: path length beyond the end"),
    (b"\x01\x00", b"", {}, "shorter than its entry count"),
    (layout_bytes((b"Main.a", b"INT", 2)) + b"\x00", b"\x01\x00", {}, "1 bytes after its last entry"),
    (layout_bytes((b"\xff\xfe", b"INT", 2)), b"\x01\x00", {}, "path is not valid UTF-8"),
    (layout_bytes((b"Main.a", b"\xc3", 2)), b"\x01\x00", {}, "signature is not valid UTF-8"),
    (struct.pack("<IH", 1, 0xFFFF) + b"a" * 8, b"", {}, "path of 65535 bytes beyond the end"),
    (struct.pack("<IH", 1, 5) + b"abcde\x07", b"", {}, "entry 0: signature length beyond the end"),
    (struct.pack("<IH", 1, 2) + b"ab" + struct.pack("<H", 0) + b"\x01\x02", b"", {},
     "entry 0: size beyond the end"),
    (layout_bytes((b"Main.a", b"INT", 2), (b"Main.a", b"INT", 2)), b"\x01\x00" * 2, {}, "occurs twice"),
    (layout_bytes((b"", b"INT", 2)), b"\x01\x00", {}, "non-empty str"),
])
def test_hostile_persistent_record_is_reported_not_loaded(
        tmp_path: Path, layout: bytes, data: bytes, fields: dict[str, Any], message: str) -> None:
    (tmp_path / "persistent.dat").write_bytes(forge(layout, data, **fields))
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="no valid PERSISTENT image"):
            assert store.load_persistent() is None
        assert message in store.problems[0]


@pytest.mark.parametrize(("fields", "message"), [
    ({"slot_size": 100}, "slot size 100 is not a positive multiple of 4096"),
    ({"slot_size": PAGE, "layout_length": PAGE}, "exceed the slot size 4096"),
    ({"slot_size": PAGE, "slot": 1}, "belongs to slot 1, found in slot 0"),
    ({"slot_size": PAGE, "kind": PERSISTENT}, "holds a PERSISTENT record where a RETAIN record belongs"),
])
def test_hostile_retain_header_is_reported_not_loaded(tmp_path: Path, fields: dict[str, Any], message: str) -> None:
    (tmp_path / "retain.dat").write_bytes(forge_retain(GOOD_LAYOUT, b"\x01\x00", **fields))
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="no valid RETAIN image"):
            assert store.load_retain() is None
        assert message in store.problems[0]


def test_huge_slot_size_is_not_followed_into_an_allocation(tmp_path: Path) -> None:
    # Slot A is a sound record; the slot size it states puts slot B far beyond the file.
    (tmp_path / "retain.dat").write_bytes(forge_retain(GOOD_LAYOUT, b"\x01\x00", slot_size=1 << 62))
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="slot B: truncated: 0 of 80 header bytes present; using slot A"):
            loaded = store.load_retain()
        assert loaded is not None and loaded.values() == {"Main.a": ("INT", b"\x01\x00")} and loaded.from_backup
        # The writer does not take over a file of that shape: it writes a new one.
        store.write_retain(*SMALL)
        assert len((tmp_path / "retain.dat").read_bytes()) == 2 * PAGE
        assert same(store.load_retain(), SMALL) and not store.problems


def test_slot_at_the_wrong_offset_is_not_loaded(tmp_path: Path) -> None:
    # A valid slot-B record of an 8 KiB-slot file placed where a 4 KiB file has slot B.
    record = forge(GOOD_LAYOUT, b"\x01\x00", kind=RETAIN, slot=1, slot_size=2 * PAGE)
    (tmp_path / "retain.dat").write_bytes(bytes(PAGE) + record + bytes(PAGE - len(record)))
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="slot size 8192 does not match the slot's offset 4096"):
            assert store.load_retain() is None


fields_strategy = st.fixed_dictionaries({}, optional={
    "layout_length": st.integers(0, 0xFFFF_FFFF),
    "data_length": st.integers(0, 0xFFFF_FFFF),
    "slot_size": st.integers(0, (1 << 64) - 1),
    "slot": st.integers(0, 1),
    "sequence": st.integers(0, (1 << 64) - 1),
})


@settings(max_examples=300, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])
@given(layout=st.one_of(st.binary(max_size=64), st.lists(
           st.tuples(st.binary(max_size=6), st.binary(max_size=4), st.integers(0, 0xFFFF_FFFF)), max_size=4,
       ).map(lambda entries: layout_bytes(*entries))),
       data=st.binary(max_size=16), fields=fields_strategy, kind=st.sampled_from(["retain", "persistent"]),
       tail=st.binary(max_size=64))
def test_forged_records_with_valid_checksums_never_raise(
        layout: bytes, data: bytes, fields: dict[str, Any], kind: str, tail: bytes) -> None:
    # The checksums hold, so only the parser's own checks stand between these
    # bytes and the runtime.
    with tempfile.TemporaryDirectory() as folder, RemanentStore(folder) as store, quiet():
        fields = dict(fields)
        if kind == "retain":
            slot_size = fields.pop("slot_size", PAGE)
            Path(folder, "retain.dat").write_bytes(forge(layout, data, kind=RETAIN, slot_size=slot_size, **fields)
                                                   + tail)
            loaded = store.load_retain()
        else:
            Path(folder, "persistent.dat").write_bytes(forge(layout, data, **fields) + tail)
            loaded = store.load_persistent()
        if loaded is None:
            assert store.problems
        else:
            assert (loaded.layout.serialised, loaded.data) == (layout, data)


@settings(max_examples=200, deadline=None, database=None)
@given(st.binary(max_size=300), st.sampled_from(["retain", "persistent"]))
def test_random_bytes_never_raise(raw: bytes, kind: str) -> None:
    with tempfile.TemporaryDirectory() as folder, RemanentStore(folder) as store, quiet():
        Path(folder, f"{kind}.dat").write_bytes(raw)
        assert (store.load_retain() if kind == "retain" else store.load_persistent()) is None
        assert store.problems


# -- corruption after real writes ---------------------------------------------------

IMAGES = [SMALL, OTHER, EMPTY, BIG, ints("Main.v", list(range(40)))]


# (layout number, seed of its data): one of a few layouts, one big enough to
# grow the file, drawn as numbers so failing examples print short.
image_keys = st.tuples(st.integers(0, len(IMAGES) - 1), st.integers(0, 1 << 32))


def build(keys: list[tuple[int, int]]) -> list[Image]:
    return [(IMAGES[index][0], random.Random(seed).randbytes(IMAGES[index][0].size)) for index, seed in keys]


# (operation, anchor, offset, value): the anchor puts offsets near the start of
# the file or of its second half, where the headers are, or anywhere.
mutations = st.lists(st.tuples(
    st.sampled_from(["flip", "set", "truncate"]), st.sampled_from(["start", "middle", "anywhere"]),
    st.integers(0, 1 << 24), st.integers(0, 255)), min_size=1, max_size=4)


def mutate(path: Path, operations: list[tuple[str, str, int, int]]) -> None:
    raw = bytearray(path.read_bytes())
    for operation, anchor, offset, value in operations:
        if not raw:
            break
        base = {"start": 0, "middle": len(raw) // 2, "anywhere": 0}[anchor]
        position = (base + (offset if anchor == "anywhere" else offset % 160)) % len(raw)
        if operation == "flip":
            raw[position] ^= 1 << (value % 8)
        elif operation == "set":
            raw[position] = value
        else:
            del raw[position:]
    path.write_bytes(bytes(raw))


def check_damaged_load(loaded: LoadedImage | None, store: RemanentStore, written: list[Image],
                       caught: list[warnings.WarningMessage], untouched: bool) -> None:
    warned = any(issubclass(warning.category, StoreWarning) for warning in caught)
    assert warned == bool(store.problems)
    if loaded is None:
        # Without any file there is nothing to report: a store never written.
        assert store.problems or not data_files(store.path), "nothing loaded and nothing reported"
        return
    got = (loaded.layout, loaded.data)
    assert got in written[-2:], "an image that was never written, or not among the last two"
    if got != written[-1]:
        assert loaded.from_backup and warned
    if untouched:
        assert got == written[-1] and not loaded.from_backup and not warned


@settings(max_examples=150, deadline=None, database=None)
@given(keys=st.lists(image_keys, min_size=1, max_size=6), operations=mutations)
def test_corrupted_retain_file_gives_a_written_image_or_nothing(
        keys: list[tuple[int, int]], operations: list[tuple[str, str, int, int]]) -> None:
    writes = build(keys)
    with tempfile.TemporaryDirectory() as folder:
        with RemanentStore(folder) as store:
            for layout, data in writes:
                store.write_retain(layout, data)
        path = Path(folder, "retain.dat")
        before = path.read_bytes()
        mutate(path, operations)
        with RemanentStore(folder) as store, quiet() as caught:
            loaded = store.load_retain()
            check_damaged_load(loaded, store, writes, caught, path.read_bytes() == before)
            # Whatever was found, writing goes on and is read back cleanly.
            store.write_retain(*writes[0])
            assert same(store.load_retain(), writes[0]) and not store.problems


@settings(max_examples=150, deadline=None, database=None)
@given(keys=st.lists(image_keys, min_size=1, max_size=4), operations=mutations,
       target=st.sampled_from(["persistent.dat", "persistent.dat.bak", "delete persistent.dat"]))
def test_corrupted_persistent_files_give_a_written_image_or_nothing(
        keys: list[tuple[int, int]], operations: list[tuple[str, str, int, int]], target: str) -> None:
    writes = build(keys)
    with tempfile.TemporaryDirectory() as folder:
        with RemanentStore(folder) as store:
            for layout, data in writes:
                store.write_persistent(layout, data)
        untouched = True
        if target.startswith("delete"):
            Path(folder, "persistent.dat").unlink()
            untouched = False
        elif Path(folder, target).exists():
            before = Path(folder, target).read_bytes()
            mutate(Path(folder, target), operations)
            untouched = Path(folder, target).read_bytes() == before
        with RemanentStore(folder) as store, quiet() as caught:
            loaded = store.load_persistent()
            check_damaged_load(loaded, store, writes, caught, untouched)
            store.write_persistent(*writes[0])
            assert same(store.load_persistent(), writes[0])


# -- a crash at every step ----------------------------------------------------------


class Crash(BaseException):
    """Stands for the process dying at that instant."""


@contextmanager
def crash_at(monkeypatch: pytest.MonkeyPatch, name: str, call: int) -> Iterator[list[int]]:
    """Make the ``call``-th ``os.<name>`` raise Crash instead of running."""
    original = getattr(os, name)
    calls = [0]

    def failing(*args: Any) -> Any:
        calls[0] += 1
        if calls[0] == call + 1:
            raise Crash
        return original(*args)
    with monkeypatch.context() as patch:
        patch.setattr(os, name, failing)
        yield calls


STEPS = [(name, call) for name in ("pwrite", "replace", "link", "fsync", "fdatasync", "open") for call in range(3)]


@pytest.mark.parametrize("durability", ["process", "power"])
@pytest.mark.parametrize(("name", "call"), STEPS)
def test_crash_while_saving_persistent_keeps_the_last_completed_save(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, durability: Any, name: str, call: int) -> None:
    with RemanentStore(tmp_path, durability=durability) as store:
        store.write_persistent(*SMALL)
        store.write_persistent(*OTHER)
        with crash_at(monkeypatch, name, call) as calls:
            try:
                store.write_persistent(*BIG)
                completed = True
            except Crash:
                completed = False
        if calls[0] <= call:
            assert completed, "no such step"
            return
        store.close()  # the process dies, and its lock on the store with it
        with quiet(), RemanentStore(tmp_path) as fresh:
            loaded = fresh.load_persistent()
        # An interrupted save may have reached its final rename (then only the
        # directory sync was missing); anything else leaves the previous save.
        assert same(loaded, BIG) if completed else (same(loaded, OTHER) or same(loaded, BIG))


@pytest.mark.parametrize("durability", ["process", "power"])
@pytest.mark.parametrize(("name", "call"), STEPS)
def test_crash_while_growing_retain_keeps_the_last_completed_write(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, durability: Any, name: str, call: int) -> None:
    with RemanentStore(tmp_path, durability=durability) as store:
        store.write_retain(*SMALL)
        store.write_retain(*OTHER)
        with crash_at(monkeypatch, name, call):
            try:
                store.write_retain(*BIG)
                completed = True
            except Crash:
                completed = False
        store.close()  # the process dies, and its lock on the store with it
        with quiet(), RemanentStore(tmp_path) as fresh:
            loaded = fresh.load_retain()
        assert same(loaded, BIG) if completed else (same(loaded, OTHER) or same(loaded, BIG))


def test_torn_retain_write_leaves_the_previous_image(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    original = os.pwrite

    def half(fd: int, data: Any, offset: int) -> int:
        original(fd, bytes(data)[:len(data) // 2], offset)
        raise Crash
    with RemanentStore(tmp_path) as store:
        store.write_retain(*ints("Main.a", [1] * 200))
        store.write_retain(*ints("Main.a", [2] * 200))
        monkeypatch.setattr(os, "pwrite", half)
        with pytest.raises(Crash):
            store.write_retain(*ints("Main.a", [3] * 200))
        monkeypatch.setattr(os, "pwrite", original)
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match=r"slot A: record checksum mismatch.*\[sequence 3\]"):
            loaded = store.load_retain()
        assert same(loaded, ints("Main.a", [2] * 200)) and loaded is not None and loaded.from_backup
        store.write_retain(*ints("Main.a", [4] * 200))
        assert same(store.load_retain(), ints("Main.a", [4] * 200)) and not store.problems


def test_backup_is_copied_where_hard_links_are_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*args: Any) -> None:
        raise PermissionError("no hard links here")
    monkeypatch.setattr(os, "link", refuse)
    with RemanentStore(tmp_path) as store:
        store.write_persistent(*SMALL)
        store.write_persistent(*OTHER)
    (tmp_path / "persistent.dat").unlink()
    with RemanentStore(tmp_path) as store:
        with pytest.warns(StoreWarning, match="missing"):
            assert same(store.load_persistent(), SMALL)


def test_store_module_needs_nothing_outside_the_standard_library() -> None:
    source = Path(store_module.__file__).read_text(encoding="utf-8")
    imports = {line.split()[1].split(".")[0] for line in source.splitlines() if line.startswith(("import ", "from "))}
    assert imports <= {"__future__", "collections", "dataclasses", "errno", "fcntl", "hashlib", "msvcrt", "os",
                       "pathlib", "struct", "sys", "threading", "types", "typing", "warnings", "weakref", "zlib",
                       "iecoop"}
    assert "pickle" not in source and "eval(" not in source
