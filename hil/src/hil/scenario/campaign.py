"""The fault times of a campaign (Table 5): the rig's one rule, used by `hil campaign`, its
flights on many rigs and the reference study alike.
"""
from __future__ import annotations

import math

import numpy as np

from hil.scenario.file import Scenario
from hil.scenario.schema import ScenarioError


def campaign_fault_times(scenario: Scenario, runs: int, seed: int,
                         margin: float = 0.5) -> np.ndarray:
    """Table 5: when the scenario's faults (moved together) start in each flight -- uniform
    over the flight, `margin` s clear of both ends, on the 50 Hz sample grid."""
    if not scenario.faults:
        raise ScenarioError(f"{scenario.source}: a campaign needs a scenario with a fault")
    ends = [f.end for f in scenario.faults]
    span = (max(ends) if all(math.isfinite(e) for e in ends) else 0.0) - min(f.start for f in scenario.faults)
    hi = scenario.duration - margin - max(span, 0.0)
    if hi <= margin:
        raise ScenarioError(f"{scenario.source}: the flight is too short for faults at random times")
    rng = np.random.default_rng([int(seed), 0x6361])  # own stream: "ca"
    return np.round(rng.uniform(margin, hi, size=runs) / 0.02) * 0.02
