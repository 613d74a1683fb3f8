"""The process ``test_store_kill`` kills: writes remanent images in a loop until then.

    python _store_writer.py DIRECTORY retain|persistent process|power small|large

Every entry of image ``n`` holds ``n`` (see ``image_for``), so a torn mix of two
writes cannot pass for either. Large images (megabytes) take long enough to
write that a kill often lands inside the ``pwrite`` and tears the record. The writer continues from the image it finds in
the store, prints ``ready``, and then prints ``n`` each time the write of image
``n`` has returned.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import struct
import sys
import warnings
from pathlib import Path

if __name__ == "__main__":
    # The child loads the store module by itself (it needs only the standard
    # library): skipping the import of the whole iecoop package keeps the
    # start-up that every kill pays short.
    _spec = importlib.util.spec_from_file_location(
        "iecoop.runtime.store", Path(__file__).resolve().parents[3] / "iecoop" / "runtime" / "store.py")
    assert _spec is not None and _spec.loader is not None
    _module = sys.modules[_spec.name] = importlib.util.module_from_spec(_spec)
    _spec.loader.exec_module(_module)

from iecoop.runtime.store import ImageLayout, LoadedImage, RemanentStore, StoreWarning  # noqa: E402

_LINT = struct.Struct("<q")


@functools.lru_cache(maxsize=None)
def _layout(entries: int, lints: int) -> ImageLayout:
    return ImageLayout(tuple((f"PlcTask.Main.station[{index}].count", f"ARRAY[0..{lints - 1}] OF LINT",
                              lints * _LINT.size) for index in range(entries)))


def image_for(counter: int, large: bool = False) -> tuple[ImageLayout, bytes]:
    """Image number ``counter``: its layout changes every 4 images, so fresh stores grow their file."""
    if large:
        layout = _layout(1 + (counter // 4) % 4, 1 << 18)
    else:
        layout = _layout(8 + (counter // 4) % 509, 8)
    return layout, _LINT.pack(counter) * (layout.size // _LINT.size)


def counter_of(image: LoadedImage) -> int:
    """The number the first entry of ``image`` holds."""
    value: int = _LINT.unpack_from(image.data, 0)[0]
    return value


def main(directory: str, kind: str, durability: str, size: str) -> None:
    if durability not in ("process", "power") or size not in ("small", "large"):
        raise SystemExit(f"unknown durability {durability!r} or size {size!r}")
    # Warnings about the slot a previous kill tore are expected here; the
    # parent checks what the store loads.
    warnings.simplefilter("ignore", StoreWarning)
    with RemanentStore(directory, durability="power" if durability == "power" else "process") as store:
        write, load = {
            "retain": (store.write_retain, store.load_retain),
            "persistent": (store.write_persistent, store.load_persistent),
        }[kind]
        found = load()
        counter = 1 if found is None else counter_of(found) + 1
        os.write(1, b"ready\n")
        while True:
            write(*image_for(counter, size == "large"))
            # One unbuffered write per line: a line is either all in the pipe or not at all.
            os.write(1, b"%d\n" % counter)
            counter += 1


if __name__ == "__main__":
    main(*sys.argv[1:5])
