"""A second node on the bus that knows everything but the key: the DBC, the E2E algorithm (its
forged frames carry valid CRCs for every alive counter) and everything said on the bus.  It
forges, replays or floods while a flight runs (`hil verify` cases with `attack = ...`, and the
attack tests); every frame it sends is counted (`sent`).
"""
from __future__ import annotations

import random
import threading
import time
from collections.abc import Callable, Collection, Iterator, Mapping
from pathlib import Path

from hil.bus import load
from hil.bus.e2e import protect
from hil.bus.protocol import COMMAND_GROUND, COMMAND_NONE, COMMAND_RESET, COMMAND_SHUTDOWN

Frames = Iterator[tuple[int, bytes]]

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


def e2e_frame(name: str, values: Mapping[str, int | float], counter: int) -> bytes:
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
    commands: list[dict[str, int | float]] = [
        {"command": COMMAND_NONE, "lqg_period": 0.3, "da_bits": 2}, {"command": COMMAND_RESET},
        {"command": COMMAND_SHUTDOWN}, {"command": COMMAND_GROUND}]
    for i in range(MAX_FRAMES // 2):
        c = {"command": COMMAND_NONE, "lqg_period": 0.0, "da_bits": 0, **commands[i % len(commands)]}
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
    for _ in range(MAX_FRAMES // 8):
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


def forge_sync(rng: random.Random) -> Frames:
    """A foreign time master (master 2): SYNC / FOLLOW_UP pairs with valid E2E, a time 50 ms
    off the rig's and sequence numbers of its own, each followed by a TSYNC_AUTH with a guessed
    freshness value and a random MAC (fcc refuses the pair unauthenticated, the authenticator
    as forged or replayed: FCC_SYNC_REFUSALS)."""
    sync, fup = SPEC.by_name("TSYNC_SYNC"), SPEC.by_name("TSYNC_FOLLOW_UP")
    for i in range(MAX_FRAMES // 3):
        seq, sec, ns = i & 0xFF, 1 + i // 10, (i % 10) * 100_000_000 + 50_000_000
        raw = sync.message.encode({"crc": 0, "counter": 0, "master": 2, "seq": seq, "interval_ms": 100,
                                   "sec": sec})
        yield ID["TSYNC_SYNC"], protect(sync.data_id, raw, i % 15)
        raw = fup.message.encode({"crc": 0, "counter": 0, "master": 2, "seq": seq, "sec_carry": 0, "ns": ns})
        yield ID["TSYNC_FOLLOW_UP"], protect(fup.data_id, raw, i % 15)
        yield ID["TSYNC_AUTH"], forged_auth(rng)


def no_frames(_rng: random.Random) -> Frames:
    """Nothing of its own (a live replay only replays what it records)."""
    yield from ()


def replay_recording(log: Path, heartbeats: bool = True) -> Callable[[random.Random], Frames]:
    """The secured frames and authenticators of an earlier run (same key, another fcc
    session) in recorded order: the commands and ticks first, then its heartbeats (unless
    not `heartbeats`: a heartbeat of another trip under the run's key fails the run as a
    second fcc on the bus, hil.rig.session)."""
    wanted = {ID[n] for n in ("SIM_CONTROL", "SIM_CONTROL_AUTH", "SIM_TICK", "SIM_TICK_AUTH",
                              "MSL_ELEV_CMD", "MSL_ELEV_CMD_AUTH")}
    if heartbeats:
        wanted |= set(range(0x700, 0x70A))
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
                 pause: float = PAUSE_S, iface: str = "vcan0", record: Collection[int] = ()) -> None:
        """record: what a live replay records and plays back late (default: the ticks)."""
        import can  # python-can: only when an attack flies
        super().__init__(daemon=True)
        self._can = can
        self.pause = pause
        self.bus = can.Bus(interface="socketcan", channel=iface, receive_own_messages=False)
        self.frames = frames(random.Random(13))
        self.replay_live = replay_live
        self.record = frozenset(record) or frozenset({ID["SIM_TICK"], ID["SIM_TICK_AUTH"]})
        self.stop = threading.Event()
        self.sent = 0
        self.recorded: list[tuple[int, bytes]] = []
        self.exhausted = threading.Event()
        #: set once the attack is under way (FIRST_FRAMES sent, or all of them)
        self.under_way = threading.Event()

    def _send(self, fid: int, data: bytes) -> None:
        try:
            self.bus.send(self._can.Message(arbitration_id=fid, data=data, is_extended_id=False))
            self.sent += 1
        except self._can.CanOperationError:
            pass

    def run(self) -> None:
        """From fcc's first heartbeat on (frames sent before it listens would prove nothing)."""
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
                if m.arbitration_id in self.record:
                    self.recorded.append((m.arbitration_id, bytes(m.data)))
                m = self.bus.recv(0)
            if len(self.recorded) >= 40:          # this session's own frames, 20 frames late
                for f in self.recorded[:20]:
                    self._send(*f)
                del self.recorded[:20]

    def wait_ready(self) -> None:
        """Until the attack is under way (its first frames are on the bus)."""
        self.under_way.wait(30.0)

    def stop_now(self) -> None:
        self.stop.set()
        self.join(10)

    def __enter__(self) -> Attacker:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.join(10)
        self.bus.shutdown()


#: the attacks a verification case can name
ATTACKS: dict[str, Callable[[random.Random], Frames]] = {
    "forged-control": forge_control, "forged-commands": forge_command,
    "forged-status": forge_status, "flood": flood, "foreign-sync-master": forge_sync,
    "replayed-sync": no_frames,
}
#: the attacks that replay this session's own frames late: what they record (the time
#: master's SYNC, FOLLOW_UP and TSYNC_AUTH: fcc refuses the replayed authenticator as not fresh)
LIVE_REPLAYS: dict[str, frozenset[int]] = {
    "replayed-sync": frozenset(ID[n] for n in ("TSYNC_SYNC", "TSYNC_FOLLOW_UP", "TSYNC_AUTH")),
}
