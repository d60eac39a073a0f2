"""A third application, registered by this test (not shipped): the rig's tables iterate over
the registered applications (hil.apps.registry), so a new one needs no branch of the rig; and
it flies on the host fcc.

"probe" is the DBC's third FccApp choice (SIM_TICK.app 2) and fcc's probe application
(firmware/app/fcc_app_probe.h), compiled into a test build only (cmake -DFCC_APP_PROBE=ON,
build-probe: scripts/test vcan builds it).  It has no frames of its own: fcc answers each of
its steps with FCC_ACK, degraded on odd steps -- a pattern neither shipped application has, so
the flight shows that its own step function ran, not the missile's (once every application
but the CDRW's fell into the missile's path).  Here it has a driver that sends its ticks, a
scenario section (the CDRW's option classes), options for fcc, a design request and an
evaluation hook.
"""
from __future__ import annotations

import dataclasses
import json
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import pytest

from hil.apps.application import Application
from hil.apps.registry import APPLICATIONS, application, of_code, register, unregister
from hil.bus import SIM_NODES, FrameCodec
from hil.bus.apps import BUS_APPS
from hil.cli import needs
from hil.cli.parser import build
from hil.rig.config import RigConfig
from hil.rig.flight import fcc_args, lqg_request, make_drivers
from hil.runs.budget import check_memory, estimate_bytes
from hil.runs.outcome import step_periods
from hil.runs.run import run_flight
from hil.scenario.file import Scenario, load_default_scenario
from hil.scenario.plant_options import CdrwPlantOptions
from hil.scenario.schema import ScenarioError
from hil.scenario.sensor_options import CdrwSensorOptions
from hil.sim.drivers import AppDriver, OracleFlag, StepIO
from hil.sim.frame_faults import TxFrame

PROBE_CODE = BUS_APPS["probe"].code
#: fcc with the probe compiled in (scripts/test vcan builds it)
PROBE_FCC = Path(__file__).resolve().parents[3] / "build-probe" / "bin" / "fcc"


class ProbeDriver(AppDriver):
    """Sends the probe's ticks (it has no sensor frames) and keeps fcc's answer to each."""

    app = PROBE_CODE
    name = "probe"

    def __init__(self, scenario: Scenario, codec: FrameCodec, realtime: bool, oracle: OracleFlag) -> None:
        period = application("probe").step_period(scenario)
        super().__init__(scenario, codec, period, round(scenario.duration / period), (), realtime, oracle)
        self.answers: list[tuple[bool, bool]] = []   # (acked, degraded) of each step

    def frames_for_step(self) -> list[TxFrame]:
        t = self.t_next
        return self.injector.outgoing(t, self._event_messages(self.k, self.injector.update(t), False))

    def end_step(self, io: StepIO) -> None:
        self.answers.append((io.acked, io.degraded))
        self.k += 1


def probe_evaluation(driver: ProbeDriver) -> dict[str, object]:
    return {"steps": driver.k, "answered": sum(a for a, _ in driver.answers),
            "degraded": [d for _, d in driver.answers]}


class Probe(Application):
    name = "probe"
    programs = ("sid_replay",)
    plant_options = CdrwPlantOptions
    sensor_options = CdrwSensorOptions
    evaluation = f"{__name__}:probe_evaluation"

    def step_period(self, scenario: Scenario) -> float:
        return 0.05

    def peak_bytes(self, scenario: Scenario, flights: int) -> int:
        return 1000 * flights

    def fcc_args(self, scenario: Scenario, realtime: bool) -> list[str]:
        return ["--stale-limit", "1"]

    def design_request(self, scenario: Scenario) -> tuple[float, int] | None:
        return 0.05, 10

    def driver(self, scenario: Scenario, codec: FrameCodec, realtime: bool, oracle: OracleFlag) -> AppDriver:
        return ProbeDriver(scenario, codec, realtime, oracle)


@pytest.fixture
def probe() -> Iterator[Application]:
    app = register(Probe())
    try:
        yield app
    finally:
        unregister("probe")


def _scenario(duration: float = 0.2) -> Scenario:
    return Scenario(aircraft="probe", duration=duration, seed=3, plant=CdrwPlantOptions(),
                    sensors=CdrwSensorOptions())


def test_the_registry_lists_it_after_the_shipped_two(probe: Application) -> None:
    assert list(APPLICATIONS) == ["cdrw", "missile", "probe"]
    assert application("probe") is probe and of_code(PROBE_CODE) is probe
    assert probe.bus == BUS_APPS["probe"] and PROBE_CODE == 2   # the DBC's FccApp
    assert [of_code(a.code).name for a in APPLICATIONS.values()] == ["cdrw", "missile", "probe"]
    with pytest.raises(ValueError, match="already registered"):
        register(Probe())


def test_the_rig_gives_fcc_its_options(probe: Application, tmp_path) -> None:
    cfg = RigConfig(out_dir=tmp_path)
    missile = load_default_scenario("missile")
    args = fcc_args([load_default_scenario("cdrw"), _scenario(), missile], cfg)
    assert args[:4] == ["--mode", "lockstep", "--apps", "cdrw,probe,missile"]
    assert args[4:6] == ["--stale-limit", "1"] and "--lqg-period" in args


def test_the_first_design_request_goes_to_a_device_configured_by_sim_control(probe: Application) -> None:
    rig = SimpleNamespace(fcc=SimpleNamespace(configured_by_args=False))
    assert lqg_request(rig, [load_default_scenario("cdrw"), _scenario()]) == (0.05, 10)  # type: ignore[arg-type]
    by_args = SimpleNamespace(fcc=SimpleNamespace(configured_by_args=True))
    assert lqg_request(by_args, [_scenario()]) == (0.0, 0)  # type: ignore[arg-type]


def test_its_driver_sends_its_ticks_only(probe: Application, tmp_path) -> None:
    codec = FrameCodec(nodes=SIM_NODES)
    (d,) = make_drivers([_scenario()], codec, RigConfig(out_dir=tmp_path))
    assert isinstance(d, ProbeDriver) and d.app == PROBE_CODE and d.n_steps == 4
    while not d.done:
        assert d.frames_for_step() == []   # no sensor frames: the runner sends its SIM_TICK
        d.end_step(StepIO(acked=True, degraded=d.k % 2 == 1))
    assert probe.hook("evaluation")(d) == {"steps": 4, "answered": 4,
                                           "degraded": [False, True, False, True]}


def test_the_flights_step_periods_have_it(probe: Application) -> None:
    cdrw, missile = load_default_scenario("cdrw"), load_default_scenario("missile")
    assert step_periods([cdrw, _scenario(), missile]) == {0: cdrw.plant.dt, PROBE_CODE: 0.05,
                                                           1: missile.lqg.period}


def test_the_memory_check_asks_it(probe: Application) -> None:
    assert estimate_bytes(_scenario(), 3) == 3000
    check_memory([_scenario()], 3, available=10_000)
    with pytest.raises(ScenarioError, match="needs about"):
        check_memory([_scenario()], 3, available=5_000)


def test_the_command_line_asks_for_its_programs(probe: Application) -> None:
    args = build().parse_args(["run", "cdrw"])
    args.aircraft = "probe"   # (a scenario file's aircraft is checked against the DBC's)
    assert "sid_replay" in needs.programs(args)
    args.aircraft = "missile"
    assert "sid_replay" not in needs.programs(args)


def test_the_shipped_applications_hooks_resolve() -> None:
    for app in APPLICATIONS.values():
        assert callable(app.hook("evaluation")) and callable(app.hook("figures"))
        assert app.bus.code == app.code and app.plant_options and app.sensor_options


@pytest.mark.vcan
def test_it_flies_on_the_host_fcc_in_its_own_path(probe: Application, tmp_path) -> None:
    """A lockstep flight of the probe and the CDRW in one fcc (the test build's): every probe
    step is answered by the probe's own step (degraded on odd steps), fcc's heartbeat counts
    no missile step, and the CDRW beside it flies as ever."""
    assert PROBE_FCC.is_file(), "build-probe/bin/fcc is not built (scripts/test vcan builds it)"
    cdrw = dataclasses.replace(load_default_scenario("cdrw"), duration=0.5, faults=())
    out = run_flight([_scenario(1.0), cdrw], RigConfig(out_dir=tmp_path / "run", fcc_binary=PROBE_FCC,
                                                       progress=False, plots=False))
    summary = json.loads((out.out_dir / "summary.json").read_text())
    assert summary["probe"] == {"steps": 20, "answered": 20, "degraded": [k % 2 == 1 for k in range(20)]}
    steps = summary["firmware"]["steps"]
    assert steps["missile"] == 0 and steps["cdrw"] == 26   # the probe fell into neither path
