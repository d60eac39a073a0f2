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
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import can
import pytest

from hil.bus import load
from hil.bus.e2e import protect
from hil.bus.secoc import TEST_KEY_FILE
from hil.rig.session import RigSession
from rig_helpers import MISSILE_2S, fly, scenario

pytestmark = pytest.mark.vcan

SPEC = load()
ID = {m.name: m.frame_id for m in SPEC.messages}
#: frames at most per attack, and the pause between two (bounded time, whatever the load).
#: About 500 forged frames/s: enough to hit every step, and below what fcc's receive queue
#: absorbs in the UML guest on a loaded machine (a lost genuine tick would stall lockstep:
#: a denial of service, which authentication does not claim to prevent); the flood goes 4x.
MAX_FRAMES = 4000
PAUSE_S = 0.002
#: the flight starts only once the attacker has sent this many frames: its attack is certain
#: to reach the flight however fast the flight runs
FIRST_FRAMES = 8

Frames = Iterator[tuple[int, bytes]]


def e2e_frame(name: str, values: dict[str, int | float], counter: int) -> bytes:
    """A frame with a valid E2E header: the attacker knows the CRC and tries every counter."""
    msg = SPEC.by_name(name)
    raw = bytes(msg.message.encode({"crc": 0, "counter": 0, **values}))
    return protect(msg.data_id, raw, counter)


def forged_auth(rng: random.Random, fv: int | None = None) -> bytes:
    fv = rng.randrange(1 << 16) if fv is None else fv
    return fv.to_bytes(2, "little") + rng.randbytes(6)


def forge_control(rng: random.Random) -> Frames:
    """Reconfigure to T = 0.3 s, N = 2; RESET; SHUTDOWN; GROUND -- each with a forged
    authenticator (a guessed freshness, a random MAC), or none at all."""
    commands = [{"command": 0, "lqg_period": 0.3, "da_bits": 2}, {"command": 2},
                {"command": 1}, {"command": 4}]
    for i in range(MAX_FRAMES // 2):
        c = {"command": 0, "lqg_period": 0.0, "da_bits": 0, **commands[i % len(commands)]}
        yield ID["SIM_CONTROL"], e2e_frame("SIM_CONTROL", c, i % 16)
        if i % 3:
            yield ID["SIM_CONTROL_AUTH"], forged_auth(rng, fv=(i // 3) & 0xFFFF)


def forge_command(rng: random.Random) -> Frames:
    """Full-scale elevator commands for every step, as fcc would send them, with forged
    authenticators."""
    for i in range(MAX_FRAMES // 2):
        v = {"degraded": 0, "saturated": 0, "step": i % 60, "da_code": 127 if i % 2 else -128,
             "da_bits": 8}
        yield ID["MSL_ELEV_CMD"], e2e_frame("MSL_ELEV_CMD", v, i % 16)
        yield ID["MSL_ELEV_CMD_AUTH"], forged_auth(rng)


def forge_status(rng: random.Random) -> Frames:
    """A heartbeat claiming a clean, busy firmware, with a forged authenticator."""
    for i in range(MAX_FRAMES // 8):
        yield ID["FCC_STATUS"], SPEC.by_name("FCC_STATUS").message.encode(
            {"mode": 0, "op_mode": 1, "cdrw_degraded": 0, "msl_degraded": 0, "sensor_stale": 0,
             "e2e_fault": 0, "overrun": 0, "config_rejected": 0, "overruns": 0,
             "cdrw_steps": 9999, "msl_steps": 9999, "worst_step_us": 1})
        yield ID["FCC_E2E_COUNTS"], (60000).to_bytes(2, "little") * 4
        yield ID["FCC_E2E_FAULTS"], bytes(8)
        yield ID["FCC_REJECT_COUNTS"], bytes(8)
        yield ID["FCC_BUS_COUNTS"], bytes(8)
        yield ID["FCC_SEC_COUNTS"], bytes(8)
        yield ID["FCC_SEC_SESSION"], rng.randbytes(8)
        yield ID["FCC_STATUS_AUTH"], forged_auth(rng)


def flood(rng: random.Random) -> Frames:
    """As fast as the socket takes them: random bytes on the control frame and on every
    authenticator identifier (a forged authenticator never displaces a genuine frame)."""
    ids = [ID[n] for n in ("SIM_CONTROL", "SIM_CONTROL_AUTH", "SIM_TICK_AUTH", "MSL_ELEV_CMD_AUTH",
                           "FCC_STATUS_AUTH")]
    for _ in range(MAX_FRAMES):
        yield rng.choice(ids), rng.randbytes(8)


def replay_recording(log: Path) -> Callable[[random.Random], Frames]:
    """The secured frames and authenticators of an earlier run (same key, another fcc
    session) in recorded order: the commands and ticks first, then its heartbeats."""
    wanted = {ID[n] for n in ("SIM_CONTROL", "SIM_CONTROL_AUTH", "SIM_TICK", "SIM_TICK_AUTH",
                              "MSL_ELEV_CMD", "MSL_ELEV_CMD_AUTH")} | set(range(0x700, 0x70A))
    frames: list[tuple[int, bytes]] = []
    for line in log.read_text().splitlines():
        parts = line.split()
        if len(parts) >= 3 and "#" in parts[2]:
            fid, data = parts[2].split("#", 1)
            if int(fid, 16) in wanted and len(data) == 16:
                frames.append((int(fid, 16), bytes.fromhex(data)))

    frames.sort(key=lambda f: f[0] >= 0x700)   # stable: recorded order within each group

    def gen(_rng: random.Random) -> Frames:
        yield from frames[:MAX_FRAMES]
    return gen


class Attacker(threading.Thread):
    """A second node: sends the attack's frames until stopped (or they run out); with
    `replay_live`, it also records this session's ticks and plays them back late."""

    def __init__(self, frames: Callable[[random.Random], Frames], replay_live: bool = False,
                 pause: float = PAUSE_S) -> None:
        super().__init__(daemon=True)
        self.pause = pause
        self.bus = can.Bus(interface="socketcan", channel="vcan0", receive_own_messages=False)
        self.frames = frames(random.Random(13))
        self.replay_live = replay_live
        self.stop = threading.Event()
        self.sent = 0
        self.recorded: list[tuple[int, bytes]] = []
        self.exhausted = threading.Event()
        #: set once the attack is under way (FIRST_FRAMES sent, or all of them)
        self.under_way = threading.Event()

    def _send(self, fid: int, data: bytes) -> None:
        try:
            self.bus.send(can.Message(arbitration_id=fid, data=data, is_extended_id=False))
            self.sent += 1
        except can.CanOperationError:
            pass

    def run(self) -> None:
        """From fcc's first heartbeat on (frames sent before it listens would prove nothing)."""
        ticks = {ID["SIM_TICK"], ID["SIM_TICK_AUTH"]}
        deadline = time.monotonic() + 30.0
        while not self.stop.is_set() and time.monotonic() < deadline:
            m = self.bus.recv(0.05)
            if m is not None and m.arbitration_id == ID["FCC_STATUS_AUTH"]:
                break
        while not self.stop.is_set():
            nxt = next(self.frames, None)
            if self.sent >= FIRST_FRAMES or nxt is None:
                self.under_way.set()
            if nxt is None:
                self.exhausted.set()
                if not self.replay_live:
                    break
            if nxt is not None:
                self._send(*nxt)
            if not self.replay_live:
                time.sleep(self.pause)
                continue
            m = self.bus.recv(self.pause)          # paces the loop, and listens
            for _ in range(64):
                if m is None:
                    break
                if m.arbitration_id in ticks:
                    self.recorded.append((m.arbitration_id, bytes(m.data)))
                m = self.bus.recv(0)
            if len(self.recorded) >= 40:          # this session's own ticks, 20 steps late
                for f in self.recorded[:20]:
                    self._send(*f)
                del self.recorded[:20]

    def __enter__(self) -> Attacker:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.join(10)
        self.bus.shutdown()


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
    record(name, s)


def test_replay_of_a_recorded_run(clean, tmp_path):
    """The secured frames of an earlier run under the same key (another fcc session, another
    trip), and this run's own ticks replayed 20 steps late: all refused."""
    s = flight(tmp_path, replay_recording(clean[1]), replay_live=True, play_all=True)
    same_flight(s, clean[0])
    sec = s["firmware"]["security"]
    # the recording's frames fail the freshness check where their counters are behind this
    # session's, the MAC (other trip) where they are ahead; this session's ticks, replayed
    # late, fail the freshness check
    assert sec["fcc"]["mac_failed"] + sec["fcc"]["freshness_failed"] > 20
    assert sec["rig"]["mac_failed"] + sec["rig"]["freshness_failed"] > 0
    assert s["_attack_frames"] > 100
    record("replay: a recorded run's frames + this run's ticks 20 steps late", s)


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


def record(name: str, s: dict) -> None:
    """One line per attack for the closing note's table ($FCC_ATTACK_TABLE, if set)."""
    path = os.environ.get("FCC_ATTACK_TABLE")
    if path:
        sec = s["firmware"]["security"]
        with open(path, "a", encoding="utf-8") as f:
            f.write(json.dumps({"attack": name, "frames": s["_attack_frames"], "fcc": sec["fcc"],
                                "rig": sec["rig"], "rms_q": s["missile"]["runs"][0]["rms_q"]}) + "\n")
