"""What an application of fcc is to the rig (hil.apps.registry lists them)."""
from __future__ import annotations

import importlib
from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, ClassVar

from hil.bus.apps import BUS_APPS, BusApp

if TYPE_CHECKING:
    from hil.bus.codec import FrameCodec
    from hil.scenario.file import Scenario
    from hil.sim.drivers import AppDriver, OracleFlag


class Application(ABC):
    """One application: a scenario's `aircraft`, a SIM_TICK.app code, a driver that flies it."""

    #: the scenario's `aircraft`, the rig's name of it: its choice of the DBC's FccApp (hil.bus.apps)
    name: ClassVar[str]
    #: the firmware programs its evaluation runs besides fcc (hil.cli.needs)
    programs: ClassVar[tuple[str, ...]] = ()
    #: its scenario's sections: [plant] and [sensors] options, and [lqg] (None: it has none)
    plant_options: ClassVar[type]
    sensor_options: ClassVar[type]
    lqg_options: ClassVar[type | None] = None
    #: "module:function" of its evaluation of a flight and of its figures (rooms above this one)
    evaluation: ClassVar[str | None] = None
    figures: ClassVar[str | None] = None

    @property
    def bus(self) -> BusApp:
        """Its frames and SIM_TICK.app code, as the DBC says them."""
        return BUS_APPS[self.name]

    @property
    def code(self) -> int:
        return self.bus.code

    @abstractmethod
    def step_period(self, scenario: Scenario) -> float:
        """Seconds between two of its steps in a flight of this scenario."""

    @abstractmethod
    def peak_bytes(self, scenario: Scenario, flights: int) -> int:
        """The memory flying it `flights` times holds at its peak (hil.runs.budget refuses a
        scenario that would need more than the machine has)."""

    def fcc_args(self, scenario: Scenario, realtime: bool) -> list[str]:
        """The options fcc takes for a flight of this scenario (after `--apps`)."""
        return []

    def design_request(self, scenario: Scenario) -> tuple[float, int] | None:
        """(period, bits) a device not configured by its command line gets through
        SIM_CONTROL (None: this application has no design to send)."""
        return None

    @abstractmethod
    def driver(self, scenario: Scenario, codec: FrameCodec, realtime: bool,
               oracle: OracleFlag) -> AppDriver:
        """The driver that flies one scenario of it (hil.sim.drivers)."""

    def hook(self, which: str) -> Callable[..., Any]:
        """Its evaluation or figures function ('evaluation', 'figures'), imported now."""
        where = getattr(self, which)
        if where is None:
            raise LookupError(f"application {self.name} has no {which}")
        module, name = where.split(":")
        return getattr(importlib.import_module(module), name)
