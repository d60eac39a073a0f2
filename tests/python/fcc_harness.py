"""Driving build/bin/fcc on a bus from pytest: start it, play the simulator's
side of the lockstep protocol with hil.bus (python-can + cantools, real E2E),
read its counters.  Used by tests/python/test_fcc_*.py; no mocks: the fcc
process, the kernel's vcan and the DBC codec are the real ones.
"""
from __future__ import annotations

import math
import re
import signal
import subprocess
import time
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

from hil.bus.protocol import COMMAND_FLIGHT
from hil.bus import SIM_NODES, Decoded, load
from hil.bus.node import BusNode
from hil.bus.secoc import TEST_KEY_FILE, Endpoint, read_key_file

STATUS_IDS = frozenset((*range(0x700, 0x705), 0x705, 0x706, 0x707))
CDRW, MISSILE = 0, 1
_SUMMARY = re.compile(r"^fcc summary: (\S+)(?: (\S+))? (.*)$")


def parse_summary(stderr: str) -> dict[str, dict[str, float]]:
    """The exit block, e.g. {"cdrw": {"steps": 150, ...}, "e2e": {...}, "latency_us missile": {...}}."""
    out: dict[str, dict[str, float]] = {}
    for line in stderr.splitlines():
        m = _SUMMARY.match(line)
        if not m:
            continue
        group, sub, rest = m.group(1), m.group(2), m.group(3)
        pairs = re.findall(r"(\w+)=([-\d.]+)", (sub or "") + " " + rest)
        key = group if sub is None or "=" in sub else f"{group} {sub}"
        out[key] = {k: float(v) for k, v in pairs}
    return out


@dataclass
class Fcc:
    """One fcc process; stderr goes to a file so a chatty run can never block it."""

    binary: Path
    args: Iterable[str] = ()
    workdir: Path = Path(".")
    proc: subprocess.Popen[bytes] | None = None
    stderr_path: Path = field(init=False)

    def __post_init__(self) -> None:
        self.stderr_path = self.workdir / "fcc.stderr"

    def start(self) -> Fcc:
        """Started with the published test key unless args name a --key-file."""
        args = list(self.args)
        if "--key-file" not in args:
            args = ["--key-file", str(TEST_KEY_FILE), *args]
        self._err = open(self.stderr_path, "wb")  # noqa: SIM115 -- closed in stop()
        self.proc = subprocess.Popen([str(self.binary), *args], stdout=subprocess.DEVNULL,
                                     stderr=self._err)
        return self

    def stderr(self) -> str:
        return self.stderr_path.read_text(errors="replace")

    def wait_ready(self, timeout: float = 5.0) -> None:
        self.wait_for("fcc: ready", timeout)

    def wait_for(self, text: str, timeout: float = 10.0) -> None:
        """Until fcc has written `text` on stderr (polled; fails after `timeout` s)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if text in self.stderr():
                return
            assert self.proc is not None
            if self.proc.poll() is not None:
                raise AssertionError(f"fcc exited {self.proc.returncode}: {self.stderr()}")
            time.sleep(0.01)
        raise AssertionError(f"fcc did not write {text!r} within {timeout} s: {self.stderr()}")

    def wait(self, timeout: float = 5.0) -> int:
        assert self.proc is not None
        rc = self.proc.wait(timeout=timeout)
        self._err.close()
        return rc

    def stop(self, sig: int = signal.SIGTERM, timeout: float = 5.0) -> int:
        assert self.proc is not None
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        return self.wait(timeout)

    def kill(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        if hasattr(self, "_err") and not self._err.closed:
            self._err.close()


class Sim:
    """The simulator's side: sends sensor frames and ticks (commands authenticated with the
    test key), collects fcc's answers (secured ones only once authenticated).  `endpoint`
    carries the freshness state over to a second simulator process on the same fcc."""

    def __init__(self, channel: str = "vcan0", endpoint: Endpoint | None = None) -> None:
        self.node = BusNode(channel, SIM_NODES)
        self.sec = endpoint or Endpoint(load(), read_key_file(TEST_KEY_FILE), SIM_NODES)
        self.status: dict[str, dict[str, float | int]] = {}
        self._held: dict[int, list[Decoded]] = {}

    def close(self) -> None:
        self.node.close()

    def send(self, name: str, values: dict) -> None:
        """Encode, send, and follow with the authenticator when the message is secured."""
        frame_id, data = self.node.encode(name, values)
        for fid, d in self.sec.protect(frame_id, data):
            assert self.node.send_raw(fid, d)

    def attach(self, timeout: float = 5.0, flight: bool = True) -> None:
        """Learn fcc's trip from its first authenticated heartbeat, then (flight) put it in FLIGHT."""
        deadline = time.monotonic() + timeout
        while self.sec.trip is None and time.monotonic() < deadline:
            for _ in self._frames(0.05):
                pass
        assert self.sec.trip is not None, "no authenticated heartbeat from fcc"
        if flight:
            self.control(COMMAND_FLIGHT)

    # -- sending
    def cdrw(self, k: int, alpha: float, q: float, de: float, skip: Iterable[str] = ()) -> None:
        frames = {"CDRW_AOA": {"alpha": alpha}, "CDRW_PITCH_RATE": {"q": q},
                  "CDRW_ELEVATOR": {"delta_e": de}}
        for name, values in frames.items():
            if name not in skip:
                self.send(name, {"step": k & 0xFFFF, **values})

    def missile(self, k: int, q_g: float, n_a: float, skip: Iterable[str] = ()) -> None:
        if "MSL_RATE_GYRO" not in skip:
            self.send("MSL_RATE_GYRO", {"step": k & 0xFFFF, "q_g": q_g})
        if "MSL_ACCELEROMETER" not in skip:
            self.send("MSL_ACCELEROMETER", {"step": k & 0xFFFF, "n_a": n_a})

    def tick(self, app: int, k: int) -> None:
        self.send("SIM_TICK", {"app": app, "step": k})

    def control(self, command: int = 0, period: float = 0.0, bits: int = 0) -> None:
        self.send("SIM_CONTROL", {"command": command, "lqg_period": period, "da_bits": bits})

    def event(self, oracle_fault: bool, k: int, kind: int = 1, target: int = 0x050) -> None:
        self.send("SIM_EVENT", {"active": int(oracle_fault), "oracle_fault":
                                            int(oracle_fault), "fault_id": 0, "kind": kind,
                                            "target_id": target, "step": k & 0xFFFF})

    # -- receiving
    def _keep_status(self, d: Decoded) -> None:
        if d.ok and d.name is not None and d.values is not None:
            self.status[d.name] = d.values

    def _frames(self, seconds: float) -> Iterator[Decoded]:
        """Every frame received for `seconds`, secured ones once authenticated (status frames
        also recorded in self.status)."""
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0:
            got = self.node.recv(left)
            if got is None:
                return
            for fid, data in self.sec.receive(got.frame_id, got.data):
                d = got if fid == got.frame_id else self._take(fid, data)
                if d is None:
                    continue
                if d.frame_id in STATUS_IDS:
                    self._keep_status(d)
                yield d
            if self.sec.is_secured(got.frame_id):
                self._held.setdefault(got.frame_id, []).append(got)
                del self._held[got.frame_id][:-8]

    def _take(self, frame_id: int, data: bytes) -> Decoded | None:
        """The held Decoded of a secured frame that has just been authenticated."""
        for d in reversed(self._held.get(frame_id, [])):
            if d.data == data:
                return d
        return None

    def until_ack(self, app: int, k: int, timeout: float = 2.0) -> tuple[list[Decoded], Decoded]:
        """Frames fcc sent before FCC_ACK(app, k) (status frames kept aside), and the ACK."""
        frames: list[Decoded] = []
        for d in self._frames(timeout):
            if d.frame_id in STATUS_IDS:
                continue
            if d.name == "FCC_ACK" and d.ok and d.values is not None \
                    and d.values["app"] == app and d.values["step"] == k:
                return frames, d
            frames.append(d)
        raise AssertionError(f"no FCC_ACK for app {app} step {k} within {timeout} s")

    def quiet(self, seconds: float) -> list[Decoded]:
        """Everything received for a while (status frames recorded too)."""
        return list(self._frames(seconds))

    def drain(self, idle: float = 0.3, limit: float = 10.0) -> list[Decoded]:
        """Everything still queued: received until the bus has been idle for `idle` seconds."""
        got: list[Decoded] = []
        deadline = time.monotonic() + limit
        while time.monotonic() < deadline:
            more = list(self._frames(idle))
            if not more:
                break
            got += more
        return got

    def step_cdrw(self, k: int, alpha: float, q: float, de: float,
                  skip: Iterable[str] = ()) -> tuple[dict[str, dict], Decoded]:
        self.cdrw(k, alpha, q, de, skip)
        self.tick(CDRW, k)
        frames, ack = self.until_ack(CDRW, k)
        return {d.name: d.values for d in frames if d.ok and d.name}, ack

    def step_missile(self, k: int, q_g: float, n_a: float,
                     skip: Iterable[str] = ()) -> tuple[dict[str, dict], Decoded]:
        self.missile(k, q_g, n_a, skip)
        self.tick(MISSILE, k)
        frames, ack = self.until_ack(MISSILE, k)
        return {d.name: d.values for d in frames if d.ok and d.name}, ack


def flight(k: int) -> tuple[float, float, float]:
    """A smooth pull-up with some excitation, rounded to the sensors' 1e-6 resolution."""
    t = 0.02 * k
    de = -0.05 - 0.08 * math.sin(1.3 * t)
    alpha = 0.16 + 0.1 * math.sin(0.9 * t) + 0.002 * math.sin(17.0 * t)
    q = 0.09 * math.cos(0.9 * t) + 0.01 * math.sin(11.0 * t)
    return round(alpha, 6), round(q, 6), round(de, 6)


def missile_sensors(k: int) -> tuple[float, float]:
    """Gyro (rad/s, 1e-5) and accelerometer (ft/s^2, 0.002) samples."""
    q_g = 0.1 * math.cos(0.7 * k) + 0.3 * math.sin(2.1 * k)
    n_a = -3.0 + 40.0 * math.sin(0.45 * k)
    return round(q_g, 5), round(n_a / 0.002) * 0.002
