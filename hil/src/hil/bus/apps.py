"""The applications fcc flies, as the DBC says them: each one's SIM_TICK.app code, the sensor
frames the simulator sends for it and the output frames fcc answers its steps with.  The one
source of "which sensors belong to which aircraft": the scenario's fault checks, the drivers,
the results and the bus log's reader all take their lists from here.

Read from the DBC (the packaged one's digest, as hil.bus.protocol reads it):
* an application is a value of SIM_TICK.app (its code);
* its sensor frames are the frames sent by its sensor nodes (BU_ names starting with its node
  prefix: CDRW_AOA_SENSOR, CDRW_GYRO, ... for the CDRW), in identifier order;
* its output frames are those its outputs' authenticator covers (SecOC_Pdus).
What the DBC does not say in one word is typed once, in DBC_NAMES: the rig's name of each
application, and which node prefix and authenticator are its own (an application attribute on
the BO_ lines of the DBC would make even that derived).
"""
from __future__ import annotations

from dataclasses import dataclass

from hil.bus.dbc import PACKAGED_DBC, BusSpec, load
from hil.bus.protocol import APPS as APP_CODES
from hil.bus.protocol import SENSOR_APP  # noqa: F401 - the sensor frames by identifier, from the DBC's FccApp

#: the rig's name of each application: (SIM_TICK.app name, its sensor nodes' prefix, the
#: authenticator of its outputs)
DBC_NAMES = {"cdrw": ("CDRW_SID", "CDRW_", "SID_OUT_AUTH"),
             "missile": ("MISSILE_LQG", "MSL_", "MSL_ELEV_CMD_AUTH")}
#: the nodes of the rig itself (neither sends an application's sensor frames)
RIG_NODES = ("SIM", "FCC")
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
    """The application `name` as the DBC `spec` describes it."""
    tick_name, prefix, auth = DBC_NAMES[name]
    sensors = tuple(m.name for m in sorted(spec.messages, key=lambda m: m.frame_id)
                    if m.senders and all(s.startswith(prefix) and s not in RIG_NODES for s in m.senders))
    signals = tuple((SCENARIO_SIGNAL.get(s.name, s.name), frame, s.name)
                    for frame in sensors for s in spec.by_name(frame).data_signals
                    if s.name != "step")
    return BusApp(name=name, code=APP_CODES[tick_name], sensor_frames=sensors, sensor_signals=signals,
                  output_frames=spec.by_name(auth).secoc_pdus, output_auth=auth)


_SPEC = load(PACKAGED_DBC)
#: every application, in SIM_TICK.app code order
BUS_APPS: dict[str, BusApp] = {a.name: a for a in sorted((bus_app(_SPEC, n) for n in DBC_NAMES),
                                                         key=lambda a: a.code)}
#: the applications' names (a scenario's `aircraft`)
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
