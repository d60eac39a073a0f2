"""`hil live --plot`: chosen signals of the bus as a chart in the browser, streaming.

A small web page served on 127.0.0.1 only (the standard library's http.server, one thread),
not a matplotlib window: the rig runs headless (a lab server, the UML guest of
scripts/with-vcan: no display to open a window on), a page is watched from any browser that
reaches the machine (through an SSH tunnel to its 127.0.0.1), and it is tested as a user sees it,
in headless Chromium.  Everything is inline (the page's script draws on a canvas): nothing is
fetched but the page's own data, no CDN.

    GET /              the page: it asks for /data every 250 ms and draws the last WINDOW_S
    GET /data?since=N  {"signals": [...], "seq": M, "points": {signal: [[t, value], ...]},
                       "faults": [[start, end, what], ...]}: the points after sequence number N
                       (t: s since the first frame), and every fault window the simulator's
                       SIM_EVENT frames told (end null: still active), shaded on the chart

The page's canvas carries the number of points it drew in ``data-points`` and of fault
windows it shaded in ``data-faults`` (what the test reads).  A request whose Host is not this
server's own address is refused (403): a web page of another site cannot read the bus through a
DNS name rebound to 127.0.0.1.
"""
from __future__ import annotations

import json
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, urlparse

from hil.bus.candump import LogFrame, parse_line
from hil.bus.dbc import BusSpec
from hil.rig.live import KIND_NAMES

#: what the chart shows unless told: the missile's measured pitch rate and fcc's estimate of
#: it, the CDRW's measured angle of attack and the AZKF's estimate
DEFAULT_SIGNALS = ("MSL_RATE_GYRO.q_g", "MSL_STATE_EST.q_hat", "CDRW_AOA.alpha", "SID_AZKF_STATE.alpha_hat")
#: points kept per signal (the page shows the last WINDOW_S seconds)
MAX_POINTS = 20_000
WINDOW_S = 20.0


def resolve(spec: BusSpec, names: Iterable[str]) -> list[tuple[str, int, str]]:
    """(label, frame id, signal) of each name: MESSAGE.signal, or a signal name only one
    message has (ValueError names what is wrong)."""
    out = []
    for name in names:
        msg_name, dot, sig = name.rpartition(".")
        if dot:
            try:
                msg = spec.by_name(msg_name)
            except KeyError:
                raise ValueError(f"--signals: no message {msg_name!r} in the DBC") from None
            if sig not in {s.name for s in msg.data_signals}:
                raise ValueError(f"--signals: {msg_name} has no signal {sig!r} "
                                 f"(it has {', '.join(s.name for s in msg.data_signals)})")
            out.append((name, msg.frame_id, sig))
            continue
        having = [m for m in spec.messages if sig in {s.name for s in m.data_signals}]
        if len(having) != 1:
            why = "no message has it" if not having else \
                f"{', '.join(m.name for m in having)} have it: name one as MESSAGE.{sig}"
            raise ValueError(f"--signals: signal {sig!r}: {why}")
        out.append((f"{having[0].name}.{sig}", having[0].frame_id, sig))
    return out


class Chart:
    """The chosen signals' points, decoded from frames as they come (any thread)."""

    def __init__(self, spec: BusSpec, names: Sequence[str]) -> None:
        self.spec = spec
        self.signals = resolve(spec, names)
        self._by_id: dict[int, list[tuple[str, str]]] = {}
        for label, fid, sig in self.signals:
            self._by_id.setdefault(fid, []).append((label, sig))
        self._points: dict[str, deque[tuple[int, float, float]]] = {
            label: deque(maxlen=MAX_POINTS) for label, _, _ in self.signals}
        self._lock = threading.Lock()
        self._seq = 0
        self._t0: float | None = None
        self._event_id = spec.by_name("SIM_EVENT").frame_id
        #: the simulator's fault windows as its SIM_EVENT frames tell them: [start, end or
        #: None, "kind on 0xID"], open ones by fault id
        self.faults: list[list[Any]] = []
        self._open: dict[int, list[Any]] = {}

    def add(self, frame_id: int, data: bytes, t: float) -> None:
        wanted = self._by_id.get(frame_id)
        if not wanted and frame_id != self._event_id:
            return
        msg = self.spec.by_id(frame_id)
        if msg is None or len(data) != msg.length:
            return
        vals = msg.decode(data)
        with self._lock:
            if self._t0 is None:
                self._t0 = t
            if frame_id == self._event_id:
                self._event(vals, t - self._t0)
                return
            for label, sig in wanted or ():
                self._seq += 1
                self._points[label].append((self._seq, t - self._t0, float(vals[sig])))

    def _event(self, vals: dict[str, Any], t: float) -> None:
        fid = int(vals["fault_id"])
        if vals["active"] and fid not in self._open:
            kind = KIND_NAMES.get(int(vals["kind"]), f"kind {int(vals['kind'])}")
            window = [round(t, 6), None, f"{kind} on 0x{int(vals['target_id']):03X}"]
            self.faults.append(window)
            self._open[fid] = window
        elif not vals["active"] and fid in self._open:
            self._open.pop(fid)[1] = round(t, 6)
        self._seq += 1   # the page asks again for what changed

    def load(self, frames: Iterable[LogFrame]) -> None:
        """A recorded bus log's frames, at their own times."""
        for fr in frames:
            if fr.classic_data:
                self.add(fr.frame_id, fr.data, fr.timestamp)

    def since(self, seq: int) -> dict[str, Any]:
        with self._lock:
            points = {label: [[round(t, 6), v] for s, t, v in pts if s > seq]
                      for label, pts in self._points.items()}
            return {"signals": [label for label, _, _ in self.signals], "seq": self._seq, "points": points,
                    "faults": [list(w) for w in self.faults]}


def growing_log(out: Path) -> Path | None:
    """The recorder's log of the run flying into --out, as it grows (hil.rig.recorder: in a
    private directory of the run's staging directory, hil.io.rundir), or None."""
    out = Path(out)
    logs = sorted(out.parent.glob(f".{out.name}.partial-*/.*-*/*.log"), key=lambda p: p.stat().st_mtime)
    return logs[-1] if logs else None


def follow(find: Callable[[], Path | None], chart: Chart, until: float, poll_s: float = 0.1) -> None:
    """Every frame appended to a growing candump log, as it comes, until `until` (monotonic):
    the log found by find() (looked for again until there is one).  Across the UML guest's
    boundary a file is what both sides see (its 127.0.0.1 is its own)."""
    fh = None
    rest = ""
    try:
        while time.monotonic() < until:
            if fh is None:
                path = find()
                fh = open(path, encoding="ascii", errors="replace") if path is not None else None  # noqa: SIM115
            if fh is not None:
                lines = (rest + fh.read()).split("\n")
                rest = lines.pop()   # a line not yet whole
                for ln in lines:
                    try:
                        fr = parse_line(ln)
                    except ValueError:
                        continue
                    if fr.classic_data:
                        chart.add(fr.frame_id, fr.data, fr.timestamp)
            time.sleep(poll_s)   # the recorder writes in blocks: a tenth of a second is its pace
    finally:
        if fh is not None:
            fh.close()


def serve(chart: Chart, port: int = 0) -> tuple[ThreadingHTTPServer, str]:
    """The chart's server on 127.0.0.1:port (0: a free port), in a thread of its own; its URL."""

    class Handler(BaseHTTPRequestHandler):
        def do_GET(self) -> None:  # noqa: N802 - http.server's name
            own = {f"127.0.0.1:{server.server_port}", f"localhost:{server.server_port}"}
            if self.headers.get("Host") not in own:
                self._send(403, "text/plain", b"forbidden\n")
                return
            url = urlparse(self.path)
            if url.path == "/":
                self._send(200, "text/html; charset=utf-8", PAGE.encode())
            elif url.path == "/data":
                try:
                    since = int(parse_qs(url.query).get("since", ["0"])[0])
                except ValueError:
                    since = 0
                self._send(200, "application/json", json.dumps(chart.since(since)).encode())
            else:
                self._send(404, "text/plain", b"not found\n")

        def _send(self, status: int, kind: str, body: bytes) -> None:
            self.send_response(status)
            self.send_header("Content-Type", kind)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args: Any) -> None:  # quiet: the terminal shows the panel
            pass

    server = ThreadingHTTPServer(("127.0.0.1", port), Handler)
    server.daemon_threads = True
    threading.Thread(target=server.serve_forever, name="hil-live-plot", daemon=True).start()
    return server, f"http://127.0.0.1:{server.server_port}/"


PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>hil live</title>
<style>
body { font: 14px system-ui, sans-serif; margin: 16px; color: #222; }
#legend span { margin-right: 18px; white-space: nowrap; }
#legend i { display: inline-block; width: 14px; height: 3px; margin-right: 5px; vertical-align: middle; }
canvas { border: 1px solid #bbb; }
</style></head>
<body>
<h1 style="font-size:18px">hil live: the bus, last @WINDOW@ s</h1>
<div id="legend"></div>
<canvas id="chart" width="1100" height="460" data-points="0" data-faults="0"></canvas>
<p id="status">waiting for data</p>
<script>
"use strict";
const WINDOW = @WINDOW@;
const COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"];
const series = {};
let order = [], seq = 0, faults = [];
const canvas = document.getElementById("chart"), ctx = canvas.getContext("2d");

function legend() {
  document.getElementById("legend").innerHTML = order.map((s, i) =>
    `<span><i style="background:${COLORS[i % COLORS.length]}"></i>${s}</span>`).join("");
}

function draw() {
  const W = canvas.width, H = canvas.height, L = 70, R = 10, T = 10, B = 30;
  ctx.clearRect(0, 0, W, H);
  let tmax = -Infinity, tfirst = Infinity;
  for (const s of order) for (const p of series[s]) { tmax = Math.max(tmax, p[0]); tfirst = Math.min(tfirst, p[0]); }
  if (!isFinite(tmax)) return 0;
  const span = Math.max(1, Math.min(WINDOW, tmax - tfirst)), tmin = tmax - span;
  let lo = Infinity, hi = -Infinity;
  for (const s of order) for (const p of series[s]) if (p[0] >= tmin && isFinite(p[1])) {
    lo = Math.min(lo, p[1]); hi = Math.max(hi, p[1]);
  }
  if (!isFinite(lo)) return 0;
  if (hi - lo < 1e-9) { lo -= 1; hi += 1; }
  const x = t => L + (t - tmin) / span * (W - L - R);
  const y = v => T + (hi - v) / (hi - lo) * (H - T - B);
  ctx.strokeStyle = "#ddd"; ctx.fillStyle = "#444"; ctx.font = "12px sans-serif"; ctx.lineWidth = 1;
  for (let i = 0; i <= 4; i++) {
    const v = lo + (hi - lo) * i / 4, yy = y(v);
    ctx.beginPath(); ctx.moveTo(L, yy); ctx.lineTo(W - R, yy); ctx.stroke();
    ctx.fillText(v.toPrecision(3), 4, yy + 4);
  }
  for (let i = 0; i <= 4; i++) {
    const t = tmin + span * i / 4;
    ctx.fillText(t.toFixed(1) + " s", Math.min(x(t) - 14, W - 50), H - 10);
  }
  let shaded = 0;
  ctx.fillStyle = "rgba(214, 39, 40, 0.12)";
  for (const f of faults) {
    const a = Math.max(f[0], tmin), b = f[1] === null ? tmax : Math.min(f[1], tmax);
    if (b <= a) continue;
    ctx.fillRect(x(a), T, x(b) - x(a), H - T - B);
    ctx.fillStyle = "#a00"; ctx.fillText(f[2], x(a) + 3, T + 12 + 14 * (shaded % 3));
    ctx.fillStyle = "rgba(214, 39, 40, 0.12)";
    shaded++;
  }
  canvas.dataset.faults = String(shaded);
  let drawn = 0;
  order.forEach((s, i) => {
    ctx.strokeStyle = COLORS[i % COLORS.length]; ctx.lineWidth = 1.5; ctx.beginPath();
    let pen = false;
    for (const p of series[s]) {
      if (p[0] < tmin || !isFinite(p[1])) { pen = false; continue; }
      if (pen) ctx.lineTo(x(p[0]), y(p[1])); else ctx.moveTo(x(p[0]), y(p[1]));
      pen = true; drawn++;
    }
    ctx.stroke();
  });
  return drawn;
}

async function poll() {
  try {
    const r = await fetch("data?since=" + seq, {cache: "no-store"});
    const j = await r.json();
    if (order.length === 0) { order = j.signals; for (const s of order) series[s] = []; legend(); }
    seq = j.seq;
    faults = j.faults;
    for (const s of order) {
      const pts = series[s];
      for (const p of j.points[s] || []) pts.push(p);
      const t = pts.length ? pts[pts.length - 1][0] : 0;
      while (pts.length && pts[0][0] < t - 2 * WINDOW) pts.shift();
    }
    const n = draw();
    canvas.dataset.points = String(n);
    document.getElementById("status").textContent = n + " points drawn";
  } catch (e) {
    document.getElementById("status").textContent = "no answer from hil live (" + e + ")";
  }
  setTimeout(poll, 250);
}
poll();
</script>
</body></html>
""".replace("@WINDOW@", f"{WINDOW_S:g}")
