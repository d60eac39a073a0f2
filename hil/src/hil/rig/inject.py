"""Faults into a running realtime flight (`hil inject`): the channel between the command and
the rig, both ends.

The channel is a directory of the run, ``RUN/inject/`` (owner-only, 0700), in the run's staging
directory (hil.io.rundir: ``.NAME.partial-...`` next to ``--out``; removed when the session
closes, so it is never published):

    state.json        the rig's: mode, a random nonce of this session, whether it flies, and
                      each aircraft's step period and duration (the readiness marker: "flying")
    req-ID.json       a request: {"id", "fault", "mac"}, written as a temporary file and
                      renamed (the rig never reads half a request)
    ack-ID.json       the rig's answer: applied (the aircraft, the fault as applied, its
                      step and time) or refused (one line why)

A file queue, not a Unix socket: the rig usually flies inside the UML guest of
scripts/with-vcan, whose host file system is the host's, but whose kernel is its own.  A socket
bound there is reachable from the guest only (measured: a host process's sendto() on it is
refused, ECONNREFUSED), while a file renamed into the directory on the host is seen by the
guest's next directory scan.  The rig scans the directory once per step of the flight
(measured in the guest: 0.18 ms for the empty directory; a step is 20 ms or more).

Every request is authenticated with the run's bus key (AES-128-CMAC, hil.bus.secoc's) over
the session's nonce, the request's id and the fault: a request of another session (another
nonce) or without the key is refused, and each id is taken once (a replayed request is
refused).  The fault is parsed again by the rig (never trusted), for the aircraft of the
flight, and applied from the next step not yet handed over (or its own later start): the
drivers add it to their fault list, so faults.log, the CSVs, summary.json and the figures
carry it as they carry a scheduled one.
"""
from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import shutil
import stat
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from hil.bus import load
from hil.bus.secoc import KeyedCmac, same_mac
from hil.scenario.faults import T_EPS
from hil.scenario.file import parse_flight_fault
from hil.scenario.schema import ScenarioError
from hil.util.errors import EXIT_REFUSED, HilError

if TYPE_CHECKING:
    from hil.sim.drivers import AppDriver

CHANNEL = "inject"
STATE = "state.json"
#: a request file larger than this is refused unread
MAX_REQUEST = 4096
#: a fault spec longer than this is refused
MAX_FAULT = 512
_REQ = re.compile(r"req-([0-9a-f]{32})\.json")


def request_mac(key: bytes | KeyedCmac, nonce: str, rid: str, fault: str) -> str:
    """The request's MAC: the full 16-byte CMAC over the channel's label, the session's
    nonce, the request id and the fault, hex."""
    keyed = key if isinstance(key, KeyedCmac) else KeyedCmac(key)
    return keyed.digest(b"\0".join((b"hil-inject/1", nonce.encode(), rid.encode(), fault.encode()))).hex()


def _write_json(path: Path, doc: Mapping[str, Any]) -> None:
    """Written whole, then renamed into place: a reader sees the old file or the new one."""
    tmp = path.with_name(f".{path.name}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW, 0o600)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        json.dump(doc, fh)
    os.replace(tmp, path)


@dataclasses.dataclass(frozen=True)
class Request:
    rid: str
    fault: str


class InjectChannel:
    """The rig's end: opened with the session (lockstep too, so that `hil inject` can say why
    it is refused), scanned once per realtime step, removed when the session closes."""

    def __init__(self, run_dir: Path, mode: str | None, key: bytes) -> None:
        self.dir = Path(run_dir) / CHANNEL
        self.dir.mkdir(mode=0o700, exist_ok=True)
        self.dir.chmod(0o700)
        self.mode = mode
        self.nonce = os.urandom(16).hex()
        self._key = key
        self._keyed: KeyedCmac | None = None   # made at the first request (its import: 0.09 s)
        self._taken: set[str] = set()
        self.state: dict[str, Any] = {"mode": mode, "nonce": self.nonce, "flying": False}
        _write_json(self.dir / STATE, self.state)

    def flying(self, drivers: Sequence[AppDriver]) -> None:
        """The flight has begun: the readiness marker, with each aircraft's period and
        duration (what `hil inject` checks a fault against before sending it)."""
        self.state.update(flying=True, aircraft={
            d.name: {"period": d.period, "duration": d.scenario.duration} for d in drivers})
        _write_json(self.dir / STATE, self.state)

    def requests(self) -> list[Request]:
        """The authentic new requests in the directory (each file removed once read; every
        one refused is answered)."""
        try:
            names = sorted(e.name for e in os.scandir(self.dir) if e.name.startswith("req-"))
        except OSError:   # the channel is gone or unreadable: the flight flies on without it
            return []
        out = []
        for name in names:
            m = _REQ.fullmatch(name)
            if m is None:
                continue
            rid = m.group(1)
            fault, why = self._read(self.dir / name, rid)
            if why is None and rid in self._taken:
                why = "a replayed request (its id was taken before)"
            if why is not None:
                self.answer(rid, False, why)
                continue
            self._taken.add(rid)
            out.append(Request(rid, fault))
        return out

    def _read(self, path: Path, rid: str) -> tuple[str, str | None]:
        """(the fault, None) of an authentic request file, else ("", why); the file removed."""
        try:
            fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK)
        except OSError as e:
            return "", f"cannot read the request ({e.strerror})"
        try:
            st = os.fstat(fd)
            if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid():
                return "", "the request is not a regular file of the rig's user"
            data = os.read(fd, MAX_REQUEST + 1)
        finally:
            os.close(fd)
            path.unlink(missing_ok=True)
        if len(data) > MAX_REQUEST:
            return "", f"the request is larger than {MAX_REQUEST} bytes"
        try:
            doc = json.loads(data)
            fault, rid_in, tag = str(doc["fault"]), str(doc["id"]), str(doc["mac"])
        except (ValueError, KeyError, TypeError):
            return "", "the request is not one JSON object with id, fault and mac"
        if rid_in != rid or len(fault) > MAX_FAULT:
            return "", "the request's id is not its file's, or its fault is too long"
        if self._keyed is None:
            self._keyed = KeyedCmac(self._key)
        want = request_mac(self._keyed, self.nonce, rid, fault)
        if not same_mac(want.encode(), tag.encode()):
            return "", "not authenticated with the run's key (or for another session)"
        return fault, None

    def answer(self, rid: str, ok: bool, line: str, **facts: Any) -> None:
        """The answer `hil inject` waits for; one that cannot be written (the channel gone, a
        full disk) is not: the flight flies on, the sender's wait ends in its time-out."""
        try:
            _write_json(self.dir / f"ack-{rid}.json", {"ok": ok, "line": line, **facts})
        except OSError:
            pass

    def close(self) -> None:
        """Requests not taken are refused by the removal (their sender sees no rig)."""
        shutil.rmtree(self.dir, ignore_errors=True)


def apply_requests(channel: InjectChannel, drivers: Sequence[AppDriver], next_step: Mapping[int, int]) -> None:
    """Every new request: its fault parsed for this flight's aircraft and added to its
    driver from the next step not yet handed over (next_step: by id(driver)), or refused."""
    for req in channel.requests():
        try:
            d, fault = _fault_for(req.fault, drivers)
            k = next_step[id(d)]
            # the first step at or after its start, not before the next one to be made
            applied = max(k, math.ceil(fault.start / d.period - T_EPS))
            if applied >= d.n_steps:
                raise ScenarioError(f"the {d.name}'s last step is at {(d.n_steps - 1) * d.period:g} s: "
                                    f"the fault would start after it")
            fault = dataclasses.replace(fault, start=max(fault.start, k * d.period))
            d.inject(fault)
        except (ScenarioError, ValueError) as e:
            channel.answer(req.rid, False, str(e).splitlines()[0])
            continue
        channel.answer(req.rid, True, f"{d.name}: {fault.describe()} from step {applied} "
                       f"(t = {applied * d.period:.3f} s)", aircraft=d.name, fault=fault.describe(),
                       received_step=k, step=applied, t=applied * d.period)


def _fault_for(text: str, drivers: Sequence[AppDriver]) -> tuple[AppDriver, Any]:
    durations = {d.name: d.scenario.duration for d in drivers}
    aircraft, fault = parse_flight_fault(text, durations, f"hil inject: fault {text!r}",
                                         {m.name for m in load().messages})
    d = next(d for d in drivers if d.name == aircraft)
    if not d.closed_loop:
        raise ScenarioError(f"hil inject: the {d.name}'s flight is computed before it starts "
                            f"(open loop): faults are injected into the missile's flight only")
    return d, fault


# -- the command's end ------------------------------------------------------------------------
class InjectRefused(HilError, RuntimeError):
    """`hil inject` refused (no live realtime rig, not its key, the rig said no): one line."""

    exit_status = EXIT_REFUSED


def live_channels(out: Path) -> list[Path]:
    """The channels of the runs flying into --out now (their staging directories')."""
    out = Path(out)
    if (out / CHANNEL / STATE).is_file():   # a session given its run directory itself
        return [out / CHANNEL]
    return sorted(p for p in out.parent.glob(f".{out.name}.partial-*/{CHANNEL}") if (p / STATE).is_file())


def read_state(channel: Path) -> dict[str, Any]:
    try:
        doc = json.loads((channel / STATE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        raise InjectRefused(f"{channel}: no rig answers there (the run has ended)") from None
    return doc if isinstance(doc, dict) else {}


def with_start(text: str) -> str:
    """A fault spec without a start: from the next step (start = 0, moved there by the rig)."""
    kind, _, body = text.partition(":")
    fields = [s.strip() for s in body.split(",") if s.strip()]
    if any(f.partition("=")[0].strip() == "start" for f in fields):
        return text
    return f"{kind}:{','.join(['start=0', *fields])}"


def send(channel: Path, text: str, key: bytes) -> str:
    """The request, written into the channel; its id."""
    state = read_state(channel)
    rid = os.urandom(16).hex()
    doc = {"id": rid, "fault": text, "mac": request_mac(key, str(state.get("nonce", "")), rid, text)}
    _write_json(channel / f"req-{rid}.json", doc)
    return rid


def check_fault(text: str, state: Mapping[str, Any]) -> None:
    """The fault parsed for the flight's aircraft, as the rig will (ScenarioError: exit 2)."""
    aircraft = state.get("aircraft") or {}
    parse_flight_fault(text, {a: float(v["duration"]) for a, v in aircraft.items()},
                       "hil inject: fault " + repr(text), {m.name for m in load().messages})

