"""The rig protocol's numbers (hil.bus.protocol) are the DBC's value tables: the same as
cantools reads them from dbc/fcc_hil.dbc, and the same as the firmware's generated C
(firmware/bus/generated/fcc_bus_msgs.h, from the same DBC)."""
from __future__ import annotations

import re

import cantools

from conftest import REPO

from hil.bus import protocol


def defines(prefix: str) -> dict[str, int]:
    text = (REPO / "firmware" / "bus" / "generated" / "fcc_bus_msgs.h").read_text()
    return {m[1]: int(m[2]) for m in re.finditer(rf"#define {prefix}_(\w+) (\d+)u", text)}


def test_commands_are_the_firmwares() -> None:
    assert defines("FCC_MSG_SIM_CONTROL_COMMAND") == protocol.COMMANDS
    assert (protocol.COMMAND_NONE, protocol.COMMAND_SHUTDOWN, protocol.COMMAND_RESET,
            protocol.COMMAND_FLIGHT, protocol.COMMAND_GROUND) == (0, 1, 2, 3, 4)


def test_value_tables_are_the_dbcs() -> None:
    db = cantools.database.load_file(str(REPO / "dbc" / "fcc_hil.dbc"))
    sig = db.get_message_by_name("SIM_CONTROL").get_signal_by_name("command")
    assert {str(name): value for value, name in sig.choices.items()} == protocol.COMMANDS
    app = db.get_message_by_name("SIM_TICK").get_signal_by_name("app")
    assert {str(name): value for value, name in app.choices.items()} == protocol.APPS
    assert protocol.MODE_CODES == {"lockstep": 0, "realtime": 1}
    assert db.get_message_by_name("SIM_CONTROL").frame_id == protocol.SIM_CONTROL_ID
    assert db.get_message_by_name("SIM_TICK").frame_id == protocol.SIM_TICK_ID
