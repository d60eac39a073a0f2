"""Attacks on the time synchronisation during a realtime missile flight at T = 0.05 s (10 s,
200 commands), as the red team made them: a second node on vcan0 learns the master's time from
the bus and, after each genuine SYNC/FOLLOW_UP, forges the next pair -- the master's next
sequence number and E2E alive counters (so that, with E2E alone, the master's own frames would
be refused as repeated and the forger would be the master), valid CRCs, a wrong time -- and a
TSYNC_AUTH with a fresh freshness value and a guessed MAC:

  (a) a -50 ms step of the master time,   (b) a drag of 4 ms/s;

and (c) the rig's own, authenticated master going wrong (the same step and drag): fcc's
plausibility check against its own clock.

The forged pairs never get past the authentication: fcc keeps following the master, every
forged frame and authenticator is counted, exactly, and `hil run` exits 7 naming the attack
(hil.results.sync).  Which of fcc's counters a forged authenticator lands in is decided by the
bus's order, not by the machine's speed: one on the bus before the master's authenticator of
the same freshness value fails on its MAC; one after it -- the forger fell behind the bus (its
thread shares the rig's process, stalled at the flight's start, the more on a loaded machine)
-- is stale, refused on its freshness as a replay.  The forger reads the bus in the order fcc
does and judges each of its own so (TimeForger.refusals).

What depends on the machine's speed -- the flight's RMS q against a clean flight, commands
missing, fcc still LOCKED -- is in the timing-marked test at the end.
"""
from __future__ import annotations

import json
import os
import random
import re
import select
import socket
import struct
import threading
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from rig_helpers import cli

from hil.bus import load
from hil.bus.e2e import protect
from hil.bus.protocol import COMMAND_FLIGHT, SIM_CONTROL_ID
from hil.bus.secoc import TEST_KEY_FILE
from hil.rig.link import CAN_FRAME, SO_TIMESTAMPNS, MonotonicStamps
from hil.rig.timesync import TimeMaster

pytestmark = pytest.mark.vcan

SPEC = load()
SYNC, FUP, AUTH = (SPEC.by_name(n) for n in ("TSYNC_SYNC", "TSYNC_FOLLOW_UP", "TSYNC_AUTH"))
MISSILE_10S = '''aircraft = "missile"
duration = 10.0
seed = 3
[lqg]
period = 0.05
bits = 8
'''
#: the forger attacks from the FLIGHT command for this long (the flight is 10 s): its last
#: forged frames are followed by genuine pairs that verify, so fcc has counted every one
ATTACK_S = 8.0
#: (c): the rig's master goes wrong this long after it started (fcc locks within ~1 s of it,
#: the flight starts then), for FAULT_S, then is right again (fcc follows it again)
FAULT_AFTER_S = 3.0
FAULT_S = 5.0


def step_error(t: float) -> float:
    """(a): the master time 50 ms behind from the attack's start (s)."""
    return -0.050


def drag_error(t: float) -> float:
    """(b): the master time dragged back at 4 ms/s."""
    return -0.004 * t


class TimeForger(threading.Thread):
    """The red team's second node.  It learns the master's epoch from the bus (a genuine
    SYNC's receive stamp minus the master time its FOLLOW_UP gives), and after each genuine
    pair -- from the rig's SIM_CONTROL(FLIGHT) on, for ATTACK_S -- sends a forged SYNC and
    FOLLOW_UP of the next sequence number with the master's next alive counters, the master
    time of its own SYNC's transmission plus error(t), and a forged TSYNC_AUTH (freshness: the
    master's last + 1, a random MAC).  It encodes with the DBC's own integer codec, not
    cantools' (whose first use parses the DBC, ~0.25 s holding the GIL: the first forgery went
    out after the master's next pair, every run)."""

    def __init__(self, error: Callable[[float], float]) -> None:
        super().__init__(daemon=True)
        self.error = error
        self.sock = socket.socket(socket.AF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        self.sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_RECV_OWN_MSGS, 1)
        ids = (SYNC.frame_id, FUP.frame_id, AUTH.frame_id, SIM_CONTROL_ID)
        self.sock.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                             b"".join(struct.pack("=II", i, 0x7FF) for i in ids))
        self.sock.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
        self.sock.bind(("vcan0",))
        self.stamps = MonotonicStamps()
        self.rng = random.Random(11)
        self.stop = threading.Event()
        self.frames = 0      # forged SYNC and FOLLOW_UP frames sent
        self.pairs = 0       # forged SYNC + FOLLOW_UP pairs sent
        self.auths = 0       # forged TSYNC_AUTH sent
        #: the forged TSYNC_AUTH on the bus as fcc judges them: "mac_failed" before the
        #: master's authenticator of its freshness value, "freshness_failed" after it
        self.refusals: Counter[str] = Counter()
        self.master_fv: int | None = None   # the master's last TSYNC_AUTH freshness (bus order)
        #: the master's TSYNC_AUTH on the bus since the last forged frame: from the second on,
        #: a pair sent after every forged frame verified, so fcc has counted each forged frame
        self.master_auths_since = 0
        self.t_attack: float | None = None

    def _recv(self, timeout: float) -> tuple[int, bytes, float, bool] | None:
        if not select.select([self.sock], [], [], timeout)[0]:
            return None
        raw, anc, flags, _ = self.sock.recvmsg(CAN_FRAME.size, socket.CMSG_SPACE(16))
        fid, _, data = CAN_FRAME.unpack(raw)
        stamp = self.stamps.of(anc)
        own = bool(flags & socket.MSG_CONFIRM)
        self._in_bus_order(fid, data, own)
        return fid, data, time.monotonic() if stamp is None else stamp, own

    def _in_bus_order(self, fid: int, data: bytes, own: bool) -> None:
        """Every frame read (here and while waiting for an echo), in the bus's order: the
        order fcc reads them in (every socket on vcan0 gets each frame as the bus carried it),
        so the verdict on a forged authenticator follows from what came before it here."""
        if own:
            self.master_auths_since = 0
        if fid != AUTH.frame_id:
            return
        fv = int.from_bytes(data[:2], "little")
        if not own:
            self.master_fv = fv
            self.master_auths_since += 1
        elif self.master_fv is not None and fv <= self.master_fv:
            self.refusals["freshness_failed"] += 1   # fcc has accepted the master's fv already
        else:
            self.refusals["mac_failed"] += 1

    def _send(self, fid: int, data: bytes) -> float | None:
        """Send, and the bus time of the frame (its own echo's stamp)."""
        self.sock.send(CAN_FRAME.pack(fid, 8, data))
        end = time.monotonic() + 0.05
        while (left := end - time.monotonic()) > 0:
            got = self._recv(left)
            if got is not None and got[3] and got[0] == fid and got[1] == data:
                return got[2]
        return None

    def run(self) -> None:
        sync: tuple[bytes, float] | None = None   # the master's last SYNC and its stamp
        fup: bytes | None = None
        epoch: float | None = None
        saw_auth = False
        end = time.monotonic() + 120.0
        while not self.stop.is_set() and time.monotonic() < end:
            got = self._recv(0.05)
            if got is None or got[3]:
                continue
            fid, data, at, _ = got
            if fid == SIM_CONTROL_ID and data[1] >> 4 == COMMAND_FLIGHT and self.t_attack is None:
                self.t_attack = at
            elif fid == SYNC.frame_id:
                sync = (data, at)
            elif fid == FUP.frame_id and sync is not None and data[2] == sync[0][2]:
                v = FUP.decode(data)
                sec = SYNC.decode(sync[0])["sec"] + v["sec_carry"]
                epoch = sync[1] - (sec + v["ns"] * 1e-9)
                fup = data
                if not saw_auth:   # a master without authenticators: forge on its FOLLOW_UP
                    self._forge(sync[0], fup, epoch, None)
            elif fid == AUTH.frame_id and sync is not None and fup is not None and epoch is not None:
                saw_auth = True
                self._forge(sync[0], fup, epoch, int.from_bytes(data[:2], "little"))

    def _forge(self, sync: bytes, fup: bytes, epoch: float, fv: int | None) -> None:
        if self.t_attack is None:
            return
        t = time.monotonic() - self.t_attack
        if t > ATTACK_S:
            return
        seq = (sync[2] + 1) & 0xFF
        err = self.error(t)
        sec = int(time.monotonic() - epoch + err)
        raw = SYNC.encode({"crc": 0, "counter": 0, "master": sync[1] >> 4, "seq": seq,
                                   "interval_ms": sync[3], "sec": sec})
        forged_sync = protect(SYNC.data_id, raw, ((sync[1] & 0x0F) + 1) % 16)
        tx = self._send(SYNC.frame_id, forged_sync)
        self.frames += 1
        if tx is None:
            return
        m = int(round((tx - epoch + err) * 1e6))
        carry = m // 1_000_000 - sec
        if carry not in (0, 1):
            return
        raw = FUP.encode({"crc": 0, "counter": 0, "master": fup[1] >> 4, "seq": seq,
                                  "sec_carry": carry, "ns": (m % 1_000_000) * 1000})
        self._send(FUP.frame_id, protect(FUP.data_id, raw, ((fup[1] & 0x0F) + 1) % 16))
        self.frames += 1
        self.pairs += 1
        if fv is not None:
            self._send(AUTH.frame_id, ((fv + 1) & 0xFFFF).to_bytes(2, "little")
                       + self.rng.randbytes(6))
            self.auths += 1

    def __enter__(self) -> TimeForger:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop.set()
        self.join(5)
        self.sock.close()


class FaultyMaster:
    """(c): the rig's own master, with the key, publishing a wrong time from FAULT_AFTER_S
    after it started, for FAULT_S: every pair it sends then carries error(t)."""

    def __init__(self, error: Callable[[float], float]) -> None:
        self.error = error
        self.pairs = 0   # pairs sent with the error
        self._send_sync, self._published = TimeMaster.send_sync, TimeMaster.published

    def __enter__(self) -> FaultyMaster:
        fault = self

        def send_sync(master: TimeMaster) -> bool:
            t = master.master_us() * 1e-6 - FAULT_AFTER_S
            on = 0 < t <= FAULT_S
            master._fault_t = t if on else None   # type: ignore[attr-defined]
            ok = fault._send_sync(master)
            fault.pairs += int(ok and on)
            return ok

        def published(master: TimeMaster, m: int) -> int:
            t = getattr(master, "_fault_t", None)
            return m if t is None else m + int(round(fault.error(t) * 1e6))

        TimeMaster.send_sync = send_sync  # type: ignore[method-assign]
        TimeMaster.published = published  # type: ignore[method-assign]
        return self

    def __exit__(self, *exc: object) -> None:
        TimeMaster.send_sync, TimeMaster.published = self._send_sync, self._published  # type: ignore[method-assign]


def fcc_refusals(s: dict, out: Path) -> dict[str, int]:
    """fcc's own count of its time-sync refusals at exit (fcc.log's `fcc summary: sync_refused`
    line: final, whenever the rig read its last heartbeat), checked against the heartbeat's."""
    line = re.search(r"fcc summary: sync_refused (.*)", (out / "fcc.log").read_text())
    assert line is not None
    final = {k: int(v) for k, v in re.findall(r"(\w+)=(\d+)", line.group(1))}
    for k, v in s["sync"]["refused"].items():
        assert v <= final[k], (k, v, final)
    return final


def flight(tmp: Path, capsys: Any, attack: Any = None) -> tuple[int, str, dict]:
    """`hil run missile --mode realtime` of MISSILE_10S, under the attack (a TimeForger or a
    FaultyMaster, or none): (exit status, stderr, summary.json with fcc's final refusals under
    `_fcc_refused`)."""
    tmp.mkdir(parents=True, exist_ok=True)
    sc = tmp / "missile_10s.toml"
    sc.write_text(MISSILE_10S)
    out = tmp / "run"
    argv = ("run", "missile", str(sc), "--mode", "realtime", "--no-plots", "--quiet",
            "--key-file", str(TEST_KEY_FILE), "--out", str(out))
    if attack is None:
        rc, _, err = cli(capsys, *argv)
    else:
        with attack:
            rc, _, err = cli(capsys, *argv)
    s = json.loads((out / "summary.json").read_text())
    s["_fcc_refused"] = fcc_refusals(s, out)
    return rc, err, s


ATTACKS = {"a -50 ms step": step_error, "a 4 ms/s drag": drag_error}
#: what fcc refuses a forged TSYNC_AUTH as (TimeForger.refusals)
AUTH_REFUSALS = ("mac_failed", "freshness_failed")


@pytest.mark.parametrize("name", list(ATTACKS))
def test_forged_sync_is_refused_counted_and_named(name, tmp_path, capsys):
    forger = TimeForger(ATTACKS[name])
    rc, err, s = flight(tmp_path, capsys, forger)
    sync = s["sync"]
    r = s["_fcc_refused"]
    assert forger.pairs >= 40 and forger.auths == forger.pairs, (forger.pairs, forger.auths)
    # fcc had the chance to count every forged frame (a pair sent after the last verified),
    # and the forger saw each of its authenticators on the bus
    assert forger.master_auths_since >= 2 and sum(forger.refusals.values()) == forger.auths
    # every forged frame refused, once: the SYNC / FOLLOW_UP dropped when the master's next
    # pair verified, the authenticator on its MAC -- or, sent after the master's own of its
    # freshness value, as stale; nothing else (no genuine replay, nothing implausible reached
    # fcc) and nothing lost (fcc's port: rx_overflows)
    assert r["unauthenticated"] == forger.frames + sync["master_unpaired_frames"], (sync, forger.frames)
    judged = {k: forger.refusals[k] for k in AUTH_REFUSALS}
    assert {k: r[k] for k in AUTH_REFUSALS} == judged, (r, judged, s["firmware"]["bus"])
    assert r["step_refused"] == 0 and r["rate_refused"] == 0
    security = s["firmware"]["security"]["fcc"]
    assert {k: security[k] for k in AUTH_REFUSALS} == judged, security
    # the forged frames never reached E2E: the master's frames were never taken for repeats
    assert s["firmware"]["e2e"]["repeated"] == 0 and s["firmware"]["e2e"]["wrong_sequence"] == 0
    assert sync["verdict"] == "attacked"
    assert rc == 7 and (f"hil: time sync attacked: {forger.frames} forged SYNC/FOLLOW_UP frames, "
                        f"{forger.refusals['mac_failed']} forged and "
                        f"{forger.refusals['freshness_failed']} replayed TSYNC_AUTH refused") in err, err
    record(f"forged sync, {name}", s, rc)


FAULTS = {"step": step_error, "drag": drag_error}


@pytest.mark.parametrize("name", list(FAULTS))
def test_authenticated_master_out_of_bounds_is_refused(name, tmp_path, capsys):
    """(c) the master itself (it has the key) steps by -50 ms or drags at 4 ms/s for 5 s: fcc
    refuses its time as implausible against its own clock (REFUSED, the estimate goes on) and
    follows it again once it is right; the run exits 7 naming it."""
    faulty = FaultyMaster(FAULTS[name])
    rc, err, s = flight(tmp_path, capsys, faulty)
    sync = s["sync"]
    r = s["_fcc_refused"]
    assert faulty.pairs >= 40
    # a faulty pair is refused as implausible, or -- its authenticator lost on a loaded
    # machine -- dropped unauthenticated (both its frames); never used
    lost = (r["unauthenticated"] - sync["master_unpaired_frames"]) // 2
    if name == "step":   # every faulty pair is a step of 50 ms
        assert r["step_refused"] + lost == faulty.pairs and r["rate_refused"] == 0, (r, faulty.pairs)
    else:                # the first (at most 3) within 1 ms + 200 ppm, then a drift
        assert faulty.pairs - 3 <= r["rate_refused"] + lost <= faulty.pairs, (r, faulty.pairs)
        assert r["step_refused"] == 0, r
    assert r["mac_failed"] == r["freshness_failed"] == 0
    assert sync["verdict"] == "refused"
    assert rc == 7 and "hil: time master refused:" in err
    record(f"authenticated master, {name}", s, rc)


@pytest.mark.timing
def test_attacked_flights_fly_as_the_clean_one(tmp_path, capsys):
    """Speed-dependent: on a machine fast enough for the clean realtime flight to have every
    command on time, the attacked flights (a), (b) have every command on time too, fcc stays
    LOCKED with no loss, and their RMS q is within 3 % of the clean flight's."""
    rc, _, clean = flight(tmp_path / "clean", capsys)
    assert rc == 0 and clean["sync"]["verdict"] == "ok"
    ref = clean["missile"]["runs"][0]
    assert ref["commands_missing"] == 0
    record("clean", clean, rc)
    for name, error in ATTACKS.items():
        rc, _, s = flight(tmp_path / name.replace(" ", "_"), capsys, TimeForger(error))
        run = s["missile"]["runs"][0]
        assert rc == 7 and s["sync"]["state"] == "LOCKED" and s["sync"]["losses"] == 0
        assert run["commands_missing"] == 0, name
        assert abs(run["rms_q"] / ref["rms_q"] - 1) < 0.03, (name, run["rms_q"], ref["rms_q"])
        record(f"forged sync, {name}", s, rc)


def record(name: str, s: dict, rc: int) -> None:
    """One line per flight for the report's table ($FCC_TSYNC_TABLE, if set)."""
    path = os.environ.get("FCC_TSYNC_TABLE")
    if path:
        run = s["missile"]["runs"][0]
        with open(path, "a", encoding="utf-8") as f:
            f.write(json.dumps({"flight": name, "exit": rc, "rms_q": run["rms_q"],
                                "open_loop_rms_q": s["missile"]["runs"][1]["rms_q"],
                                "commands_missing": run.get("commands_missing"),
                                "sync": s["sync"]}) + "\n")
