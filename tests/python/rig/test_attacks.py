"""Attacks on the bus during real flights (issue 13): a second node on vcan0 forges, replays
and floods while the rig flies a lockstep missile flight through the real fcc.  Every attack
is rejected and counted, and the flight result, fcc's E2E counters and its step counts are
those of the same flight without the attack.  The last test does the same in realtime.

The attacker knows everything but the key: the DBC, the E2E algorithm (its forged frames
carry valid CRCs for every alive counter), and everything said on the bus.
"""
from __future__ import annotations

import json
import os
import random
from collections.abc import Callable
from pathlib import Path

import pytest

from hil.bus import load
from hil.bus.secoc import TEST_KEY_FILE, read_key_file
from hil.results.buslog import BusAuth
from hil.results.timing import bus_timing, summarise
from hil.verify.attack import (ID, PAUSE_S, Attacker, Frames, flood,  # the attacker
                               forge_command, forge_control, forge_status, replay_recording)
from hil.rig.session import RigSession
from rig_helpers import MISSILE_2S, fly, scenario

pytestmark = pytest.mark.vcan
SPEC = load()
TEST_KEY = read_key_file(TEST_KEY_FILE)

def no_frames(_rng: random.Random) -> Frames:
    yield from ()


def flight(out: Path, attack: Callable[[random.Random], Frames] | None = None,
           replay_live: bool = False, mode: str = "lockstep", pause: float = PAUSE_S,
           play_all: bool = False) -> dict:
    """One missile flight under attack: the attacker runs from before fcc starts until the
    flight is over (it is stopped before the rig's shutdown, so that the recorder can close
    its log on the rig's end marker); with play_all, not before it has sent all its frames."""
    sc = scenario(MISSILE_2S)
    shutdown, control = RigSession.shutdown, RigSession.control
    with Attacker(attack or no_frames, replay_live, pause) as atk:
        def control_once_attacked(rig: RigSession, *a: object, **kw: object) -> object:
            atk.under_way.wait(30.0)
            return control(rig, *a, **kw)
        def stop_then_shutdown(rig: RigSession, *a: object, **kw: object) -> int:
            if play_all:
                atk.exhausted.wait(60.0)
            atk.stop.set()
            atk.join(10)
            return shutdown(rig, *a, **kw)
        RigSession.shutdown = stop_then_shutdown  # type: ignore[method-assign]
        RigSession.control = control_once_attacked  # type: ignore[method-assign]
        try:
            outcome = fly(out, sc, key_file=TEST_KEY_FILE, mode=mode, timeout=10.0)
        finally:
            RigSession.shutdown, RigSession.control = shutdown, control  # type: ignore[method-assign]
    summary = dict(outcome.summary)
    summary["_attack_frames"] = atk.sent
    return summary


@pytest.fixture(scope="module")
def clean(tmp_path_factory) -> tuple[dict, Path]:
    out = tmp_path_factory.mktemp("clean")
    return flight(out), out / "bus.log"


def same_flight(s: dict, clean_summary: dict) -> None:
    """The flight's result and fcc's view of the genuine traffic are the clean flight's (frames
    on identifiers fcc does not consume, e.g. forged status frames, count as unknown_id)."""
    assert s["missile"] == clean_summary["missile"]
    for key in ("steps", "e2e"):
        assert s["firmware"][key] == clean_summary["firmware"][key], key
    for key in ("wrong_dlc", "out_of_range", "tx_refused"):
        assert s["firmware"]["rejected"][key] == clean_summary["firmware"]["rejected"][key], key


ATTACKS = {
    "forged SIM_CONTROL (reconfigure, RESET, SHUTDOWN, GROUND)": (forge_control, "fcc"),
    "forged MSL_ELEV_CMD": (forge_command, "rig"),
    "forged status frames": (forge_status, "rig"),
    "flood of control frames and authenticators": (flood, "both"),
}


@pytest.mark.parametrize("name", list(ATTACKS))
def test_attack_is_rejected_counted_and_changes_nothing(name, clean, tmp_path):
    attack, where = ATTACKS[name]
    s = flight(tmp_path, attack, pause=PAUSE_S / 4 if attack is flood else PAUSE_S)
    assert s["_attack_frames"] > 0
    same_flight(s, clean[0])
    sec = s["firmware"]["security"]
    fcc_refused = sec["fcc"]["mac_failed"] + sec["fcc"]["freshness_failed"] + sec["fcc"]["unpaired"]
    rig_refused = sec["rig"]["mac_failed"] + sec["rig"]["freshness_failed"] + sec["rig"]["unpaired"]
    if where in ("fcc", "both"):
        assert fcc_refused > 0, sec
    if where in ("rig", "both"):
        assert rig_refused > 0, sec
    assert sec["fcc"]["mode_refused"] == 0   # nothing forged ever got as far as the mode check
    # frames on fcc's own identifiers (its command, its authenticator, its heartbeat): fcc
    # counted them, and the run says the bus was attacked (`hil run`: exit 7)
    own = s["firmware"]["rejected"]["own_id"]
    if where in ("rig", "both"):
        assert own > 0 and s["bus_trust"]["verdict"] != "ok", s["bus_trust"]
    else:
        assert own == 0 and s["bus_trust"]["verdict"] == "ok", s["bus_trust"]
    record(name, s)


def test_replay_of_a_recorded_run(clean, tmp_path):
    """The secured frames of an earlier run under the same key (another fcc session, another
    trip), and this run's own ticks replayed 20 steps late: all refused."""
    s = flight(tmp_path, replay_recording(clean[1], heartbeats=False), replay_live=True, play_all=True)
    same_flight(s, clean[0])
    sec = s["firmware"]["security"]
    # the recording's frames fail the freshness check where their counters are behind this
    # session's, the MAC (other trip) where they are ahead; this session's ticks, replayed
    # late, fail the freshness check
    assert sec["fcc"]["mac_failed"] + sec["fcc"]["freshness_failed"] > 20
    assert sec["rig"]["mac_failed"] + sec["rig"]["freshness_failed"] > 0
    assert s["_attack_frames"] > 100
    record("replay: a recorded run's frames + this run's ticks 20 steps late", s)


def test_replayed_heartbeats_of_another_trip_fail_the_run(clean, tmp_path):
    """The heartbeats of an earlier run under the same key verify under their own trip: to
    the rig, a second fcc with its key is on the bus; the run fails (one line, exit 1)."""
    from hil.rig.errors import RigError
    with pytest.raises(RigError, match="a second fcc is on vcan0"):
        flight(tmp_path, replay_recording(clean[1]), play_all=True)


def test_attacks_in_a_realtime_flight(tmp_path):
    """Realtime: forged reconfiguration/RESET/SHUTDOWN and forged commands during the flight;
    fcc keeps its design and mode, is reset only by the rig, and the rig flies only fcc's
    commands (the run itself is not repeatable: two clocks)."""
    def both(rng: random.Random) -> Frames:
        for a, b in zip(forge_control(rng), forge_command(rng)):
            yield a
            yield b
    s = flight(tmp_path, both, mode="realtime")
    sec = s["firmware"]["security"]
    assert sec["fcc"]["mac_failed"] + sec["fcc"]["unpaired"] > 0
    assert sec["rig"]["mac_failed"] + sec["rig"]["unpaired"] > 0
    assert sec["fcc"]["mode_refused"] == 0
    log = (tmp_path / "fcc.log").read_text()
    assert "fcc summary: control resets=1 configs_accepted=0" in log   # the rig's one reset
    assert "fcc summary: lqg period_s=0.0500 bits=8" in log
    run = s["missile"]["runs"][0]
    assert run["bits"] == 8 and run["period"] == pytest.approx(0.05)
    assert s["firmware"]["steps"]["missile"] >= 10                       # flew, not shut down
    record("realtime: forged SIM_CONTROL + forged MSL_ELEV_CMD", s)


#: the forger's FCC_SYNC_STATUS: fcc locked with a 30 ms residual (clean: a few us)
FORGED_SYNC_STATUS = SPEC.by_name("FCC_SYNC_STATUS").message.encode(
    {"state": 2, "master": 1, "offset_us": 30000, "rate_ppm": 0.0, "syncs": 1, "rejected": 0, "losses": 0})


def forge_timing(rng: random.Random) -> Frames:
    """What the realtime timing is measured from: fcc's sync status (a 30 ms offset) and its
    commands (forge_command's), a keyless node's, interleaved."""
    for status, command in zip(iter(lambda: (ID["FCC_SYNC_STATUS"], FORGED_SYNC_STATUS), None),
                               forge_command(rng)):
        yield status
        yield command


def test_forged_timing_frames_change_no_timing_figure(tmp_path):
    """Realtime, forged FCC_SYNC_STATUS and MSL_ELEV_CMD (with forged authenticators) through
    the flight: summary.json's timing is what the authentic frames of the same log give (the
    log without the forger's frames, read under the key), never the forger's 30 ms; the run
    says the bus was attacked."""
    s = flight(tmp_path, forge_timing, mode="realtime")
    assert s["_attack_frames"] > 0
    forged = {(ID["FCC_SYNC_STATUS"], FORGED_SYNC_STATUS.hex().upper())} | {
        (fid, data.hex().upper()) for fid, data in forge_command(random.Random(0))
        if fid == ID["MSL_ELEV_CMD"]}
    lines = (tmp_path / "bus.log").read_text().splitlines()
    kept = [ln for ln in lines if not (len(p := ln.split()) >= 3 and "#" in p[2] and
                                       (int(p[2].split("#")[0], 16), p[2].split("#")[1]) in forged)]
    assert len(lines) - len(kept) > 10                     # the forger's frames were on the bus
    (tmp_path / "authentic.log").write_text("\n".join(kept) + "\n")
    want = summarise(bus_timing(tmp_path / "authentic.log", SPEC, 0.05, BusAuth(TEST_KEY)), "")
    got = s["realtime"]["bus"]
    assert got == want["bus"]
    assert got["sync_offset"]["n"] > 0 and got["sync_offset"]["max"] < 30000
    assert got["cmd_delay"]["n"] <= s["firmware"]["steps"]["missile"]
    assert s["bus_trust"]["verdict"] != "ok" and s["firmware"]["rejected"]["own_id"] > 0


def record(name: str, s: dict) -> None:
    """One line per attack for the closing note's table ($FCC_ATTACK_TABLE, if set)."""
    path = os.environ.get("FCC_ATTACK_TABLE")
    if path:
        sec = s["firmware"]["security"]
        with open(path, "a", encoding="utf-8") as f:
            f.write(json.dumps({"attack": name, "frames": s["_attack_frames"], "fcc": sec["fcc"],
                                "rig": sec["rig"], "rms_q": s["missile"]["runs"][0]["rms_q"]}) + "\n")
