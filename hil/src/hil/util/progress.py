"""The one progress display of the rig, on stderr: tqdm's bar when stderr is a terminal; one
line every LINE_EVERY_S seconds otherwise (CI logs, `2>run.err`, a pipe), so a long run is
never silent and a log gets no carriage-return redraws; say() for the line that opens or
closes a long step (the Cortex-M4F cross-build).  Inside scripts/with-vcan, stderr is a
terminal exactly when the user's is.  All of it off with --quiet."""
from __future__ import annotations

import sys
import time
from typing import Any

#: a redirected stderr gets a progress line this often (none for a run that ends sooner)
LINE_EVERY_S = 10.0


class _Hidden:
    """The display nobody sees: tqdm's interface, doing nothing."""

    def update(self, n: float = 1) -> None:
        pass

    def set_postfix(self, *args: Any, **kwargs: Any) -> None:
        pass

    def close(self) -> None:
        pass

    def __enter__(self) -> _Hidden:
        return self

    def __exit__(self, *exc: object) -> None:
        pass


class _Lines(_Hidden):
    """Progress as plain lines: `DESC: 120/351 step (34 %), 12 s`."""

    def __init__(self, total: int, desc: str, unit: str) -> None:
        self.total, self.desc, self.unit = total, desc, unit
        self.done = 0.0
        self.t0 = self.last = time.monotonic()

    def update(self, n: float = 1) -> None:
        self.done += n
        now = time.monotonic()
        if now - self.last >= LINE_EVERY_S:
            self.last = now
            share = f" ({100 * self.done / self.total:.0f} %)" if self.total else ""
            print(f"{self.desc}: {self.done:g}/{self.total} {self.unit}{share}, {now - self.t0:.0f} s",
                  file=sys.stderr, flush=True)


def bar(total: int, enabled: bool, desc: str, unit: str = "step") -> Any:
    if not enabled:
        return _Hidden()
    if not sys.stderr.isatty():
        return _Lines(total, desc, unit)
    from tqdm import tqdm

    return tqdm(total=total, unit=unit, desc=desc, leave=False, dynamic_ncols=True)


def say(text: str, enabled: bool) -> None:
    """One progress line (`hil: TEXT`), where the bar would be: a long step starts or ends."""
    if enabled:
        print(f"hil: {text}", file=sys.stderr, flush=True)
