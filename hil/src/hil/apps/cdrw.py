"""The CDRW (seed 1): the pull-up flown open loop, fcc's three identification filters."""
from __future__ import annotations

from typing import TYPE_CHECKING

from hil.apps.application import Application
from hil.scenario.file import SECTIONS, Scenario

if TYPE_CHECKING:
    from hil.bus.codec import FrameCodec
    from hil.sim.drivers import AppDriver, OracleFlag


class Cdrw(Application):
    name = "cdrw"
    programs = ("sid_replay",)   # the cross-check of fcc's rows (hil.results.rowtables)
    plant_options, sensor_options, lqg_options = SECTIONS["cdrw"]
    evaluation = "hil.results.flight:cdrw_result"
    figures = "hil.plots.cdrw:all_figures"

    def step_period(self, scenario: Scenario) -> float:
        return float(scenario.plant.dt)  # type: ignore[union-attr]

    def driver(self, scenario: Scenario, codec: FrameCodec, realtime: bool,
               oracle: OracleFlag) -> AppDriver:
        from hil.sim.drivers import CdrwDriver  # numpy (hil.rig.flight's docstring)
        return CdrwDriver(scenario, codec, realtime, oracle)
