"""`hil live`: a dashboard of the bus while a run flies (realtime or lockstep), decoded with
the DBC: the CDRW's measured alpha and q beside each filter's estimate (order, fault flag),
the missile's gyro, estimate and D/A command, fcc's health flags and its E2E counters, the
simulator's active faults, and every message's rate.

On a terminal it redraws in place (rich); otherwise (a log, scripts/with-vcan's relayed
output) it prints one plain block per refresh; --rich forces the redrawing form (with-vcan
relays the escape sequences to your terminal).
"""
from __future__ import annotations

import sys
import time
from collections import defaultdict, deque
from collections.abc import Callable
from typing import Any

from hil.bus.dbc import BusSpec
from hil.bus.protocol import FAULT_KIND_NAMES

#: SIM_EVENT.kind: the fault kind of each code (the DBC's value table, hil.bus.protocol)
KIND_NAMES = FAULT_KIND_NAMES

FILTER_FRAMES = (("AZKF", "SID_AZKF_STATE"), ("ZKF", "SID_ZKF_STATE"), ("KF", "SID_KF_STATE"))
HEALTH = ("cdrw_degraded", "msl_degraded", "sensor_stale", "e2e_fault", "overrun", "config_rejected")
E2E = (("FCC_E2E_COUNTS", ("ok", "repeated", "ok_some_lost", "wrong_sequence")),
       ("FCC_E2E_FAULTS", ("error", "no_new_data", "stale_now")))


class BusView:
    """The latest decoded value of every message, and message rates over the last second."""

    def __init__(self, spec: BusSpec, also: Callable[[int, bytes, float], None] | None = None) -> None:
        """also: every frame goes there too (`hil live --plot`'s chart, hil.rig.liveplot)."""
        self.spec = spec
        self.also = also
        self.values: dict[str, dict[str, Any]] = {}
        self.arrivals: dict[str, deque[float]] = defaultdict(lambda: deque(maxlen=2000))
        self.faults: dict[int, str] = {}
        self.frames = 0

    def add(self, frame_id: int, data: bytes, t: float) -> None:
        msg = self.spec.by_id(frame_id)
        self.frames += 1
        if self.also is not None:
            self.also(frame_id, data, t)
        if msg is None or len(data) != msg.length:
            return
        vals = msg.decode(data)
        self.values[msg.name] = vals
        self.arrivals[msg.name].append(t)
        if msg.name == "SIM_EVENT":
            fid = int(vals["fault_id"])
            if vals["active"]:
                kind = KIND_NAMES.get(int(vals["kind"]), f"kind {int(vals['kind'])}")
                self.faults[fid] = f"#{fid} {kind} on 0x{int(vals['target_id']):03X}"
            else:
                self.faults.pop(fid, None)

    def rate(self, name: str, now: float) -> float:
        return float(sum(1 for t in self.arrivals.get(name, ()) if now - t <= 1.0))

    def get(self, msg: str, sig: str) -> Any:
        return self.values.get(msg, {}).get(sig)

    def lines(self, now: float) -> list[str]:
        def f(v: Any, spec: str = "+.4f") -> str:
            return "-" if v is None else format(v, spec)

        out = [f"CDRW  alpha {f(self.get('CDRW_AOA', 'alpha'))} rad   q {f(self.get('CDRW_PITCH_RATE', 'q'))} rad/s"
               f"   elevator {f(self.get('CDRW_ELEVATOR', 'delta_e'))} rad   ({self.rate('CDRW_AOA', now):.0f} Hz)"]
        for label, frame in FILTER_FRAMES:
            g = lambda s: self.get(frame, s)  # noqa: E731, B023 - used in this iteration only
            out.append(f"  {label:<5} alpha_hat {f(g('alpha_hat'))}  q_hat {f(g('q_hat'))}  order "
                       f"{f(g('order'), 'd')}  fault {f(g('fault'), 'd')}  degraded {f(g('degraded'), 'd')}")
        out.append(f"MSL   q_g {f(self.get('MSL_RATE_GYRO', 'q_g'))} rad/s   q_hat "
                   f"{f(self.get('MSL_STATE_EST', 'q_hat'))}   D/A code {f(self.get('MSL_ELEV_CMD', 'da_code'), 'd')}"
                   f" ({f(self.get('MSL_ELEV_CMD', 'da_bits'), 'd')} bit)   ({self.rate('MSL_ELEV_CMD', now):.0f} Hz)")
        flags = [h for h in HEALTH if self.get("FCC_STATUS", h)]
        out.append(f"FCC   steps cdrw {f(self.get('FCC_STATUS', 'cdrw_steps'), 'd')} missile "
                   f"{f(self.get('FCC_STATUS', 'msl_steps'), 'd')}"
                   f"  overruns {f(self.get('FCC_STATUS', 'overruns'), 'd')}"
                   f"  worst {f(self.get('FCC_STATUS', 'worst_step_us'), 'd')} us  flags: {' '.join(flags) or 'none'}")
        e2e = [f"{s} {f(self.get(m, s), 'd')}" for m, sigs in E2E for s in sigs]
        out.append("E2E   " + "  ".join(e2e))
        out.append(f"SIM   active faults: {', '.join(self.faults.values()) or 'none'}   frames seen {self.frames}")
        return out


def run(iface: str, seconds: float, spec: BusSpec, force_rich: bool = False, refresh_s: float = 0.25,
        recv: Callable[[float], Any] | None = None,
        also: Callable[[int, bytes, float], None] | None = None,
        ready: Callable[[], None] | None = None) -> BusView:
    """Watch the bus for `seconds`; returns the final view (also: as BusView's; ready: called
    once the bus is open, every frame from then on is seen)."""
    import can

    view = BusView(spec, also)
    fancy = force_rich or sys.stdout.isatty()
    with can.Bus(interface="socketcan", channel=iface) as bus:
        if ready is not None:
            ready()
        receive = recv or bus.recv
        end = time.monotonic() + seconds
        if fancy:
            from rich.console import Console
            from rich.live import Live
            from rich.text import Text

            console = Console(force_terminal=True)
            with Live(Text(""), console=console, refresh_per_second=1 / refresh_s) as live:
                _loop(view, receive, end, refresh_s, lambda now: live.update(Text("\n".join(view.lines(now)))))
        else:
            def show(now: float) -> None:
                print("\n".join(view.lines(now)) + "\n", flush=True)
            _loop(view, receive, end, max(refresh_s, 1.0), show)
    return view


def _loop(view: BusView, receive: Callable[[float], Any], end: float, every: float,
          show: Callable[[float], None]) -> None:
    next_show = time.monotonic()
    while (now := time.monotonic()) < end:
        msg = receive(min(0.05, max(0.0, end - now)))
        if msg is not None and not (msg.is_error_frame or msg.is_remote_frame or msg.is_extended_id):
            view.add(msg.arbitration_id, bytes(msg.data), time.monotonic())
        if time.monotonic() >= next_show:
            show(time.monotonic())
            next_show += every
    show(time.monotonic())
