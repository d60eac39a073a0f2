"""Memory before flying: a scenario's duration and step sizes decide how much the simulator
holds (the CDRW's whole flight is computed before the first tick; the missile keeps every
2.5 ms sub-step), so an absurd duration is refused up front with one line instead of the
run being OOM-killed without a message.

The per-step figures are measured (tracemalloc on the drivers: 3.0 kB per CDRW step, 0.6 kB
per missile period at T = 0.05 s) and doubled for the results computed after the flight.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

from hil.scenario.file import Scenario
from hil.scenario.schema import ScenarioError

#: bytes per CDRW step of the flight in the air (driver 3.0 kB, measured; results and the
#: bus log read back: x2.5), and of each flight a campaign keeps (its record: ~30 columns)
CDRW_STEP_BYTES = 7_500
CDRW_RECORD_BYTES = 300
#: bytes per missile 2.5 ms sub-step (driver, the reference flight, results) and per period
MISSILE_FINE_BYTES = 100
MISSILE_PERIOD_BYTES = 2_000
FINE_STEP_S = 0.0025
#: a run may plan to use at most this share of the memory available
SHARE = 0.5


def estimate_bytes(sc: Scenario, flights: int = 1) -> int:
    """What flying sc `flights` times is expected to hold at its peak."""
    if sc.aircraft == "cdrw":
        steps = math.ceil(sc.duration / sc.plant.dt)  # type: ignore[union-attr]
        return steps * (CDRW_STEP_BYTES + flights * CDRW_RECORD_BYTES)
    assert sc.lqg is not None
    per_flight = (sc.duration / FINE_STEP_S * MISSILE_FINE_BYTES
                  + sc.duration / sc.lqg.period * MISSILE_PERIOD_BYTES)
    return int(per_flight * flights)


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
