"""Real-time timing of a run: step-start jitter, data age at use and sync offset, measured by
one observer (candump's kernel stamps in bus.log) and by fcc itself (its exit summary).

From bus.log, with the time master's SYNC/FOLLOW_UP pairs mapping candump's clock to master
time (median offset over the run):

* step-start jitter of the simulator: each missile sensor frame's master time minus its
  sampling instant (the nearest multiple of T: the simulator's sampling instants are on the
  master grid);
* command delay: each MSL_ELEV_CMD's master time minus the sampling instant it belongs to
  (the last one before it): fcc's computation + transport, what the LQG's delay covers;
* data age at use: each command's time minus the newest missile sensor frame before it;
* sync offset: FCC_SYNC_STATUS.offset_us (fcc's last residual), every heartbeat.

Given the run's key (``BusAuth``), only authentic frames are measured, each at its own kernel
stamp (hil.results.buslog.authentic_frames): the master's SYNC/FOLLOW_UP once TSYNC_AUTH
verified them, MSL_ELEV_CMD once MSL_ELEV_CMD_AUTH did, FCC_SYNC_STATUS once its heartbeat's
FCC_STATUS_AUTH did.  A forged status or command changes no figure.

realtime_timing.csv holds every sample (columns ``what``, ``us``), for the histograms
(hil.plots.realtime); ``summarise`` gives the percentiles written into summary.json and
run_info.json, with fcc's own histograms (``fcc summary: ...`` lines of fcc.log).
"""
from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hil.bus.candump import read_log
from hil.bus.dbc import BusSpec
from hil.results.buslog import BusAuth, authentic_frames

SYNC_ID, FOLLOW_UP_ID, SYNC_STATUS_ID = 0x001, 0x002, 0x705
GYRO_ID, ACCEL_ID, CMD_ID = 0x040, 0x041, 0x030
KINDS = ("sim_jitter", "cmd_delay", "data_age", "sync_offset")
CSV_NAME = "realtime_timing.csv"
#: FCC_SYNC_STATUS.state of a locked time sync (firmware/timesync/fcc_tsync.h FCC_TSYNC_LOCKED):
#: the residual percentiles are over these heartbeats only; a LOCKING servo's residuals are its
#: acquisition (measured on the M4F image: 170-314 us for 3-5 heartbeats, then within 25 us)
LOCKED = 2
_FCC_HIST = re.compile(r"^fcc summary: (\w+) (\w+) n=(\d+) p50=(\d+) p99=(\d+) max=(\d+)$")
#: a device behind a serial link (the M4F image) says what its line cost: each frame's way over
#: it beyond the fastest delivery (bus_delay_us_*), a line's time on it (line_us_*)
_FCC_LINK = re.compile(r"^fcc summary: rx_timing ((?:\w+=\d+ ?)+)$")


def bus_timing(log: Path, spec: BusSpec, period: float, auth: BusAuth | None = None) -> dict[str, np.ndarray]:
    """Per-sample timing (us) of the missile at `period` from a bus log (see module doc); auth:
    only the frames that verify under it (None: every frame)."""
    sync = spec.by_name("TSYNC_SYNC")
    fup = spec.by_name("TSYNC_FOLLOW_UP")
    status = spec.by_name("FCC_SYNC_STATUS")
    sync_t: dict[int, tuple[float, int]] = {}
    offsets: list[float] = []
    sensors: list[float] = []
    cmds: list[tuple[float, float]] = []   # (time, newest sensor time before it)
    sync_offset: list[float] = []
    last_sensor = None
    frames = read_log(log) if auth is None else authentic_frames(read_log(log), auth, own_time=True)
    for f in frames:
        if f.frame_id == SYNC_ID and len(f.data) == 8:
            v = sync.decode(f.data)
            sync_t[int(v["seq"])] = (f.timestamp, int(v["sec"]))
        elif f.frame_id == FOLLOW_UP_ID and len(f.data) == 8:
            v = fup.decode(f.data)
            got = sync_t.pop(int(v["seq"]), None)
            if got is not None:
                master = (got[1] + int(v["sec_carry"])) * 1e6 + int(v["ns"]) / 1e3
                offsets.append(master - got[0] * 1e6)
        elif f.frame_id in (GYRO_ID, ACCEL_ID):
            sensors.append(f.timestamp)
            last_sensor = f.timestamp
        elif f.frame_id == CMD_ID and last_sensor is not None:
            cmds.append((f.timestamp, last_sensor))
        elif f.frame_id == SYNC_STATUS_ID and len(f.data) == 8:
            v = status.decode(f.data)
            if int(v["state"]) == LOCKED:   # acquisition is TS-LOCK-1's, not the residual's
                sync_offset.append(float(v["offset_us"]))
    out = {k: np.empty(0) for k in KINDS}
    out["sync_offset"] = np.asarray(sync_offset)
    if cmds:
        out["data_age"] = np.array([(c - s) * 1e6 for c, s in cmds])
    if not offsets:
        return out
    off = float(np.median(offsets))
    p_us = period * 1e6
    m_sens = np.asarray(sensors) * 1e6 + off
    out["sim_jitter"] = m_sens - np.round(m_sens / p_us) * p_us
    m_cmd = np.array([c for c, _ in cmds]) * 1e6 + off
    out["cmd_delay"] = m_cmd - np.floor(m_cmd / p_us) * p_us
    return out


def fcc_histograms(text: str) -> dict[str, dict[str, int]]:
    """fcc's own histograms from its exit summary: {"latency_us missile": {n, p50, p99, max}}."""
    out = {}
    for line in text.splitlines():
        m = _FCC_HIST.match(line.strip())
        if m:
            out[f"{m[1]} {m[2]}"] = {"n": int(m[3]), "p50": int(m[4]), "p99": int(m[5]), "max": int(m[6])}
    return out


def link_timing(text: str) -> dict[str, int]:
    """The device's link from its exit summary (`rx_timing`: {bus_delay_us_worst, line_us_mean,
    ...}); {} for a device on the bus itself (the host fcc)."""
    for line in text.splitlines():
        m = _FCC_LINK.match(line.strip())
        if m:
            return {k: int(v) for k, v in (kv.split("=") for kv in m[1].split())}
    return {}


def _pct(x: np.ndarray) -> dict[str, float | int | None]:
    if x.size == 0:
        return {"n": 0, "p50": None, "p99": None, "max": None}
    a = np.abs(x) if x.min() < 0 else x
    return {"n": int(x.size), "p50": float(np.percentile(a, 50)), "p99": float(np.percentile(a, 99)),
            "max": float(a.max())}


def summarise(timing: dict[str, np.ndarray], fcc_log_text: str) -> dict[str, Any]:
    """Percentiles (us; of |x| for signed quantities) from the bus, and fcc's own."""
    fcc: dict[str, Any] = fcc_histograms(fcc_log_text)
    link = link_timing(fcc_log_text)
    return {"bus": {k: _pct(v) for k, v in timing.items()},
            "fcc": {k: fcc[k] for k in ("jitter_us missile", "latency_us missile", "delay_us missile",
                                        "sync_offset_us abs") if k in fcc} | ({"link": link} if link else {})}


def write_csv(path: Path, timing: dict[str, np.ndarray]) -> None:
    lines = ["what,us"] + [f"{k},{v:.1f}" for k in KINDS for v in timing.get(k, ())]
    path.write_text("\n".join(lines) + "\n")


def read_csv(path: Path) -> dict[str, np.ndarray]:
    rows: dict[str, list[float]] = {k: [] for k in KINDS}
    for line in path.read_text().splitlines()[1:]:
        what, _, us = line.partition(",")
        rows.setdefault(what, []).append(float(us))
    return {k: np.asarray(v) for k, v in rows.items()}


__all__: Sequence[str] = ("bus_timing", "fcc_histograms", "link_timing", "summarise", "write_csv", "read_csv")
