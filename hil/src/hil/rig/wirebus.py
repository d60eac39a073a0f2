"""`hil run --bus wire`: the rig's nodes on a wire-time bus (firmware/tools/canbus).

Each node -- the simulator, fcc, the bus recorder -- gets a vxcan pair of its own: the node
uses one end, canbus holds the other and moves frames between them as a classic CAN bus does
(arbitration, stuffed frame lengths at the bit rate; docs/bus-timing.md).  canbus is started
first, with each node's queue policy, and the nodes are pointed at their ends once it says it
is ready; at the end it is drained (every frame sent has ended on the bus), stopped with
SIGTERM, and its statistics line (JSON) is the run's bus section (hil.results.busstats).

    with WireBus(run_dir, 500_000) as bus:
        bus.end("sim"), bus.end("fcc"), bus.end("recorder")   # the interfaces the nodes use
        ...
        bus.drain()          # before the recorder is stopped: the end marker has reached it
        stats = bus.stop()   # canbus's statistics (a dict)
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path
from types import TracebackType

from hil.bus.dbc import BusSpec
from hil.io.paths import ToolNotFound, tool
from hil.rig.errors import RigError
from hil.rig.wirefaults import canbus_args
from hil.scenario.faults import Fault
from hil.util.processes import last_line, spawn

#: the nodes and their controllers' queue policy: the simulator's sensor ECUs are
#: priority-ordered mailboxes (what hil.bus.wcrt analyses); fcc is a Linux SocketCAN node,
#: whose frames wait in one FIFO (pfifo_fast, then the driver's one transmit buffer); the M4F
#: image is a FIFO too, its serial line joined by slcan_bridge to fcc's end (hil.targets.qemu_m4f).  canbus
#: writes a frame to the nodes in this order: the recorder's end (where the time master reads
#: its SYNC back) before fcc's, since fcc, a realtime process, runs as soon as its frame comes
#: and would delay the next write by its step (measured: SYNC pairs refused by fcc's
#: plausibility check, |offset step| > 1 ms, in 5-13 % of the pairs with fcc written first)
NODES = {"sim": "prio", "recorder": "prio", "fcc": "fifo"}
#: the DBC's names of the FIFO-queued senders (what hil.bus.wcrt analyses as a FIFO node; a
#: real bus's device is assumed one too: its controller's policy unknown, FIFO is the safe bound)
FIFO_SENDERS = tuple(node.upper() for node, policy in NODES.items() if policy == "fifo")
#: canbus's SCHED_FIFO priority: above fcc's (hil.rig.flight.FCC_RT_PRIORITY, 50)
RT_PRIORITY = 60
READY_TIMEOUT_S = 10.0
#: how long drain() waits for canbus to carry what the nodes sent (an over-utilised bus at
#: 125 kbit/s may hold seconds of backlog)
DRAIN_TIMEOUT_S = 60.0
_POLL_S = 0.02


def _ip(*args: str) -> None:
    """`ip link ...`; a failure is the run's (one line)."""
    done = subprocess.run(["ip", "link", *args], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        said = (done.stderr or done.stdout).strip().splitlines()
        raise RigError(f"--bus wire: ip link {' '.join(args)}: {said[-1] if said else done.returncode}"
                       f" (vxcan needs the vxcan module and CAP_NET_ADMIN: scripts/with-vcan)")


class WireBus:
    """canbus and one vxcan pair per node, for a ``with`` block."""

    def __init__(self, run_dir: Path, bitrate: int, faults: tuple[Fault, ...] = (),
                 spec: BusSpec | None = None, seed: int = 0) -> None:
        self.bitrate = bitrate
        #: the scenario's wire faults (hil.rig.wirefaults), their times from start_faults()
        self.faults = faults
        #: the scenario's seed: a background load's phases and data (as in lockstep)
        self.seed = seed
        self._spec = spec
        self._dir = Path(run_dir) / f".canbus-{os.getpid()}"
        self._dir.mkdir(parents=True, exist_ok=True)
        # interface names are at most 15 characters: w<pid><s|f|r>[b]
        tag = f"w{os.getpid() % 10_000_000}"
        self.ends = {node: f"{tag}{node[0]}" for node in NODES}
        self._made: list[str] = []
        self.proc: subprocess.Popen | None = None
        self.rt_priority = 0
        self.stats: dict = {}

    def end(self, node: str) -> str:
        """The interface the node uses."""
        return self.ends[node]

    def __enter__(self) -> WireBus:
        try:
            for node in NODES:
                self._pair(self.ends[node])
            self._start()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def _pair(self, name: str) -> None:
        _ip("add", name, "type", "vxcan", "peer", "name", f"{name}b")
        self._made.append(name)
        _ip("set", name, "up")
        _ip("set", f"{name}b", "up")

    def _start(self) -> None:
        try:
            exe = str(tool("canbus"))
        except ToolNotFound as e:
            raise RigError(str(e)) from None
        cmd = [exe, "--bitrate", str(self.bitrate)]
        for node, policy in NODES.items():
            cmd += ["--node", f"{self.ends[node]}b:{policy}"]
        if self.faults:
            assert self._spec is not None
            cmd += ["--epoch", str(self._dir / "epoch"),
                    *canbus_args(self.faults, {n: f"{e}b" for n, e in self.ends.items()}, self._spec,
                                 self.seed)]
        with open(self._dir / "stderr", "wb") as err, open(self._dir / "stdout", "wb") as out:
            self.proc = spawn(cmd, stdin=subprocess.DEVNULL, stdout=out, stderr=err)
        self.rt_priority = self._realtime(self.proc.pid)
        deadline = time.monotonic() + READY_TIMEOUT_S
        while b"canbus: ready" not in (self._dir / "stderr").read_bytes():
            if self.proc.poll() is not None:
                raise RigError(f"canbus stopped at start-up: {self._said()}")
            if time.monotonic() > deadline:
                raise RigError(f"canbus did not say it is ready within {READY_TIMEOUT_S:g} s")
            time.sleep(_POLL_S)

    @staticmethod
    def _realtime(pid: int) -> int:
        """canbus in SCHED_FIFO above fcc's priority, where allowed (0: not allowed): the
        wire must not wait for a node (a realtime fcc woken by one delivery would otherwise
        run its step before canbus writes the same frame to the next node)."""
        try:
            os.sched_setscheduler(pid, os.SCHED_FIFO, os.sched_param(RT_PRIORITY))
        except OSError:
            return 0
        return RT_PRIORITY

    def _said(self) -> str:
        return last_line(self._dir / "stderr") or f"exit status {self.proc.returncode if self.proc else '?'}"

    def _lines(self) -> list[str]:
        return (self._dir / "stdout").read_text().splitlines()

    def start_faults(self, t0: float) -> None:
        """The faults' times count from t0 (time.monotonic(): the flight's first instant)."""
        if self.faults and self.proc is not None:
            (self._dir / "epoch").write_text(f"{round(t0 * 1e9)}\n")
            self.proc.send_signal(signal.SIGUSR2)

    def report(self, timeout: float = 2.0) -> dict:
        """canbus's statistics now (SIGUSR1: one JSON line, after it has read every frame sent
        before the signal)."""
        assert self.proc is not None
        before = len(self._lines())
        self.proc.send_signal(signal.SIGUSR1)
        deadline = time.monotonic() + timeout
        while (lines := self._lines())[before:] == [] or not lines[-1].endswith("}"):
            if self.proc.poll() is not None:
                raise RigError(f"canbus stopped during the run: {self._said()}")
            if time.monotonic() > deadline:
                raise RigError(f"canbus did not report its statistics within {timeout:g} s")
            time.sleep(_POLL_S)
        return json.loads(lines[-1])

    def drain(self) -> None:
        """Until every frame the nodes sent has ended on the bus and been delivered: one report
        with nothing pending, and the next with no new frame (so canbus's reading found
        nothing more in its endpoints' queues)."""
        deadline = time.monotonic() + DRAIN_TIMEOUT_S
        last = -1
        while time.monotonic() < deadline:
            s = self.report()
            if s["pending"] == 0 and s["frames"] == last:
                return
            last = s["frames"] if s["pending"] == 0 else -1
            time.sleep(_POLL_S)
        raise RigError(f"canbus still carried frames {DRAIN_TIMEOUT_S:g} s after the run")

    def stop(self) -> dict:
        """SIGTERM; canbus's last statistics (exit 0, or 3 when it lost frames: `lost` says)."""
        if self.proc is None:
            return self.stats
        proc, self.proc = self.proc, None
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(5.0)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        lines = self._lines()
        if proc.returncode not in (0, 3) or not lines:
            raise RigError(f"canbus failed: {self._said()}")
        self.stats = json.loads(lines[-1])
        names = {f"{end}b": node for node, end in self.ends.items()}
        for n in self.stats.get("nodes", []):   # the rig's names: sim, recorder, fcc, babble0
            n["node"] = names.get(n["iface"], n["iface"])
        return self.stats

    def close(self) -> None:
        """canbus stopped (if still running), the pairs deleted, the private directory gone."""
        try:
            if self.proc is not None and self.proc.poll() is None:
                self.proc.kill()
                self.proc.wait()
            self.proc = None
        finally:
            for name in self._made:
                subprocess.run(["ip", "link", "del", name], capture_output=True, check=False)
            self._made = []
            for f in self._dir.glob("*"):
                f.unlink()
            self._dir.rmdir() if self._dir.exists() else None
