"""The rig protocol's numbers, from the DBC: SIM_CONTROL's commands, the applications of
SIM_TICK, FCC_STATUS.mode, the frames the bus log is read by.  The DBC's value tables (VAL_) are
the one source: the firmware's C has the same numbers from them (hil.bus.cgen writes
FCC_MSG_SIM_CONTROL_COMMAND_* into firmware/bus/generated/fcc_bus_msgs.h), and the rig takes
them here, so no side types them by hand.

Read from the packaged DBC (its digest, data/fcc_hil.spec.json: no cantools), whatever --dbc
says later: a DBC given on the command line describes the same protocol.
"""
from __future__ import annotations

from hil.bus.dbc import PACKAGED_DBC, load

_SPEC = load(PACKAGED_DBC)


def value_table(message: str, signal: str) -> dict[str, int]:
    """A signal's value table in the DBC: {name: raw value}."""
    return dict(_SPEC.by_name(message).signal(signal).choices)


#: SIM_CONTROL.command (fcc accepts reset, designs and shutdown on the ground only)
COMMANDS = value_table("SIM_CONTROL", "command")
COMMAND_NONE = COMMANDS["NONE"]
COMMAND_SHUTDOWN = COMMANDS["SHUTDOWN"]
COMMAND_RESET = COMMANDS["RESET"]
COMMAND_FLIGHT = COMMANDS["FLIGHT"]
COMMAND_GROUND = COMMANDS["GROUND"]
COMMAND_MAINTENANCE = COMMANDS["MAINTENANCE"]
#: SIM_TICK.app: the application a step is for
APPS = value_table("SIM_TICK", "app")
APP_CDRW = APPS["CDRW_SID"]
APP_MISSILE = APPS["MISSILE_LQG"]
#: FCC_STATUS.mode, by the rig's names of the modes
MODE_CODES = {name.lower(): code for name, code in value_table("FCC_STATUS", "mode").items()}
MODE_NAMES = {code: name for name, code in MODE_CODES.items()}
SIM_CONTROL_ID = _SPEC.by_name("SIM_CONTROL").frame_id
SIM_TICK_ID = _SPEC.by_name("SIM_TICK").frame_id
#: the sensor frames, by identifier: the application whose step they feed
SENSOR_APP = {_SPEC.by_name(name).frame_id: app for app, names in (
    (APP_CDRW, ("CDRW_AOA", "CDRW_PITCH_RATE", "CDRW_ELEVATOR")),
    (APP_MISSILE, ("MSL_RATE_GYRO", "MSL_ACCELEROMETER"))) for name in names}
