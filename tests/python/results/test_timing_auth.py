"""Realtime timing from authentic frames only (hil.results.timing with the run's key): forged
FCC_SYNC_STATUS frames (an offset of 30 ms) and forged MSL_ELEV_CMD frames (commands late in
the period) in a recorded log leave every timing sample what the authentic frames give; read
without the key, the same log's figures move (the test has teeth)."""
from __future__ import annotations

import numpy as np

from hil.bus import FCC_NODE, SIM_NODES, FrameCodec, load
from hil.bus.candump import format_line
from hil.bus.secoc import Sender
from hil.results.buslog import BusAuth
from hil.results.timing import bus_timing, link_timing, summarise

SPEC = load()
KEY, TRIP = bytes(range(16)), 0x5678
PERIOD = 0.05
HEARTBEAT = SPEC.by_name("FCC_STATUS_AUTH")
T0 = 1000.0   # the log's clock (candump's), s; the master's time is T0 + 7 s


def _auth(name: str) -> Sender:
    return Sender(KEY, SPEC.by_name(name).secoc_data_id, TRIP)


def realtime_log(forged: bool) -> list[tuple[float, int, bytes]]:
    """40 missile periods as a realtime run puts them on the bus (each group followed by its
    authenticator): a sync pair every period, the two sensor samples, fcc's command and estimate
    0.4 ms later, a heartbeat every other period; forged: a keyless node's FCC_SYNC_STATUS
    and MSL_ELEV_CMD in every period, 10 ms after fcc's."""
    sim, fcc = FrameCodec(nodes=SIM_NODES), FrameCodec(nodes=FCC_NODE)
    tsync, cmd_auth, hb_auth = _auth("TSYNC_AUTH"), _auth("MSL_ELEV_CMD_AUTH"), _auth("FCC_STATUS_AUTH")
    out: list[tuple[float, int, bytes]] = []
    for k in range(40):
        t = T0 + k * PERIOD
        master = t + 7.0
        sync = sim.encode("TSYNC_SYNC", {"master": 1, "seq": k & 0xFF, "interval_ms": 50,
                                         "sec": int(master)})
        fup = sim.encode("TSYNC_FOLLOW_UP", {"master": 1, "seq": k & 0xFF, "sec_carry": 0,
                                             "ns": round((master - int(master)) * 1e9)})
        out += [(t, *sync), (t + 1e-4, *fup), (t + 2e-4, SPEC.by_name("TSYNC_AUTH").frame_id,
                                                tsync.protect(sync[1] + fup[1]))]
        out += [(t + 3e-4, *sim.encode("MSL_RATE_GYRO", {"step": k, "q_g": 0.1})),
                (t + 4e-4, *sim.encode("MSL_ACCELEROMETER", {"step": k, "n_a": 1.0}))]
        c = fcc.encode("MSL_ELEV_CMD", {"degraded": 0, "saturated": 0, "step": k, "da_code": 5, "da_bits": 8})
        e = fcc.encode("MSL_STATE_EST", {"q_hat": 0.1, "alpha_t_hat": 0.0, "w_g_hat": 0.0, "step": k & 0xFF})
        out += [(t + 8e-4, *c), (t + 9e-4, *e), (t + 1e-3, SPEC.by_name("MSL_ELEV_CMD_AUTH").frame_id,
                                                  cmd_auth.protect(c[1] + e[1]))]
        if k % 2:
            frames = [fcc.encode(name, {s.name: (2 if s.name == "state" else 1 if s.name == "trip" else 0)
                                        for s in SPEC.by_name(name).signals if s.name not in ("crc", "counter")})
                      for name in HEARTBEAT.secoc_pdus]
            out += [(t + 0.02 + 1e-5 * i, fid, d) for i, (fid, d) in enumerate(frames)]
            out.append((t + 0.021, HEARTBEAT.frame_id, hb_auth.protect(b"".join(d for _, d in frames))))
        if forged:
            status = fcc.encode("FCC_SYNC_STATUS", {"state": 2, "master": 1, "offset_us": 30000,
                                                    "rate_ppm": 0.0, "syncs": 0, "rejected": 0, "losses": 0})
            out += [(t + 0.03, *status), (t + 0.031, *c)]
    return out


def write(path, frames) -> None:
    path.write_text("".join(format_line(t, "vcan0", fid, d) + "\n" for t, fid, d in sorted(frames)))


def test_forged_status_and_commands_change_no_timing(tmp_path):
    write(tmp_path / "clean.log", realtime_log(False))
    write(tmp_path / "forged.log", realtime_log(True))
    auth = BusAuth(KEY, TRIP)
    clean = bus_timing(tmp_path / "clean.log", SPEC, PERIOD, auth)
    got = bus_timing(tmp_path / "forged.log", SPEC, PERIOD, auth)
    assert len(clean["cmd_delay"]) == 40 and len(clean["sync_offset"]) == 20
    assert np.allclose(clean["cmd_delay"], 800.0, atol=1.0)   # each command 0.8 ms into its period
    assert np.all(clean["sync_offset"] == 0.0)
    for kind in clean:
        assert np.array_equal(got[kind], clean[kind]), kind
    # without the key, the forged frames are measured: 40 more commands, 40 offsets of 30 ms
    naive = bus_timing(tmp_path / "forged.log", SPEC, PERIOD)
    assert len(naive["cmd_delay"]) == 80 and np.count_nonzero(naive["sync_offset"] == 30000.0) == 40


def test_a_devices_link_comes_from_its_summary_and_the_host_has_none() -> None:
    """The M4F image's `rx_timing` line is its serial link's figures (summary.json
    realtime.fcc.link); the host fcc prints none, and its summary has no link."""
    image = ("fcc summary: latency_us missile n=100 p50=536 p99=704 max=2428\n"
             "fcc summary: rx_timing lines=379 line_us_mean=1800 line_us_worst=6020 bus_stamped=372 "
             "bus_delay_us_mean=1651 bus_delay_us_worst=16218 bus_rebases=0\n")
    assert link_timing(image) == {"lines": 379, "line_us_mean": 1800, "line_us_worst": 6020, "bus_stamped": 372,
                                  "bus_delay_us_mean": 1651, "bus_delay_us_worst": 16218, "bus_rebases": 0}
    assert summarise({}, image)["fcc"]["link"]["bus_delay_us_worst"] == 16218
    host = "fcc summary: latency_us missile n=100 p50=60 p99=80 max=90\n"
    assert link_timing(host) == {} and "link" not in summarise({}, host)["fcc"]
