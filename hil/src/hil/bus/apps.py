"""The applications fcc flies, as the DBC says them: each one's SIM_TICK.app code, the sensor
frames the simulator sends for it and the output frames fcc answers its steps with.  The one
source of "which sensors belong to which aircraft": the scenario's fault checks, the drivers,
the results and the bus log's reader all take their lists from here.

Read from the DBC (the packaged one's digest, as hil.bus.protocol reads it), all of it from
its FccApp attribute:
* an application is a choice of FccApp (but "none"), its rig name the choice's name; its code
  (SIM_TICK.app) the choice's place: the first application is 0 (hil.bus.cgen checks that
  SIM_TICK.app has a value for each);
* its sensor frames are the frames sent to FCC with its FccApp, in identifier order (fcc's
  input slots, dbc/generate);
* its output frames are those its own authenticator covers: the authenticator fcc sends with
  its FccApp (SecOC_Pdus); an application without one (the test build's probe) has none.
"""
from __future__ import annotations

from dataclasses import dataclass

from hil.bus.dbc import FCC_NODE, PACKAGED_DBC, BusSpec, load
from hil.bus.protocol import SENSOR_APP  # noqa: F401 - the sensor frames by identifier, from the DBC's FccApp

#: the nodes of the rig itself (neither sends an application's sensor frames)
RIG_NODES = ("SIM", FCC_NODE)
#: scenario names of the DBC's sensor signals where the two differ (a sensor fault's `signal=`)
SCENARIO_SIGNAL = {"delta_e": "de"}


@dataclass(frozen=True)
class BusApp:
    """An application on the bus."""

    name: str
    code: int
    #: the frames the simulator sends for it, in identifier order
    sensor_frames: tuple[str, ...]
    #: (scenario name, frame, DBC signal) of each sensor reading, in the frames' order
    sensor_signals: tuple[tuple[str, str, str], ...]
    #: the frames fcc answers one of its steps with, and their authenticator
    output_frames: tuple[str, ...]
    output_auth: str


def bus_app(spec: BusSpec, name: str) -> BusApp:
    """The application `name` (a choice of FccApp) as the DBC `spec` describes it."""
    sensors = tuple(m.name for m in spec.app_inputs(name))
    signals = tuple((SCENARIO_SIGNAL.get(s.name, s.name), frame, s.name)
                    for frame in sensors for s in spec.by_name(frame).data_signals
                    if s.name != "step")
    auth = next((m for m in spec.messages
                 if m.app == name and m.is_authenticator and m.senders == (FCC_NODE,)), None)
    return BusApp(name=name, code=spec.apps.index(name), sensor_frames=sensors, sensor_signals=signals,
                  output_frames=auth.secoc_pdus if auth else (), output_auth=auth.name if auth else "")


_SPEC = load(PACKAGED_DBC)
#: every application, in SIM_TICK.app code order
BUS_APPS: dict[str, BusApp] = {n: bus_app(_SPEC, n) for n in _SPEC.apps}
#: the applications' names: every one of the DBC's (the scenario loader flies those it has
#: sections for, hil.scenario.file.AIRCRAFT; the probe is the test build's)
APP_NAMES = tuple(BUS_APPS)
#: the application of each code (SIM_TICK.app)
NAME_OF_CODE = {a.code: a.name for a in BUS_APPS.values()}


def sensor_frames(app: str) -> tuple[str, ...]:
    """The frames the simulator sends for the application `app`."""
    return BUS_APPS[app].sensor_frames


def sensor_signals(app: str) -> tuple[str, ...]:
    """The scenario names of the application's sensor readings (what a sensor fault names)."""
    return tuple(name for name, _, _ in BUS_APPS[app].sensor_signals)


def output_frames(app: str) -> tuple[str, ...]:
    """The frames fcc answers a step of `app` with."""
    return BUS_APPS[app].output_frames
