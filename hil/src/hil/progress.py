"""The one progress bar of the rig (tqdm on stderr): shown only when stderr is a terminal, so
redirected logs (CI, `2>run.err`, the UML guest's captured stderr) get no carriage-return
redraws.  A bar that is not shown does not import tqdm (half a second in the UML guest)."""
from __future__ import annotations

import sys
from typing import Any


class _Hidden:
    """The bar nobody sees: tqdm's interface, doing nothing."""

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


def bar(total: int, enabled: bool, desc: str, unit: str = "step") -> Any:
    if not (enabled and sys.stderr.isatty()):
        return _Hidden()
    from tqdm import tqdm

    return tqdm(total=total, unit=unit, desc=desc, leave=False, dynamic_ncols=True)
