"""The platform a realtime run flies on, measured beside the flight: what the kernel is, and how
late it wakes a thread of fcc's priority at the flight's period (the baseline).

A realtime verdict needs both: a step that misses its deadline on a kernel that by itself
wakes a SCHED_FIFO thread 5 ms late says little about the firmware (hil.results.platform).
The baseline is rt-tests' ``cyclictest`` (a real tool, in Debian: scripts/setup installs it),
one measuring thread at the flight's shortest period and fcc's SCHED_FIFO priority
(hil.rig.config.FCC_RT_PRIORITY) for as long as the flight, with ``--default-system`` so that
the measurement does not tune the system it measures (no /dev/cpu_dma_latency request).  A
Python thread would measure Python's jitter, not the platform's.

Its histogram is exported in cyclictest's own histogram format (``platform_latency.hist``:
``USEC COUNT`` rows, then the ``# Total``/``# Min``/``# Avg``/``# Max Latencies`` and
``# Histogram Overflows`` lines; rows with a zero count are left out) and summarised in
run_info.json's ``platform.baseline``.  Where cyclictest is missing or cannot run (no
privilege for SCHED_FIFO), the baseline says why and no verdict is excused by it.
"""
from __future__ import annotations

import json
import os
import platform as pyplatform
import re
import shutil
import signal
import subprocess
import tempfile
from collections import Counter
from pathlib import Path
from typing import Any

from hil.io.rundir import atomic_write_text
from hil.util.processes import spawn

#: the baseline's histogram, in cyclictest's format, in the run directory
HIST_NAME = "platform_latency.hist"
#: cyclictest stops at its next wake-up after SIGINT, then writes its results
STOP_TIMEOUT_S = 10.0
#: the histogram's range is one period (a wake-up later than that is a whole missed period:
#: an overflow, counted; the maximum is exact anyway), at most this many 1-us buckets
HIST_MAX_US = 300_000


def _read(path: str) -> str | None:
    try:
        return Path(path).read_text(encoding="utf-8", errors="replace").strip()
    except OSError:
        return None


def preempt_model(version: str, realtime_flag: str | None) -> str:
    """The kernel's preemption model from `uname -v` (its build string) and
    /sys/kernel/realtime (1 on a PREEMPT_RT kernel)."""
    if realtime_flag == "1" or "PREEMPT_RT" in version:
        return "PREEMPT_RT"
    for model in ("PREEMPT_DYNAMIC", "PREEMPT"):
        if re.search(rf"\b{model}\b", version):
            return model
    return "none (voluntary or server)"


def _uml_host() -> str | None:
    """A User-Mode Linux guest names its host kernel in /proc/cpuinfo (`host : Linux ...`)."""
    text = _read("/proc/cpuinfo") or ""
    if "User Mode Linux" not in text and "model name\t: UML" not in text:
        return None
    m = re.search(r"^host\s*:\s*(.*)$", text, re.M)
    return m[1].strip() if m else ""


def facts() -> dict[str, Any]:
    """What the kernel is: release, build string, preemption model, UML or native (and the
    UML host's kernel), the CPU frequency governors, the isolated CPUs, the load average
    (of the guest, in UML: the host's is not visible from it), the CPUs."""
    uname = os.uname()
    host = _uml_host()
    governors = sorted({g for g in (_read(str(p)) for p in
                                    Path("/sys/devices/system/cpu").glob("cpu[0-9]*/cpufreq/scaling_governor"))
                        if g})
    try:
        load = [round(x, 2) for x in os.getloadavg()]
    except OSError:
        load = []
    return {"kernel": uname.release, "kernel_version": uname.version,
            "preempt": preempt_model(uname.version, _read("/sys/kernel/realtime")),
            "uml": host is not None, "uml_host": host, "machine": pyplatform.machine(),
            "cpus": os.cpu_count(), "cpu_governor": ",".join(governors) or None,
            "isolated_cpus": _read("/sys/devices/system/cpu/isolated") or "",
            "load_average": load}


def percentile(hist: Counter[int], overflow: int, max_us: int, q: float) -> int | None:
    """The q-quantile (us) of a 1-us histogram whose overflows lie above its range (counted
    at the measured maximum: an upper bound)."""
    n = sum(hist.values()) + overflow
    if n == 0:
        return None
    rank = max(1, int(-(-q * n // 1)))   # ceil(q n): the nearest-rank quantile
    seen = 0
    for us in sorted(hist):
        seen += hist[us]
        if seen >= rank:
            return us
    return max_us


class Baseline:
    """cyclictest beside the flights of a session: start() before a flight, stop() after it;
    the histograms of all of them add up (summary(), write_hist())."""

    def __init__(self, period_s: float, priority: int) -> None:
        self.interval_us = max(100, int(round(period_s * 1e6)))
        self.priority = priority
        self.hist_us = min(self.interval_us, HIST_MAX_US)
        self.hist: Counter[int] = Counter()
        self.cycles = self.overflow = 0
        self.min_us: int | None = None
        self.max_us = 0
        self.sum_us = 0.0
        self.error = ""
        self._proc: subprocess.Popen | None = None
        self._dir: str | None = None

    def start(self, loops: int | None = None) -> None:
        """Measure from now until stop(), or for `loops` wake-ups (wait() for them)."""
        self.collect()   # the previous flight's, if not read yet
        exe = shutil.which("cyclictest")
        if exe is None:
            self.error = "cyclictest not found: install rt-tests (scripts/setup does)"
            return
        self._dir = tempfile.mkdtemp(prefix="hil-cyclictest-")
        args = [exe, "-q", "-m", "--default-system", "-t", "1", "-p", str(self.priority),
                "-i", str(self.interval_us), "-h", str(self.hist_us),
                f"--json={self._dir}/result.json"] + (["-l", str(loops)] if loops else [])
        with open(f"{self._dir}/stderr", "wb") as err:
            self._proc = spawn(args, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err)

    def stop(self) -> None:
        """End the measurement now (SIGINT: cyclictest writes its results at its next wake-up,
        up to a period later); collect() waits for them.  Not waiting here: the flight's end
        (fcc's GROUND) must not wait for the measurement (measured: it did, and fcc flew two
        more steps on stale data)."""
        if self._proc is not None and self._proc.poll() is None:
            self._proc.send_signal(signal.SIGINT)

    def wait(self, timeout_s: float) -> bool:
        """Until a measurement of start(loops=N) has had its N wake-ups (cyclictest exits), at
        most timeout_s; False when it has not by then."""
        if self._proc is None:
            return True
        try:
            self._proc.wait(timeout_s)
        except subprocess.TimeoutExpired:
            return False
        return True

    def collect(self) -> None:
        """Wait for a stopped measurement and add its results up."""
        proc, tmp = self._proc, self._dir
        self._proc = self._dir = None
        if proc is None or tmp is None:
            return
        try:
            if proc.poll() is None:
                proc.send_signal(signal.SIGINT)
            try:
                proc.wait(STOP_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
                self.error = f"cyclictest did not stop within {STOP_TIMEOUT_S:g} s"
                return
            self._add(tmp, proc.returncode)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)

    def _add(self, tmp: str, rc: int) -> None:
        try:
            doc = json.loads(Path(tmp, "result.json").read_text(encoding="utf-8"))
            th = doc["thread"]["0"]
            hist = Counter({int(k): int(v) for k, v in th.get("histogram", {}).items()})
            cycles, lo, hi, avg = int(th["cycles"]), int(th["min"]), int(th["max"]), float(th["avg"])
        except (OSError, ValueError, KeyError, TypeError):
            lines = [ln for ln in (_read(f"{tmp}/stderr") or "").splitlines()
                     if ln.strip() and "shm_open" not in ln and "cpu_dma_latency" not in ln]
            self.error = f"cyclictest (exit {rc}): {lines[-1] if lines else 'no results'}"
            return
        if cycles == 0:
            return
        self.hist.update(hist)
        self.overflow += max(0, cycles - sum(hist.values()))
        self.cycles += cycles
        self.min_us = lo if self.min_us is None else min(self.min_us, lo)
        self.max_us = max(self.max_us, hi)
        self.sum_us += avg * cycles

    def summary(self) -> dict[str, Any]:
        """run_info.json's platform.baseline: wake-up latency percentiles (us) and the
        histogram ({us: count}; overflows above hist_range_us), or the error."""
        self.collect()
        if not self.cycles:
            return {"tool": "cyclictest", "error": self.error or "no measurement (no flight)"}
        pct = {f"{name}_us": percentile(self.hist, self.overflow, self.max_us, q)
               for name, q in (("p50", 0.5), ("p99", 0.99))}
        return {"tool": "cyclictest", "interval_us": self.interval_us, "priority": self.priority,
                "policy": "fifo", "cycles": self.cycles, "min_us": self.min_us,
                **pct, "max_us": self.max_us, "avg_us": round(self.sum_us / self.cycles, 1),
                "hist_range_us": self.hist_us, "overflows": self.overflow,
                "histogram": {str(k): self.hist[k] for k in sorted(self.hist)},
                "histogram_file": HIST_NAME, **({"error": self.error} if self.error else {})}

    def write_hist(self, run_dir: Path) -> Path | None:
        """The histogram in cyclictest's format (--histfile), its zero rows left out."""
        self.collect()
        if not self.cycles:
            return None
        rows = [f"{us:06d} {self.hist[us]:06d}" for us in sorted(self.hist)]
        avg = int(round(self.sum_us / self.cycles))
        text = "\n".join(["# Histogram", *rows, f"# Total: {sum(self.hist.values()):09d}",
                          f"# Min Latencies: {self.min_us or 0:05d}", f"# Avg Latencies: {avg:05d}",
                          f"# Max Latencies: {self.max_us:05d}",
                          f"# Histogram Overflows: {self.overflow:05d}"]) + "\n"
        return atomic_write_text(Path(run_dir) / HIST_NAME, text)
