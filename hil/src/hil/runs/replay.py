"""`hil replay RUN_DIR`: a recorded lockstep run as a firmware regression test.

The simulator's frames of the recording (everything the DBC says a simulator node sends,
in recorded order, E2E counters and faults included) go to a fresh fcc with lockstep flow
control: after a SIM_TICK that the recorded fcc acknowledged, the replay waits for the live
FCC_ACK of the same step before it sends on.  fcc's frames between two acknowledges are
compared with the recording's, frame by frame and signal by signal, except what depends on
the wall clock: the heartbeat frames (0x700 and above) and FCC_ACK's exec_us (and so its CRC).
The first difference is reported with its step, message, signal and both values.
Authenticator frames are session-bound (key, fcc's trip): the recorded ones are dropped, the
replay authenticates what it sends for the live fcc, and fcc's live authenticators are not
compared (the frames they authenticate are).

fcc runs with the recorded command line (run_info.json) and the extra --fcc-args; the
firmware is the current one (--fcc, $FCC_HIL_FCC, the build), not the recorded path.
"""
from __future__ import annotations

import json
import shlex
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from hil.bus import load
from hil.bus.apps import NAME_OF_CODE
from hil.bus.candump import LogFrame
from hil.bus.dbc import BusSpec
from hil.bus.logio import read_frames, run_log
from hil.bus.secoc import KeyFileError, read_key_file
from hil.results.buslog import BusAuth, authentic_frames
from hil.rig.config import RigConfig
from hil.rig.errors import FccDied
from hil.rig.link import pack_frame
from hil.rig.session import KEPT_KEY, RigSession
from hil.rig.simtime import WALL_LOG
from hil.targets.host import HostFcc
from hil.util.bounded import UnfitFile, read_bounded
from hil.util.errors import InputError

SIM_SENDERS = {"SIM", "CDRW_AOA_SENSOR", "CDRW_GYRO", "CDRW_ELEV_SENSOR", "MSL_GYRO", "MSL_ACCEL"}
WALL_CLOCK_IDS = 0x700          # heartbeat and rig frames from here up: not compared
SKIP_SIGNALS = {"FCC_ACK": ("exec_us", "crc")}


#: run_info.json: a few kB
RUN_INFO_MAX_BYTES = 1 << 20


class ReplayError(InputError, ValueError):
    """The run directory cannot be replayed: not a lockstep run, its bus key not kept, its
    run_info.json or bus log malformed (one line, exit 2: nothing is started)."""


@dataclass
class Segment:
    """What the simulator sent up to one acknowledge, and what fcc answered."""

    send: list[tuple[int, bytes]] = field(default_factory=list)
    fcc: list[tuple[int, bytes]] = field(default_factory=list)
    ack: tuple[int, int] | None = None      # (app, step) acknowledged at its end


@dataclass
class Difference:
    step: str
    message: str
    signal: str
    recorded: object
    replayed: object

    def __str__(self) -> str:
        def fmt(v: object) -> str:
            return f"{v:.10g}" if isinstance(v, float) else str(v)
        return (f"first difference at {self.step}: {self.message}.{self.signal}: recorded "
                f"{fmt(self.recorded)}, replayed {fmt(self.replayed)}")


def run_info(run_dir: Path) -> dict:
    """The recorded run's run_info.json (ReplayError: one line why it cannot be read)."""
    path = run_dir / "run_info.json"
    try:
        info = json.loads(read_bounded(path, RUN_INFO_MAX_BYTES, "run_info.json"))
    except UnfitFile as e:
        raise ReplayError(str(e)) from None
    except OSError as e:
        raise ReplayError(f"{path}: cannot be read: {e.strerror or e}") from None
    except (ValueError, RecursionError, MemoryError) as e:  # not JSON (nor UTF-8), or nested too deeply
        raise ReplayError(f"{path}: not valid JSON: {type(e).__name__}: {str(e)[:120]}") from None
    if not isinstance(info, dict):
        raise ReplayError(f"{path}: not a run_info object")
    return info


def recorded_fcc_args(run_dir: Path) -> list[str]:
    """fcc's options of the recorded run, without the interface, key file and trip."""
    info = run_info(run_dir)
    try:
        cmd = shlex.split(info["fcc_command"])
    except (ValueError, KeyError, TypeError, AttributeError) as e:
        raise ReplayError(f"{run_dir / 'run_info.json'}: no fcc command line "
                          f"({type(e).__name__}: {e})") from None
    if info.get("mode") != "lockstep":
        raise ReplayError(f"{run_dir}: a {info.get('mode')} run; only lockstep runs replay")
    args = cmd[1:]
    out: list[str] = []
    skip = False
    for a in args:
        if skip:
            skip = False
        elif a in ("--iface", "--key-file", "--trip"):   # this bus, this session's key and trip
            skip = True
        else:
            out.append(a)
    return out


def recorded_key(run_dir: Path) -> bytes:
    """The recorded run's bus key: its session key kept in the run directory, or the
    --key-file it ran with (run_info.json); without it the recording cannot be told from
    frames forged on its bus: refused."""
    kept = run_dir / KEPT_KEY
    try:
        if kept.is_file():
            return read_key_file(kept)
        key_file = run_info(run_dir).get("key_file")
        if key_file:
            return read_key_file(key_file)
    except (KeyFileError, OSError, ValueError) as e:
        raise ReplayError(f"{run_dir}: the run's bus key cannot be read ({e}); only its "
                          f"authenticated frames may be replayed") from None
    raise ReplayError(f"{run_dir}: the run's bus key is not kept ({KEPT_KEY}, or run_info.json's "
                      f"key_file): its authenticated frames cannot be told from forged ones")


def recorded_segments(run_dir: Path, log: Path, spec: BusSpec) -> list[Segment]:
    """The recording's authentic frames cut at fcc's acknowledges, read before anything starts:
    a malformed log (a line not candump -L, a file python-can cannot read, not a regular file)
    is a ReplayError naming the log, not a difference."""
    key = recorded_key(run_dir)
    try:
        segs = segments(authentic_frames(read_frames(log), BusAuth(key)), spec)
    except UnfitFile as e:
        raise ReplayError(str(e)) from None
    except OSError as e:
        raise ReplayError(f"{log}: cannot be read: {e.strerror or e}") from None
    except Exception as e:  # noqa: BLE001 - the log's parsers (candump's, python-can's) raise many kinds
        raise ReplayError(f"{log}: not a bus log hil can replay: "
                          f"{str(e).splitlines()[0] if str(e) else type(e).__name__}") from None
    if not any(seg.ack for seg in segs):
        raise ReplayError(f"{log}: no step fcc acknowledged under the run's key: nothing to replay")
    return segs


def segments(frames: Iterator[LogFrame], spec: BusSpec) -> list[Segment]:
    """The recording cut at fcc's acknowledges."""
    ack_id = spec.by_name("FCC_ACK").frame_id
    out = [Segment()]
    for f in frames:
        if not f.classic_data:
            continue
        msg = spec.by_id(f.frame_id)
        if msg is None or (f.frame_id >= WALL_CLOCK_IDS and msg.name != "SIM_EVENT") \
                or msg.is_authenticator:
            continue
        if SIM_SENDERS.intersection(msg.senders):
            out[-1].send.append((f.frame_id, f.data))
        elif f.frame_id == ack_id:
            out[-1].ack = ack_key(f.data)
            out[-1].fcc.append((f.frame_id, f.data))
            out.append(Segment())
        else:
            out[-1].fcc.append((f.frame_id, f.data))
    return out


def ack_key(data: bytes) -> tuple[int, int]:
    return (data[1] >> 4) & 0x3, int.from_bytes(data[2:6], "little")


def compare(spec: BusSpec, where: str, rec: Sequence[tuple[int, bytes]],
            live: Sequence[tuple[int, bytes]]) -> Difference | None:
    for i in range(max(len(rec), len(live))):
        r = rec[i] if i < len(rec) else None
        v = live[i] if i < len(live) else None
        if r is None or v is None or r[0] != v[0]:
            name = lambda fr: (m.name if fr and (m := spec.by_id(fr[0])) else "-")  # noqa: E731
            return Difference(where, f"frame {i + 1}", "message", name(r), name(v))
        if r[1] == v[1]:
            continue
        msg = spec.by_id(r[0])
        assert msg is not None
        skip = SKIP_SIGNALS.get(msg.name, ())
        dr = msg.decode(r[1])
        dv = msg.decode(v[1])
        for sig in msg.signals:
            if sig.name not in skip and dr[sig.name] != dv[sig.name]:
                return Difference(where, msg.name, sig.name, dr[sig.name], dv[sig.name])
    return None


def replay(run_dir: Path, out_dir: Path, extra_args: Sequence[str] = (), iface: str = "vcan0",
           timeout: float = 2.0, fcc_binary: Path | None = None) -> tuple[int, Difference | None]:
    """Replay; returns (steps acknowledged, first difference or None)."""
    log = run_dir / WALL_LOG if (run_dir / WALL_LOG).is_file() else run_log(run_dir)
    if log is None:
        raise ReplayError(f"{run_dir}: no bus log (bus_wall.log, bus.log, bus.asc, bus.blf)")
    args = recorded_fcc_args(run_dir) + list(extra_args)
    spec = load()
    segs = recorded_segments(run_dir, log, spec)
    rig = RigSession(out_dir, args, RigConfig(out_dir=out_dir, iface=iface, fcc_binary=fcc_binary),
                     record=False, spec=spec)
    fcc_ids = {m.frame_id for m in spec.messages
               if not SIM_SENDERS.intersection(m.senders) and m.frame_id < WALL_CLOCK_IDS}
    rig.fcc_ids = tuple(sorted(fcc_ids | set(rig.fcc_ids)))
    auth_ids = {m.frame_id for m in spec.messages if m.is_authenticator}
    steps = 0
    with rig:
        link = rig.link
        assert link is not None
        for seg in segs:
            live: list[tuple[int, bytes]] = []
            for fid, data in seg.send:
                for f, d in rig.secure(fid, data):
                    link.send_raw(pack_frame(f, d))
            if seg.ack is None:      # the tail: fcc's last words after the shutdown
                break
            app, k = seg.ack
            where = f"step {k} of app {NAME_OF_CODE.get(app, app)}"
            deadline = time.monotonic() + timeout
            while True:
                got = link.recv()
                if got is None:
                    rig.check_alive(f"during {where}")
                    if time.monotonic() > deadline:
                        return steps, Difference(where, "FCC_ACK", "received", "an acknowledge",
                                                 f"nothing within {timeout:g} s")
                    continue
                if got[0] >= WALL_CLOCK_IDS:
                    rig.note_frame(*got)
                    continue
                if got[0] in auth_ids:
                    continue
                live.append(got)
                if got[0] == spec.by_name("FCC_ACK").frame_id and ack_key(got[1]) == seg.ack:
                    break
            diff = compare(spec, where, seg.fcc, live)
            if diff is not None:
                return steps, diff
            steps += 1
        if isinstance(rig.fcc, HostFcc) and rig.fcc.wait(5.0) is None:  # replay runs the host's fcc
            raise FccDied("fcc did not exit after the recorded shutdown command")
        rest = [g for g in link.drain() if g[0] < WALL_CLOCK_IDS and g[0] not in auth_ids]
        diff = compare(spec, "the end of the run", segs[-1].fcc, rest)
    return steps, diff
