"""Memory before flying: a scenario's duration and step sizes decide how much the simulator
holds (the CDRW's whole flight is computed before the first tick; the missile keeps every
2.5 ms sub-step), so an absurd duration is refused up front with one line instead of the
run being OOM-killed without a message.

The per-step figures are each application's (hil.apps.cdrw, hil.apps.missile: measured with
tracemalloc on the drivers and doubled for the results computed after the flight).
"""
from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from hil.apps.registry import application
from hil.scenario.file import Scenario
from hil.scenario.schema import ScenarioError

#: a run may plan to use at most this share of the memory available
SHARE = 0.5


def estimate_bytes(sc: Scenario, flights: int = 1) -> int:
    """What flying sc `flights` times is expected to hold at its peak (its application's
    figures: hil.apps)."""
    return application(sc.aircraft).peak_bytes(sc, flights)


def available_bytes(meminfo: Path = Path("/proc/meminfo")) -> int | None:
    try:
        for line in meminfo.read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


def check_memory(scenarios: Sequence[Scenario], flights: int = 1,
                 available: int | None = None) -> None:
    """ScenarioError (exit 2) when the run would need more than SHARE of the free memory."""
    need = sum(estimate_bytes(sc, flights) for sc in scenarios)
    avail = available_bytes() if available is None else available
    if avail is None or need <= SHARE * avail:
        return
    sc = max(scenarios, key=lambda s: estimate_bytes(s, flights))
    raise ScenarioError(f"{sc.source}: field 'duration': {sc.duration:g} s needs about "
                        f"{need / 1e9:.1f} GB of memory, this machine has {avail / 1e9:.1f} GB "
                        f"available (at most {SHARE:.0%} of it is used); shorten the flight")
