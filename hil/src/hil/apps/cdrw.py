"""The CDRW (seed 1): the pull-up flown open loop, fcc's three identification filters."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from hil.apps.application import Application
from hil.scenario.file import SECTIONS, Scenario

if TYPE_CHECKING:
    from hil.bus.codec import FrameCodec
    from hil.sim.drivers import AppDriver, OracleFlag


#: bytes per CDRW step of the flight in the air (driver 3.0 kB, measured with tracemalloc;
#: results and the bus log read back: x2.5), and of each flight a campaign keeps (its record:
#: ~30 columns)
CDRW_STEP_BYTES = 7_500
CDRW_RECORD_BYTES = 300


class Cdrw(Application):
    name = "cdrw"
    programs = ("sid_replay",)   # the cross-check of fcc's rows (hil.results.rowtables)
    plant_options, sensor_options, lqg_options = SECTIONS["cdrw"]
    evaluation = "hil.results.flight:cdrw_result"
    figures = "hil.plots.cdrw:all_figures"

    def step_period(self, scenario: Scenario) -> float:
        return float(scenario.plant.dt)  # type: ignore[union-attr]

    def peak_bytes(self, scenario: Scenario, flights: int) -> int:
        """The whole flight is computed before the first tick; a campaign keeps each record."""
        steps = math.ceil(scenario.duration / scenario.plant.dt)  # type: ignore[union-attr]
        return steps * (CDRW_STEP_BYTES + flights * CDRW_RECORD_BYTES)

    def driver(self, scenario: Scenario, codec: FrameCodec, realtime: bool,
               oracle: OracleFlag) -> AppDriver:
        from hil.sim.drivers import CdrwDriver  # numpy (hil.rig.flight's docstring)
        return CdrwDriver(scenario, codec, realtime, oracle)
