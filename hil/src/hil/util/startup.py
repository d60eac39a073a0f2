"""A program's first moments: SIGINT, SIGTERM or SIGHUP while its modules are still being
imported (`hil` imports for up to 0.5 s in the UML guest) end it at once, with one line and the
signal's exit status (128 + its number), not a KeyboardInterrupt traceback from inside some
import, nor an interrupt swallowed by an import's callback ("Exception ignored in ...").
Nothing has been started or written then, so there is nothing to stop or keep.

Importing this module installs the handlers (a program imports it first of all, before its
other imports: hil.cli does); started() puts back what was there, for the program's own
handling from then on.  The line names the program as it was called (sys.argv[0]).  A signal
ignored (`nohup`, a background job) stays ignored; a thread other than the main one installs
nothing.
"""
from __future__ import annotations

import os
import signal
import sys

#: the signals that stop a program, and how its one line names each
STOPPING = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated by SIGTERM",
            signal.SIGHUP: "terminated by SIGHUP"}


def _exit_at_once(signum: int, _frame: object) -> None:
    prog = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else "python"
    try:
        os.write(2, f"{prog}: {STOPPING[signal.Signals(signum)]}\n".encode())
    except OSError:  # no stderr: the status says it
        pass
    os._exit(128 + signum)


def _install() -> dict[signal.Signals, signal.Handlers | int | object]:
    previous: dict[signal.Signals, signal.Handlers | int | object] = {}
    try:
        for sig in STOPPING:
            if signal.getsignal(sig) != signal.SIG_IGN:
                previous[sig] = signal.signal(sig, _exit_at_once)
    except ValueError:  # not the main thread: the process's signals are not ours to take
        pass
    return previous


_previous = _install()


def started() -> None:
    """The program has its handlers to set: the ones before this module's are back."""
    while _previous:
        sig, handler = _previous.popitem()
        signal.signal(sig, signal.SIG_DFL if handler is None else handler)  # type: ignore[arg-type]
