"""SIGTERM and SIGHUP end a command as Ctrl-C does: clean-up runs, nothing is left behind.

``timeout``, ``kill``, ``docker stop``, CI cancellation and a closed terminal
send SIGTERM or SIGHUP, whose default action ends the process at once,
leaving temporary files (audit C32, C33).  While a command runs,
:func:`signals_as_interrupts` turns them into :class:`Terminated`, a
:class:`KeyboardInterrupt`, so every ``except BaseException``/``finally``
clean-up of the writers and of the FMU build (which kills its compiler's
process group) runs; the command exits with ``128 + signal number``.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from typing import Any, Iterator, Optional

__all__ = ["ClosedStream", "Terminated", "signals_as_interrupts", "exit_status"]

_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))


class Terminated(KeyboardInterrupt):
    """The process received SIGTERM or SIGHUP (``signum``)."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"terminated by {signal.Signals(signum).name}")
        self.signum = signum


def _raise(signum: int, frame: Any) -> None:
    raise Terminated(signum)


@contextlib.contextmanager
def signals_as_interrupts() -> Iterator[None]:
    """Raise :class:`Terminated` on SIGTERM/SIGHUP inside the block (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    for sig in _SIGNALS:
        if signal.getsignal(sig) is signal.SIG_IGN:
            continue                    # nohup: a hang-up is meant to be ignored
        previous[sig] = signal.signal(sig, _raise)
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def exit_status(exc: BaseException) -> int:
    """128 + the signal number for a termination (also when re-raised as a cause), else 130."""
    seen: Optional[BaseException] = exc
    while seen is not None:
        if isinstance(seen, Terminated):
            return 128 + seen.signum
        seen = seen.__cause__ or seen.__context__
    return 130


class ClosedStream:
    """Stands for a standard output closed before the program started (``>&-``).

    Python sets ``sys.stdout`` to None then and ``print`` writes nothing,
    so a command would exit 0 with its output lost (audit C39); writing to
    this raises :class:`BrokenPipeError`, reported as a closed output.
    """

    def write(self, text: str) -> int:
        raise BrokenPipeError(32, "standard output is closed")

    def flush(self) -> None:
        return None
