"""scripts/diag: what is on the bus, decoded with the DBC.

    scripts/diag --log FILE [--dbc DBC] [--json]          a log: candump -L (.log), or any
                                                          format python-can reads (.asc .blf .trc ...)
    scripts/diag --iface vcan0 --seconds 5 [--save FILE]  a live interface (python-can)

Per message: count, mean rate, mean period, the period the run used (per flight: the median
of its own inter-arrival times, so a T = 0.2 s missile run is not measured against the
DBC's 100 ms), jitter against that period (RMS and worst), E2E classification counts (OK,
REPEATED, OK_SOME_LOST, WRONG_SEQUENCE, ERROR; NO_NEW_DATA = whole periods in which no frame
arrived, E2E-protected cyclic messages only), wrong-DLC and out-of-range counts.  Flights are
the segments between SIM_CONTROL resets; no period spans two.  Then frames the DBC does not
know, error frames, and the bus load: exact (stuff bits counted from each frame's bit stream)
and worst case (135 bits per 8-byte frame).  --json is strict JSON (null where there is no value).
Exit status: 0; 1 timestamps go backwards in the log (counted, the report still printed,
periods across them left out); 2 bad file or flags, or an interface that cannot be opened
(one line on stderr: what is wrong and what to do, hil.bus.canif).
"""
from __future__ import annotations

import argparse
import json
import logging
import math
import statistics
import sys
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

from hil.bus import busload, candump, canif, dbc, logio
from hil.bus.codec import decode_values
from hil.bus.e2e import E2EReceiver, E2EStatus
from hil.bus.protocol import COMMAND_RESET, SIM_CONTROL_ID

PROG = "diag"
#: messages that carry an application in bits 12-13 (lockstep tick and answer): one stream each
PER_APP = ("SIM_TICK", "FCC_ACK")
APPS = {0: "cdrw", 1: "missile"}


@dataclass
class MessageStats:
    name: str
    frame_id: int
    cycle_ms: int            # 0: an event message (no period, no jitter)
    protected: bool          # E2E: NO_NEW_DATA is counted
    times: list[float] = field(default_factory=list)
    flights: list[int] = field(default_factory=list)   # flight (reset segment) of each frame
    e2e: dict[str, int] = field(default_factory=lambda: {s.name: 0 for s in E2EStatus})
    wrong_dlc: int = 0
    out_of_range: int = 0

    def _periods(self) -> dict[int, list[float]]:
        """Inter-arrival times inside each flight (never across a reset, never backwards)."""
        per: dict[int, list[float]] = {}
        for (a, fa), (b, fb) in zip(zip(self.times, self.flights), zip(self.times[1:], self.flights[1:])):
            if fa == fb and b >= a:
                per.setdefault(fb, []).append(b - a)
        return per

    def summary(self) -> dict[str, object]:
        per = self._periods()
        periods = [p for ps in per.values() for p in ps]
        # the period each flight actually used: the median of its own periods (robust to lost
        # and repeated frames), the DBC's cycle time only when a flight has too few frames
        cycle = self.cycle_ms / 1000.0
        used = {f: statistics.median(ps) if len(ps) >= 2 else cycle for f, ps in per.items()}
        dev = [p - used[f] for f, ps in per.items() for p in ps] if self.cycle_ms else []
        mean = statistics.fmean(periods) if periods else math.nan
        std = math.sqrt(statistics.fmean([d * d for d in dev])) if len(dev) > 1 else math.nan
        worst = max((abs(d) for d in dev), default=math.nan)
        span = sum(sum(ps) for ps in per.values())
        rate = len(periods) / span if span > 0 else math.nan
        if self.cycle_ms and self.protected:
            self.e2e["NO_NEW_DATA"] = sum(max(0, round(p / used[f]) - 1)
                                          for f, ps in per.items() for p in ps if used[f] > 0)
        steps = sorted({round(v * 1e3, 3) for v in used.values() if v > 0}) if self.cycle_ms else []
        return {"name": self.name, "id": f"0x{self.frame_id:03X}", "count": len(self.times),
                "rate_hz": rate, "expected_hz": 1000.0 / self.cycle_ms if self.cycle_ms else None,
                "used_period_ms": steps, "period_ms": mean * 1e3, "jitter_std_ms": std * 1e3,
                "jitter_max_ms": worst * 1e3, "e2e": dict(self.e2e), "wrong_dlc": self.wrong_dlc,
                "out_of_range": self.out_of_range}


@dataclass
class BusStats:
    spec: dbc.BusSpec
    messages: dict[int, MessageStats] = field(default_factory=dict)
    receivers: dict[int, E2EReceiver] = field(default_factory=dict)
    unknown: dict[str, int] = field(default_factory=dict)
    error_frames: int = 0
    frames: int = 0
    bits_exact: int = 0
    bits_worst: int = 0
    first: float | None = None
    last: float | None = None
    flight: int = 0                  # SIM_CONTROL resets seen (the rig starts every flight with one)
    backwards: int = 0               # frames stamped earlier than the frame before them
    first_backwards: str = ""

    def add(self, f: candump.LogFrame) -> None:
        self.frames += 1
        if self.last is not None and f.timestamp < self.last:
            self.backwards += 1
            if not self.first_backwards:
                self.first_backwards = (f"frame {self.frames}: {f.timestamp:.6f} after "
                                        f"{self.last:.6f}")
        self.first = f.timestamp if self.first is None else min(self.first, f.timestamp)
        self.last = f.timestamp if self.last is None else max(self.last, f.timestamp)
        if f.error:
            self.error_frames += 1
            return
        if not f.fd:
            self.bits_exact += busload.frame_bits(f.frame_id, f.data, f.extended, f.remote)
            self.bits_worst += busload.worst_case_bits(len(f.data), f.extended)
        msg = None if (f.extended or f.fd or f.remote) else self.spec.by_id(f.frame_id)
        if msg is None:
            ident = f"{f.frame_id:08X}" if f.extended else f"{f.frame_id:03X}"
            self.unknown[ident] = self.unknown.get(ident, 0) + 1
            return
        if f.frame_id == SIM_CONTROL_ID and len(f.data) == 8 and (f.data[1] >> 4) == COMMAND_RESET:
            self.flight += 1
        key, name = msg.frame_id, msg.name
        if msg.name in PER_APP and len(f.data) == msg.length:  # one stream per application
            app = (f.data[1] >> 4) & 0x3
            key, name = msg.frame_id * 4 + app, f"{msg.name}[{APPS.get(app, app)}]"
        st = self.messages.setdefault(key, MessageStats(name, msg.frame_id, msg.cycle_ms, msg.protected))
        st.times.append(f.timestamp)
        st.flights.append(self.flight)
        if len(f.data) != msg.length:
            st.wrong_dlc += 1
            return
        if msg.protected:
            rx = self.receivers.setdefault(msg.frame_id,
                                           E2EReceiver(msg.data_id, msg.max_delta_counter))
            status = rx.check(f.data)
            st.e2e[status.name] += 1
            if not status.data_usable:
                return
        if decode_values(msg, f.data) is None:
            st.out_of_range += 1

    def report(self) -> dict[str, object]:
        duration = (self.last - self.first) if self.first is not None and self.last is not None else 0.0
        per = [m.summary() for m in sorted(self.messages.values(), key=lambda m: (m.frame_id, m.name))]
        span = duration if duration > 0 else math.nan
        return {"frames": self.frames, "duration_s": duration, "messages": per,
                "unknown_ids": dict(sorted(self.unknown.items())),
                "error_frames": self.error_frames, "timestamps_backwards": self.backwards,
                "first_backwards": self.first_backwards or None, "baudrate": self.spec.baudrate,
                "load_exact_pct": busload.load_percent(self.bits_exact / span, self.spec.baudrate),
                "load_worst_pct": busload.load_percent(self.bits_worst / span, self.spec.baudrate)}


def strict_json(x: object) -> object:
    """The report with every NaN/inf as null (JSON has no NaN)."""
    if isinstance(x, float):
        return x if math.isfinite(x) else None
    if isinstance(x, dict):
        return {k: strict_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [strict_json(v) for v in x]
    return x


def _fmt(x: object, spec: str) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return format(x, spec)


def render(rep: dict[str, Any]) -> str:
    e2e_cols = ("OK", "REPEATED", "OK_SOME_LOST", "WRONG_SEQUENCE", "ERROR", "NO_NEW_DATA")
    short = ("ok", "rep", "lost", "wseq", "err", "nnd")
    # (a space before each time column: a wall-clock heartbeat's period runs to 4 digits)
    head = (f"{'message':<20}{'id':>6}{'count':>8}{'Hz':>9}{'exp':>6} {'T ms':>9}"
            f" {'jit ms':>8} {'max ms':>8} " + "".join(f"{s:>6}" for s in short) + f"{'dlc':>5}{'rng':>5}")
    lines = [head, "-" * len(head)]
    for m in rep["messages"]:
        e2e = m["e2e"]
        lines.append(
            f"{m['name']:<20}{m['id']:>6}{m['count']:>8}{_fmt(m['rate_hz'], '.2f'):>9}"
            f"{_fmt(m['expected_hz'], '.0f'):>6} {_fmt(m['period_ms'], '.3f'):>9}"
            f" {_fmt(m['jitter_std_ms'], '.3f'):>8} {_fmt(m['jitter_max_ms'], '.3f'):>8} "
            + "".join(f"{e2e[c]:>6}" for c in e2e_cols) + f"{m['wrong_dlc']:>5}{m['out_of_range']:>5}")
    unknown = rep["unknown_ids"]
    lines.append("-" * len(head))
    lines.append(f"frames {rep['frames']} in {rep['duration_s']:.3f} s; unknown ids "
                 + (", ".join(f"{k}×{v}" for k, v in unknown.items()) or "none")
                 + f"; error frames {rep['error_frames']}")
    if rep.get("timestamps_backwards"):
        lines.append(f"timestamps going backwards: {rep['timestamps_backwards']} (first at "
                     f"{rep['first_backwards']}); periods across them are left out")
    lines.append(f"bus load at {rep['baudrate'] // 1000} kbit/s: {_fmt(rep['load_exact_pct'], '.2f')} % "
                 f"(exact stuffing), {_fmt(rep['load_worst_pct'], '.2f')} % (worst-case stuffing)")
    return "\n".join(lines)


def capture(iface: str, seconds: float, interface: str = "socketcan") -> list[candump.LogFrame]:
    import can  # only the live mode needs python-can

    logging.getLogger("can").addHandler(logging.NullHandler())  # its errors: one line of ours
    frames: list[candump.LogFrame] = []
    try:
        canif.check_up(iface)
        bus = can.Bus(interface=interface, channel=iface)
    except (OSError, can.CanError) as e:
        raise _Fail(canif.open_error(iface, e)) from None
    with bus:
        print(f"{PROG}: capturing {iface} for {seconds:g} s", file=sys.stderr, flush=True)
        end = time.monotonic() + seconds
        while (left := end - time.monotonic()) > 0:
            msg = bus.recv(timeout=min(left, 0.2))
            if msg is None:
                continue
            frames.append(candump.LogFrame(msg.timestamp, iface, msg.arbitration_id,
                                           bytes(msg.data), msg.is_extended_id,
                                           msg.is_remote_frame, msg.is_error_frame, msg.is_fd))
    return frames


def analyse(frames: Iterable[candump.LogFrame], spec: dbc.BusSpec) -> dict[str, object]:
    stats = BusStats(spec)
    for f in frames:
        stats.add(f)
    return stats.report()


class _Fail(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # one line, not the usage block
        raise _Fail(message)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog=PROG, description="Decode a CAN log or a live "
                                "interface with the DBC: rates, jitter, E2E classes, bus load.")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--log", type=Path, help="log file: candump -L (.log) or any format python-can "
                     "reads (.asc, .blf, .trc, .csv, ...)")
    src.add_argument("--iface", help="live SocketCAN interface, e.g. vcan0")
    p.add_argument("--seconds", type=float, default=5.0, help="capture time with --iface")
    p.add_argument("--save", type=Path, help="with --iface: also write the capture (format by suffix: "
                   ".log candump -L, .asc, .blf, ...)")
    p.add_argument("--dbc", type=Path, default=None, help="the DBC (default $FCC_HIL_DBC, else hil's)")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    return p


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    try:
        args = parser.parse_args(argv)
        if args.seconds <= 0 or not math.isfinite(args.seconds):
            raise _Fail(f"--seconds must be positive, not {args.seconds}")
        spec = dbc.load(args.dbc)
        if args.log is not None:
            if not args.log.is_file():
                raise _Fail(f"cannot read log {args.log}: no such file")
            frames = _read(args.log)
        else:
            frames = capture(args.iface, args.seconds)
            if args.save is not None:
                logio.write_frames(args.save, frames)
        rep = analyse(frames, spec)
    except _Fail as exc:
        print(f"{PROG}: {exc}", file=sys.stderr)
        return 2
    except candump.LogFormatError as exc:
        print(f"{PROG}: {args.log}: {exc}", file=sys.stderr)
        return 2
    except (OSError, ValueError) as exc:
        print(f"{PROG}: {exc}".splitlines()[0], file=sys.stderr)
        return 2
    print(json.dumps(strict_json(rep), indent=1, allow_nan=False) if args.json else render(rep))
    if rep["timestamps_backwards"]:
        print(f"{PROG}: {args.log or args.iface}: {rep['timestamps_backwards']} timestamps go backwards "
              f"(first at {rep['first_backwards']})", file=sys.stderr)
        return 1
    return 0


def _read(path: Path) -> list[candump.LogFrame]:
    """Every frame of a log file, any format; unreadable content is one _Fail line."""
    try:
        return list(logio.read_frames(path))
    except candump.LogFormatError:
        raise
    except Exception as e:  # noqa: BLE001 - python-can's readers raise many kinds on bad files
        raise _Fail(f"{path}: cannot read as a {path.suffix or 'suffix-less'} log: "
                    f"{str(e).splitlines()[0] if str(e) else type(e).__name__}") from None


if __name__ == "__main__":
    sys.exit(main())
