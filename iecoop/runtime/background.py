"""A runtime's background run: one daemon thread, a stop that joins it, and what ended it kept for the caller.

``Runtime.start`` / ``stop_running`` / ``running`` are the public face; this
module holds the thread's bookkeeping so the runtime's cycle code stays where
it is.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Callable

__all__ = ["Background"]


class Background:
    """The thread running a runtime's cycles, the event that halts it, and the error that ended it."""

    __slots__ = ("thread", "halt", "error")

    def __init__(self) -> None:
        self.thread: threading.Thread | None = None
        self.halt = threading.Event()
        self.error: BaseException | None = None

    def start(
        self,
        name: str,
        hold: Callable[[], contextlib.AbstractContextManager[None]],
        run: Callable[[threading.Event], None],
    ) -> None:
        """Start a thread that holds the runtime (``hold()``) and runs ``run(halt)`` in it.

        Returns once the thread holds the runtime, so a ``run()`` from the
        caller right after is refused; if the thread cannot hold it, its
        error is raised here.
        """
        self.halt.clear()
        self.error = None
        held = threading.Event()
        refused: list[BaseException] = []

        def main() -> None:
            try:
                with hold():
                    held.set()
                    run(self.halt)
            except BaseException as exc:
                if held.is_set():
                    self.error = exc
                else:
                    refused.append(exc)
            finally:
                held.set()

        thread = threading.Thread(target=main, name=name, daemon=True)
        thread.start()
        held.wait()
        if refused:
            thread.join()
            raise refused[0]
        self.thread = thread

    @property
    def alive(self) -> bool:
        return self.thread is not None and self.thread.is_alive()

    def join(self, timeout: float | None) -> bool:
        if self.thread is not None:
            self.thread.join(timeout)
            return not self.thread.is_alive()
        return True

    def stop(self) -> BaseException | None:
        """Halt the thread after its current cycle and join it; what ended it, once."""
        thread = self.thread
        if thread is None:
            return None
        self.halt.set()
        thread.join()
        self.thread = None
        error, self.error = self.error, None
        return error
