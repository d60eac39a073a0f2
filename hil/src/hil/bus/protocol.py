"""The rig protocol's numbers, from the DBC: SIM_CONTROL's commands, the applications of
SIM_TICK, FCC_STATUS.mode, the frames the bus log is read by.  The DBC's value tables (VAL_) are
the one source: the firmware's C has the same numbers from them (hil.bus.cgen writes
FCC_MSG_SIM_CONTROL_COMMAND_* into firmware/bus/generated/fcc_bus_msgs.h), and the rig takes
them here, so no side types them by hand.

Read from the packaged DBC (its digest, data/fcc_hil.spec.json: no cantools), whatever --dbc
says later: a DBC given on the command line describes the same protocol.
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping

from hil.bus.dbc import PACKAGED_DBC, BusSpec, load

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
#: FCC_SYNC_STATUS.state: fcc's time synchronisation (firmware/timesync/fcc_tsync.h)
SYNC_STATES = value_table("FCC_SYNC_STATUS", "state")
SYNC_STATE_NAMES = {code: name for name, code in SYNC_STATES.items()}
SYNC_LOCKED = SYNC_STATES["LOCKED"]
#: the states in which fcc counts its steps by the master's instants (it has an estimate)
SYNC_HAS_TIME = tuple(SYNC_STATES[n] for n in ("LOCKING", "LOCKED", "HOLDOVER", "REFUSED"))
SIM_CONTROL_ID = _SPEC.by_name("SIM_CONTROL").frame_id
SIM_TICK_ID = _SPEC.by_name("SIM_TICK").frame_id
SIM_EVENT_ID = _SPEC.by_name("SIM_EVENT").frame_id


#: the sensor frames of each application (SIM_TICK.app: the order of the DBC's FccApp
#: choices), in identifier order -- fcc's input tables (dbc/generate) are the same
APP_INPUTS = {i: tuple(m.name for m in _SPEC.app_inputs(app))
              for i, app in enumerate(_SPEC.apps)}
#: the sensor frames, by identifier: the application whose step they feed
SENSOR_APP = {_SPEC.by_name(name).frame_id: app for app, names in APP_INPUTS.items()
              for name in names}


def fault_kind_codes(spec: BusSpec) -> dict[str, int]:
    """SIM_EVENT.kind's value table: the code of each fault kind on the bus, by the kind's
    name (hil.scenario.faults' names are the table's names in lower case; 0, NONE, left out)."""
    return {name.lower(): code for name, code in spec.by_name("SIM_EVENT").signal("kind").choices
            if code != 0}


def fault_code_mismatches(kinds: Iterable[str], codes: Mapping[str, int]) -> list[str]:
    """What keeps a fault-kind registry and the DBC's codes from agreeing: a kind without a
    code, a code without a kind, a code given twice.  Empty when they agree."""
    kinds = list(kinds)
    problems = [f"fault kind {k!r} has no code in SIM_EVENT.kind's value table (append one)"
                for k in kinds if k not in codes]
    problems += [f"SIM_EVENT.kind code {c} ({n}) names no fault kind"
                 for n, c in codes.items() if n not in kinds]
    seen: dict[int, str] = {}
    for n, c in codes.items():
        if c in seen:
            problems.append(f"SIM_EVENT.kind code {c} given to both {seen[c]} and {n}")
        seen[c] = n
    return problems


#: SIM_EVENT.kind of each fault kind, from the DBC's value table (VAL_ 1808 kind): a new kind
#: gets a new code appended there; a code once on the bus never changes
FAULT_KIND_CODES = fault_kind_codes(_SPEC)
FAULT_KIND_NAMES = {code: name for name, code in FAULT_KIND_CODES.items()}
