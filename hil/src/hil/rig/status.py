"""fcc's heartbeat: the frames it is made of and its counters, unwrapped across the DBC's 16-bit
(or 8-bit) fields (StatusCounters: the session keeps them, the results report them).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from hil.bus.dbc import BusSpec

STATUS_FRAMES = ("FCC_STATUS", "FCC_E2E_COUNTS", "FCC_E2E_FAULTS", "FCC_REJECT_COUNTS",
                 "FCC_BUS_COUNTS", "FCC_SEC_COUNTS", "FCC_SEC_SESSION", "FCC_SYNC_STATUS",
                 "FCC_SYNC_REFUSALS")
#: heartbeat signals that are states or gauges, not wrapping counters
GAUGES = ("mode", "op_mode", "stale_now", "worst_step_us", "trip", "state", "master", "offset_us",
          "rate_ppm")


@dataclass
class StatusCounters:
    """fcc's heartbeat counters, unwrapped across the 16-bit (or 8-bit) fields of the DBC
    (the heartbeat comes often enough that no counter moves by a whole wrap in between)."""

    values: dict[str, int | float] = field(default_factory=dict)  # a scaled gauge is a float
    _last_raw: dict[str, int] = field(default_factory=dict)
    last: dict[str, dict[str, int | float]] = field(default_factory=dict)
    heartbeats: int = 0

    @classmethod
    def from_frames(cls, spec: BusSpec, frames: list[tuple[int, bytes]]) -> StatusCounters:
        sc = cls()
        for frame_id, data in frames:
            sc.update(spec, frame_id, data)
        return sc

    def update(self, spec: BusSpec, frame_id: int, data: bytes) -> None:
        msg = spec.by_id(frame_id)
        if msg is None or msg.name not in STATUS_FRAMES or len(data) != 8:
            return
        vals = msg.decode(data)
        self.last[msg.name] = dict(vals)
        if msg.name == "FCC_STATUS":
            self.heartbeats += 1
        for sig in msg.signals:
            key = f"{msg.name}.{sig.name}"
            if sig.length == 1 or sig.name in GAUGES:
                self.values[key] = vals[sig.name]  # flags and gauges: not counters
                continue
            raw = int(vals[sig.name])
            prev = self._last_raw.get(key)
            mod = 1 << sig.length
            self.values[key] = self.values.get(key, 0) + (raw if prev is None else (raw - prev) % mod)
            self._last_raw[key] = raw

    def get(self, name: str, default: int = 0) -> int | float:
        return self.values.get(name, default)
