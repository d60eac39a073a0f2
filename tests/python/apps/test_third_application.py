"""A third application, registered by this test (not shipped): the rig's tables iterate over
the registered applications (hil.apps.registry), so a new one needs no branch of the rig.

"echo" has one sensor frame, an existing one (CDRW_AOA: a third application's own frames and
its SIM_TICK.app code are the DBC's, and fcc's dispatch is the C side's -- so it is not flown
on the host fcc here; docs/extending.md has the checklist), a driver that sends a ramp, a
scenario section (the CDRW's option classes), options for fcc, a design request and an
evaluation hook.
"""
from __future__ import annotations

from collections.abc import Iterator
from types import SimpleNamespace

import pytest

from hil.apps.application import Application
from hil.apps.registry import APPLICATIONS, application, of_code, register, unregister
from hil.bus import SIM_NODES, FrameCodec
from hil.bus.apps import BusApp
from hil.cli import needs
from hil.cli.parser import build
from hil.rig.config import RigConfig
from hil.rig.flight import fcc_args, lqg_request, make_drivers
from hil.runs.budget import check_memory, estimate_bytes
from hil.runs.outcome import step_periods
from hil.scenario.file import Scenario, load_default_scenario
from hil.scenario.plant_options import CdrwPlantOptions
from hil.scenario.schema import ScenarioError
from hil.scenario.sensor_options import CdrwSensorOptions
from hil.sim.drivers import AppDriver, OracleFlag, StepIO
from hil.sim.frame_faults import TxFrame

ECHO_CODE = 2


class EchoDriver(AppDriver):
    """Sends alpha = 0.001 k on CDRW_AOA at step k; fcc's answer is only counted."""

    app = ECHO_CODE
    name = "echo"

    def __init__(self, scenario: Scenario, codec: FrameCodec, realtime: bool, oracle: OracleFlag) -> None:
        period = application("echo").step_period(scenario)
        super().__init__(scenario, codec, period, round(scenario.duration / period),
                         ("CDRW_AOA",), realtime, oracle)
        self.answered = 0

    def frames_for_step(self) -> list[TxFrame]:
        t = self.t_next
        msgs = [("CDRW_AOA", {"step": self.k & 0xFFFF, "alpha": 0.001 * self.k})]
        return self.injector.outgoing(t, [*self._event_messages(self.k, self.injector.update(t), False), *msgs])

    def end_step(self, io: StepIO) -> None:
        self.answered += io.acked
        self.k += 1


def echo_evaluation(driver: EchoDriver) -> dict[str, int]:
    return {"steps": driver.k, "answered": driver.answered}


class Echo(Application):
    name = "echo"
    programs = ("sid_replay",)
    plant_options = CdrwPlantOptions
    sensor_options = CdrwSensorOptions
    evaluation = f"{__name__}:echo_evaluation"

    @property
    def bus(self) -> BusApp:
        return BusApp(name="echo", code=ECHO_CODE, sensor_frames=("CDRW_AOA",),
                      sensor_signals=(("alpha", "CDRW_AOA", "alpha"),), output_frames=(), output_auth="")

    def step_period(self, scenario: Scenario) -> float:
        return 0.05

    def peak_bytes(self, scenario: Scenario, flights: int) -> int:
        return 1000 * flights

    def fcc_args(self, scenario: Scenario, realtime: bool) -> list[str]:
        return ["--echo-gain", "2"]

    def design_request(self, scenario: Scenario) -> tuple[float, int] | None:
        return 0.05, 10

    def driver(self, scenario: Scenario, codec: FrameCodec, realtime: bool, oracle: OracleFlag) -> AppDriver:
        return EchoDriver(scenario, codec, realtime, oracle)


@pytest.fixture
def echo() -> Iterator[Application]:
    app = register(Echo())
    try:
        yield app
    finally:
        unregister("echo")


def _scenario() -> Scenario:
    return Scenario(aircraft="echo", duration=0.2, seed=3, plant=CdrwPlantOptions(), sensors=CdrwSensorOptions())


def test_the_registry_lists_it_after_the_shipped_two(echo: Application) -> None:
    assert list(APPLICATIONS) == ["cdrw", "missile", "echo"]
    assert application("echo") is echo and of_code(ECHO_CODE) is echo
    assert [of_code(a.code).name for a in APPLICATIONS.values()] == ["cdrw", "missile", "echo"]
    with pytest.raises(ValueError, match="already registered"):
        register(Echo())


def test_the_rig_gives_fcc_its_options(echo: Application, tmp_path) -> None:
    cfg = RigConfig(out_dir=tmp_path)
    missile = load_default_scenario("missile")
    args = fcc_args([load_default_scenario("cdrw"), _scenario(), missile], cfg)
    assert args[:4] == ["--mode", "lockstep", "--apps", "cdrw,echo,missile"]
    assert args[4:6] == ["--echo-gain", "2"] and "--lqg-period" in args


def test_the_first_design_request_goes_to_a_device_configured_by_sim_control(echo: Application) -> None:
    rig = SimpleNamespace(fcc=SimpleNamespace(configured_by_args=False))
    assert lqg_request(rig, [load_default_scenario("cdrw"), _scenario()]) == (0.05, 10)  # type: ignore[arg-type]
    by_args = SimpleNamespace(fcc=SimpleNamespace(configured_by_args=True))
    assert lqg_request(by_args, [_scenario()]) == (0.0, 0)  # type: ignore[arg-type]


def test_its_driver_flies_its_frames(echo: Application, tmp_path) -> None:
    codec = FrameCodec(nodes=SIM_NODES)
    (d,) = make_drivers([_scenario()], codec, RigConfig(out_dir=tmp_path))
    assert isinstance(d, EchoDriver) and d.app == ECHO_CODE and d.n_steps == 4
    peer = FrameCodec(nodes="FCC")
    while not d.done:
        k = d.k
        (frame,) = d.frames_for_step()
        assert frame.name == "CDRW_AOA"
        got = peer.decode(frame.frame_id, frame.data)
        assert got.ok and got.values is not None and got.values["alpha"] == pytest.approx(0.001 * k)
        d.end_step(StepIO(acked=True))
    assert echo.hook("evaluation")(d) == {"steps": 4, "answered": 4}


def test_the_flights_step_periods_have_it(echo: Application) -> None:
    cdrw, missile = load_default_scenario("cdrw"), load_default_scenario("missile")
    assert step_periods([cdrw, _scenario(), missile]) == {0: cdrw.plant.dt, ECHO_CODE: 0.05,
                                                           1: missile.lqg.period}


def test_the_memory_check_asks_it(echo: Application) -> None:
    assert estimate_bytes(_scenario(), 3) == 3000
    check_memory([_scenario()], 3, available=10_000)
    with pytest.raises(ScenarioError, match="needs about"):
        check_memory([_scenario()], 3, available=5_000)


def test_the_command_line_asks_for_its_programs(echo: Application) -> None:
    args = build().parse_args(["run", "cdrw"])
    args.aircraft = "echo"   # (a scenario file's aircraft is checked against the DBC's)
    assert "sid_replay" in needs.programs(args)
    args.aircraft = "missile"
    assert "sid_replay" not in needs.programs(args)


def test_the_shipped_applications_hooks_resolve() -> None:
    for app in APPLICATIONS.values():
        assert callable(app.hook("evaluation")) and callable(app.hook("figures"))
        assert app.bus.code == app.code and app.plant_options and app.sensor_options
