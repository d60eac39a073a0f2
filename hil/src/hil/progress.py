"""The one progress bar of the rig (tqdm on stderr): shown only when stderr is a terminal, so
redirected logs (CI, `2>run.err`, the UML guest's captured stderr) get no carriage-return
redraws."""
from __future__ import annotations

import sys
from typing import Any


def bar(total: int, enabled: bool, desc: str, unit: str = "step") -> Any:
    from tqdm import tqdm

    shown = enabled and sys.stderr.isatty()
    return tqdm(total=total, disable=not shown, unit=unit, desc=desc, leave=False, dynamic_ncols=True)
