"""summary.json's `bus` section on a real bus: `hil run --target external --bus wire` (a board
on can0).  No model runs: the bus is a wire already.  What the rig can measure there is judged
against the bound of hil.bus.wcrt at the bus's bit rate (--bitrate, else the DBC's Baudrate)
and the scenario's periods, as a `--bus wire` run over canbus is (hil.results.busstats).

A response time is from a frame's being queued at its sender to its end of frame.  On a real
bus the rig knows both ends for the simulator's frames only:

* queued: the simulator's transmitter notes when it hands each frame to its socket
  (hil.rig.txsched --send-log, CLOCK_REALTIME);
* end of frame: the recorder's receive stamp (SO_TIMESTAMP, the same clock): a SocketCAN
  controller with IFF_ECHO hands a sent frame back to the host's other sockets when its
  transmission is confirmed, at the end of frame, plus the interrupt's latency.

Frame k of an identifier sent is frame k of it recorded (one sender, CAN keeps its order); an
identifier whose counts differ (a recorder that lost frames, a fault flooding it) or whose
stamps would go backwards is reported as not measured, never paired at a guess.  The device's
frames (fcc's: a board's) are queued inside the device: their queue time is not on the bus, so
they are counted and given their bound but not measured; what the rig measures of them is their
data age (summary.json realtime.bus.data_age: command − newest sensor frame).
"""
from __future__ import annotations

import csv
from collections import defaultdict
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from hil.bus.candump import LogFrame
from hil.bus.dbc import BusSpec
from hil.bus.wcrt import analyse, utilisation
from hil.results.busstats import flight_frames, judged_frames
from hil.rig.wirebus import FIFO_SENDERS
from hil.scenario.file import Scenario

#: why the device's frames have no measured response time
DEVICE_WHY = ("queued inside the device: its queue time is not on the bus (its data age is: "
              "summary.json realtime.bus.data_age)")
#: why the simulator's other frames (time master, control, pings) have none
OTHER_WHY = "sent outside the simulator's transmitter: its send time is not recorded"


def read_sends(path: Path) -> dict[int, np.ndarray]:
    """The send log: identifier -> its frames' send times (s, CLOCK_REALTIME), in order."""
    out: dict[int, list[int]] = defaultdict(list)
    with open(path, newline="", encoding="ascii") as f:
        for row in csv.DictReader(f):
            out[int(row["can_id"])].append(int(row["t_realtime_ns"]))
    return {i: np.asarray(t, dtype=np.int64) * 1e-9 for i, t in out.items()}


def recorded(frames: Iterable[LogFrame]) -> dict[int, np.ndarray]:
    """The bus log: identifier -> its frames' receive stamps (s), in log order."""
    out: dict[int, list[float]] = defaultdict(list)
    for f in frames:
        if f.classic_data:
            out[f.frame_id].append(f.timestamp)
    return {i: np.asarray(t) for i, t in out.items()}


def response_times(sent: np.ndarray, seen: np.ndarray) -> np.ndarray | str:
    """Frame k recorded minus frame k sent, or why they cannot be paired."""
    if len(sent) != len(seen):
        return f"{len(sent)} sent, {len(seen)} recorded: not paired"
    r = seen - sent
    if len(r) and float(r.min()) < -1e-6:   # the log's stamps have microseconds
        return f"recorded {-float(r.min()) * 1e3:.3f} ms before it was sent: not paired"
    return np.maximum(r, 0.0)


def stats_of(r: np.ndarray) -> dict[str, Any]:
    """canbus's shape of one identifier's response times (percentiles: nearest rank, never
    below the true value)."""
    return {"n": int(len(r)), **{k: float(np.percentile(r, q, method="higher"))
                                 for k, q in (("p50_s", 50), ("p99_s", 99))},
            "max_s": float(r.max())}


def real_bus_section(frames: Iterable[LogFrame], sends: dict[int, np.ndarray], spec: BusSpec,
                     scenarios: Sequence[Scenario], bitrate: int, jitter_s: float = 0.0) -> dict[str, Any]:
    """The section of a real bus: the simulator's frames measured and judged, the others
    counted with their bounds and why they are not measured."""
    seen = recorded(frames)
    ids: dict[str, dict[str, Any]] = {}
    not_measured: dict[str, dict[str, Any]] = {}
    cyclic = flight_frames(spec, scenarios)
    bounds = {r.frame.frame_id: r.wcrt_s for r in analyse(cyclic, bitrate, FIFO_SENDERS)}
    for fid in sorted(set(seen) | set(sends)):
        stamps = seen.get(fid, np.zeros(0))
        m = spec.by_id(fid)
        name = m.name if m is not None else f"0x{fid:03X}"
        r = response_times(sends[fid], stamps) if fid in sends else None
        if isinstance(r, np.ndarray) and len(r):
            ids[f"0x{fid:03X}"] = stats_of(r)
            continue
        why = r if isinstance(r, str) else (
            DEVICE_WHY if m is not None and "FCC" in m.senders else OTHER_WHY)
        bound = bounds.get(fid)
        not_measured[name] = {"id": fid, "n": len(stamps), "wcrt_s": None if bound is None else float(bound),
                              "why": why}
    return {"bitrate": bitrate, "model": "real",
            "utilisation": round(float(utilisation(cyclic, bitrate)), 5), "jitter_s": jitter_s,
            "frames_on_bus": int(sum(len(t) for t in seen.values())),
            "frames": judged_frames(ids, spec, cyclic, bitrate, jitter_s, FIFO_SENDERS),
            "not_measured": not_measured}


__all__ = ["DEVICE_WHY", "OTHER_WHY", "read_sends", "real_bus_section", "recorded", "response_times", "stats_of"]
