"""The missile (seed 2): fcc's LQG autopilot closes the loop through the bus."""
from __future__ import annotations

from typing import TYPE_CHECKING

from hil.apps.application import Application
from hil.scenario.file import SECTIONS, Scenario
from hil.scenario.schema import ScenarioError
from hil.scenario.sensor_options import MissileSensorOptions

if TYPE_CHECKING:
    from hil.bus.codec import FrameCodec
    from hil.sim.drivers import AppDriver, OracleFlag

#: the LQG periods fcc accepts (firmware/app/README.md)
FCC_PERIOD_RANGE = (0.02, 0.3)


def check_missile(sc: Scenario) -> None:
    """A scenario's [lqg] period fcc runs (one line naming the field otherwise)."""
    lo, hi = FCC_PERIOD_RANGE
    assert sc.lqg is not None
    if not lo - 1e-12 <= sc.lqg.period <= hi + 1e-12:
        raise ScenarioError(f"{sc.source}: [lqg]: field 'period': fcc runs the LQG at "
                            f"{lo:g} to {hi:g} s, got {sc.lqg.period:g}")


#: bytes per missile 2.5 ms sub-step (driver, the reference flight, results; 0.6 kB per period
#: at T = 0.05 s measured with tracemalloc, doubled) and per period
MISSILE_FINE_BYTES = 100
MISSILE_PERIOD_BYTES = 2_000
FINE_STEP_S = 0.0025


class Missile(Application):
    name = "missile"
    plant_options, sensor_options, lqg_options = SECTIONS["missile"]
    evaluation = "hil.results.flight:missile_result"
    figures = "hil.plots.missile:fig_time_response"

    def fcc_args(self, scenario: Scenario, realtime: bool) -> list[str]:
        """The LQG's period, D/A bits and delay, and the sensors' noise variances."""
        sc = scenario
        assert sc.lqg is not None and isinstance(sc.sensors, MissileSensorOptions)
        check_missile(sc)
        return ["--lqg-period", f"{sc.lqg.period:.6g}", "--lqg-bits", str(sc.lqg.bits),
                "--lqg-delay", f"{sc.lqg.resolved_delay(realtime):.6g}",
                "--gyro-var", repr(sc.sensors.var_gyro), "--accel-var", repr(sc.sensors.var_acc)]

    def step_period(self, scenario: Scenario) -> float:
        assert scenario.lqg is not None
        return float(scenario.lqg.period)

    def peak_bytes(self, scenario: Scenario, flights: int) -> int:
        """Every 2.5 ms sub-step is kept."""
        assert scenario.lqg is not None
        per_flight = (scenario.duration / FINE_STEP_S * MISSILE_FINE_BYTES
                      + scenario.duration / scenario.lqg.period * MISSILE_PERIOD_BYTES)
        return int(per_flight * flights)

    def design_request(self, scenario: Scenario) -> tuple[float, int] | None:
        assert scenario.lqg is not None
        return scenario.lqg.period, scenario.lqg.bits

    def driver(self, scenario: Scenario, codec: FrameCodec, realtime: bool,
               oracle: OracleFlag) -> AppDriver:
        from hil.sim.drivers import MissileDriver  # numpy (hil.rig.flight's docstring)
        return MissileDriver(scenario, codec, realtime, oracle)
