"""A child process for the memory tests that could take the interpreter down.

``python _memory_child.py CASE SECONDS`` runs one case and prints ``done N``
(N operations that completed) when it ends normally. A crash shows as a
signal in the return code, which the test reports as a failure.
"""

from __future__ import annotations

import sys
import threading
import time
from typing import Any

from iecoop import ARRAY, LINT, VAR, ExceptionCode, PlcException, Pointer, Struct, adr, delete, memcmp, memcpy, memset, new


class Big(Struct):
    # 2 MiB: the C allocator maps a block this large on its own and unmaps it when freed,
    # so a C call on freed memory faults at once instead of corrupting quietly.
    data: ARRAY[LINT] = VAR(bounds=(0, 262143))


def _race(operation: str, seconds: float) -> int:
    """One thread creates and deletes blocks; two run a memory operator on them meanwhile."""
    sys.setswitchinterval(1e-6)
    first = Big()
    shared: list[Pointer[Any]] = [adr(first)]
    keep = Big()
    stop = threading.Event()
    done = [0]

    def churn() -> None:
        while not stop.is_set():
            p = new(Big)
            shared[0] = p + 0
            delete(p)

    def use() -> None:
        while not stop.is_set():
            try:
                if operation == "memset":
                    memset(shared[0], 1, 8)
                elif operation == "memcpy":
                    memcpy(shared[0], adr(keep), 1 << 20)
                else:
                    memcmp(shared[0], adr(keep), 1 << 20)
                done[0] += 1
            except PlcException as exc:
                assert exc.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, exc

    threads = [threading.Thread(target=churn)] + [threading.Thread(target=use) for _ in range(2)]
    for thread in threads:
        thread.start()
    time.sleep(seconds)
    stop.set()
    for thread in threads:
        thread.join()
    return done[0]


def _handle_deletes_destination() -> int:
    """A Pointer subclass whose ``handle`` deletes the destination of the copy in progress."""
    destination = new(Big)
    source_block = Big()
    source = adr(source_block)

    class Treacherous(Pointer[Any]):
        @property
        def handle(self) -> int:
            if destination:
                delete(destination)
            return super().handle

    sneaky = Treacherous(source.handle, source._target)
    target = destination + 0
    copied = 0
    for _ in range(3):
        try:
            copied += memcpy(target, sneaky, 1 << 21)
            memset(target, 7, 1 << 21)
        except PlcException as exc:
            assert exc.code == ExceptionCode.RTSEXCPT_ACCESS_VIOLATION, exc
    return copied


def main() -> None:
    case, seconds = sys.argv[1], float(sys.argv[2])
    if case == "handle":
        count = _handle_deletes_destination()
    else:
        count = _race(case, seconds)
    print(f"done {count}", flush=True)


if __name__ == "__main__":
    main()
