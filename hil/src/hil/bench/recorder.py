"""The bus recorder's share of a lockstep flight (scripts/bench.d/recorder runs this inside
scripts/with-vcan): candump against canrec side by side in one guest, the same CDRW flights
in one session each, rounds alternated.

    python -m hil.bench.recorder [--flights 4] [--rounds 2] [--no-strace]

Per flight: the wall time of the lockstep loops and the CPU time of each process of the rig
(the recorder, fcc: /proc/PID/stat; the simulator: this process), all taken around the
flights only (session start and stop left out); per lockstep step: the recorder's wake-ups
(voluntary context switches) and, in a separate session under ``strace -c -p`` (which slows
it down, so it is not timed), its system calls.
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import statistics
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from hil.bench.rig import print_table
from hil.rig.config import RigConfig
from hil.rig.flight import fly, open_session
from hil.rig.recorder import RECORDERS, BusRecorder
from hil.scenario.file import load_default_scenario
from hil.sim.drivers import CdrwDriver
from hil.targets.host import HostFcc
from hil.util.processes import proc_stat
from hil.util.progress import bar as progress_bar

_TICK = os.sysconf("SC_CLK_TCK")


def _cpu_s(pid: int) -> float:
    """User + system CPU seconds of a process so far (utime, stime: proc(5) fields 14, 15)."""
    fields = proc_stat(pid)
    return (int(fields[11]) + int(fields[12])) / _TICK


def _wakeups(pid: int) -> int:
    with open(f"/proc/{pid}/status", encoding="ascii") as fh:
        m = re.search(r"^voluntary_ctxt_switches:\s+(\d+)", fh.read(), re.M)
    return int(m.group(1)) if m else 0


def _own_cpu_s() -> float:
    t = os.times()
    return t.user + t.system


@dataclass
class Sample:
    wall_s: float = 0.0
    steps: int = 0
    flights: int = 0
    recorder_s: float = 0.0
    fcc_s: float = 0.0
    sim_s: float = 0.0
    wakeups: int = 0
    syscalls: int = 0


def _session(out: Path, recorder: str, flights: int, strace: bool) -> Sample:
    """`flights` default CDRW flights in one rig session with this recorder."""
    sc = load_default_scenario("cdrw")
    cfg = RigConfig(out_dir=out, progress=False, plots=False, recorder=recorder)
    s = Sample(flights=flights)
    with open_session(out, [sc], cfg) as rig:
        assert isinstance(rig.bus_recorder, BusRecorder) and isinstance(rig.fcc, HostFcc)
        rec_pid, fcc_pid = rig.bus_recorder.pid, rig.fcc.pid
        tracer = None
        if strace:
            tracer = subprocess.Popen(["strace", "-c", "-q", "-o", str(out / "strace.txt"),
                                       "-p", str(rec_pid)], stderr=subprocess.DEVNULL)
            _wait_traced(rec_pid)
        c_rec, c_fcc, c_sim, w0 = _cpu_s(rec_pid), _cpu_s(fcc_pid), _own_cpu_s(), _wakeups(rec_pid)
        t0 = time.perf_counter()
        runner = None
        for _ in range(flights):
            d = CdrwDriver(sc, rig.codec, False)
            with progress_bar(d.n_steps, False, "") as bar:
                runner = fly(rig, [d], cfg, bar, runner)
            s.steps += d.n_steps
        rig.bus_recorder.wait_idle(10.0)  # it has read the last step
        s.wall_s = time.perf_counter() - t0
        s.recorder_s = _cpu_s(rec_pid) - c_rec
        s.fcc_s = _cpu_s(fcc_pid) - c_fcc
        s.sim_s = _own_cpu_s() - c_sim
        s.wakeups = _wakeups(rec_pid) - w0
        if tracer is not None:
            tracer.send_signal(signal.SIGINT)
            tracer.wait(30)
            s.syscalls = _strace_calls(out / "strace.txt")
        rig.shutdown()
    if not rig.log_complete:
        raise SystemExit(f"bench recorder: {recorder}: bus.log incomplete: {rig.recorder_error}")
    return s


def _wait_traced(pid: int, timeout: float = 10.0) -> None:
    """Until strace has attached (TracerPid in /proc/PID/status)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with open(f"/proc/{pid}/status", encoding="ascii") as fh:
            m = re.search(r"^TracerPid:\s+(\d+)", fh.read(), re.M)
        if m and int(m.group(1)) != 0:
            return
        time.sleep(0.01)
    raise SystemExit("bench recorder: strace did not attach")


def _strace_calls(path: Path) -> int:
    """The 'total' line's call count of strace -c."""
    for line in path.read_text().splitlines():
        parts = line.split()
        if parts and parts[-1] == "total":
            nums = [p for p in parts[:-1] if p.replace(".", "", 1).isdigit()]
            return int(nums[3])  # % time, seconds, usecs/call, calls[, errors]
    raise SystemExit(f"bench recorder: no total in {path}")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="hil.bench.recorder")
    p.add_argument("--flights", type=int, default=4, help="default CDRW flights per session")
    p.add_argument("--rounds", type=int, default=2, help="rounds of the recorders, alternated")
    p.add_argument("--no-strace", action="store_true", help="no system call count (strace)")
    a = p.parse_args(argv)
    strace = not a.no_strace and shutil.which("strace") is not None
    got: dict[str, list[Sample]] = {rec: [] for rec in RECORDERS}
    calls: dict[str, Sample] = {}
    load = [" ".join(f"{x:.1f}" for x in os.getloadavg())]
    with tempfile.TemporaryDirectory(prefix="bench-recorder.") as tmp:
        root = Path(tmp)
        for r in range(a.rounds):
            for rec in RECORDERS:
                got[rec].append(_session(root / f"{rec}-{r}", rec, a.flights, False))
        if strace:
            for rec in RECORDERS:
                calls[rec] = _session(root / f"strace-{rec}", rec, 1, True)
    load.append(" ".join(f"{x:.1f}" for x in os.getloadavg()))
    rows = []
    for label in RECORDERS:
        ss = got[label]

        def per_flight(attr: str) -> float:
            return statistics.median(getattr(x, attr) / x.flights for x in ss)  # noqa: B023 - this iteration's

        wake = statistics.median(x.wakeups / x.steps for x in ss)
        rows += [
            (f"{label}: lockstep loops, per flight", f"{per_flight('wall_s'):.3f} s", "", ""),
            ("  CPU per flight: recorder / fcc / simulator",
             f"{per_flight('recorder_s'):.3f} / {per_flight('fcc_s'):.3f} / {per_flight('sim_s'):.3f} s",
             "", ""),
            ("  recorder wake-ups per step", f"{wake:.2f}", "", ""),
        ]
        if label in calls:
            c = calls[label]
            rows.append(("  recorder system calls per step (strace -c, 1 flight)",
                         f"{c.syscalls / c.steps:.2f}", "", ""))
    print_table(f"the bus recorder in a lockstep CDRW session ({a.flights} flights of 351 steps per "
                f"session, median of {a.rounds} rounds, UML guest)", rows)
    print(f"the guest's load average (1, 5, 15 min) before | after: {' | '.join(load)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
