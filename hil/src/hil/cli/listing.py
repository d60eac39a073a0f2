"""`hil run --list-scenarios`: the scenarios shipped with hil (hil.io.paths.SCENARIOS), by the
name `hil run`, `campaign` and `sweep` take, with their aircraft and description.  Read with
tomllib alone: the listing needs neither the DBC nor the scenario validator."""
from __future__ import annotations

import tomllib

from hil.io import paths


def scenarios() -> str:
    """One line per shipped scenario: name, aircraft, description."""
    rows = []
    for name, path in paths.shipped(paths.SCENARIOS).items():
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        rows.append((name, str(data.get("aircraft", "")), str(data.get("description", ""))))
    width = max(len(r[0]) for r in rows)
    return "\n".join(f"{name:<{width}}  {aircraft:<7}  {text}" for name, aircraft, text in rows)
