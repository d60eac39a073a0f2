"""The bus end to end on vcan0 (run inside scripts/with-vcan): python-can, candump/cansend,
the C SocketCAN port through can_echo, and scripts/diag on a log recorded here.

    scripts/with-vcan .venv/bin/python -m pytest -m vcan tests/python/bus/test_bus_vcan.py
"""
from __future__ import annotations

import json
import re
import os
import signal
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import can
import pytest

from hil.bus import FCC_NODE, SIM_NODES, dbc
from hil.bus.candump import read_log
from hil.bus.codec import FrameCodec, Verdict
from hil.bus.e2e import E2EStatus
from hil.bus.node import BusNode

pytestmark = pytest.mark.vcan
IFACE = "vcan0"


@pytest.fixture(autouse=True)
def _needs_vcan() -> None:
    assert Path(f"/sys/class/net/{IFACE}").exists(), f"no {IFACE}: run inside scripts/with-vcan"


class Candump:
    """candump -L running in the background, writing to a file (it flushes every frame)."""

    def __init__(self, path: Path, *args: str) -> None:
        self.path = path
        self._f = open(path, "w")  # noqa: SIM115 - candump writes it until stop() closes it
        self.proc = subprocess.Popen(["candump", "-L", *args, IFACE], stdout=self._f)

    def wait_ready(self, node: BusNode) -> None:
        """Send a marker until candump has recorded one (no race with its start)."""
        for _ in range(200):
            node.send_raw(0x7FF, b"\x00")
            time.sleep(0.02)
            if self.path.read_text():
                return
        raise AssertionError("candump did not start")

    def stop(self) -> list:
        self.proc.send_signal(signal.SIGINT)
        self.proc.wait(timeout=10)
        self._f.close()
        return [f for f in read_log(self.path) if f.frame_id != 0x7FF]


@pytest.fixture()
def sim() -> Iterator[BusNode]:
    with BusNode(IFACE, SIM_NODES) as node:
        yield node


def test_python_can_to_candump_and_cantools_decode(sim: BusNode, tmp_path: Path,
                                                  repo: Path) -> None:
    dump = Candump(tmp_path / "a.log")
    dump.wait_ready(sim)
    sent = []
    for step in range(20):
        for name, values in (("CDRW_AOA", {"step": step, "alpha": 0.15 + 1e-4 * step}),
                             ("CDRW_PITCH_RATE", {"step": step, "q": -0.01 * step}),
                             ("SIM_TICK", {"app": 0, "step": step})):
            fid, data = sim.codec.encode(name, values)
            assert sim.send_raw(fid, data)
            sent.append((fid, data))
    time.sleep(0.3)
    frames = dump.stop()
    assert [(f.frame_id, f.data) for f in frames] == sent
    assert all(f.channel == IFACE and f.timestamp > 1e9 for f in frames)  # absolute times
    # the README's one-liner: candump -L | cantools decode --single-line
    r = subprocess.run([sys.executable, "-m", "cantools", "decode", "--single-line",
                        str(dbc.DEFAULT_DBC)], input=dump.path.read_text(),
                       capture_output=True, text=True, check=True)
    assert r.stdout.count("SIM_TICK(") == 20
    assert r.stdout.count("CDRW_AOA(crc: ") == 20
    m = re.search(r"CDRW_AOA\(crc: \d+, counter: 3, step: 19, alpha: ([0-9.e-]+) rad\)", r.stdout)
    assert m is not None and float(m.group(1)) == pytest.approx(0.1519, abs=1e-12)


def test_cansend_to_python_can() -> None:
    sender = FrameCodec(nodes=SIM_NODES)
    with BusNode(IFACE, FCC_NODE) as fcc:
        fid, good = sender.encode("CDRW_ELEVATOR", {"step": 9, "delta_e": -0.0349})
        bad = bytes([good[0] ^ 0x10]) + good[1:]
        for data in (good, good, bad):
            subprocess.run(["cansend", IFACE, f"{fid:03X}#{data.hex()}"], check=True)
        subprocess.run(["cansend", IFACE, "124#00"], check=True)        # not in the DBC
        subprocess.run(["cansend", IFACE, f"{fid:03X}#0011"], check=True)  # wrong DLC
        got = [fcc.recv(timeout=5.0) for _ in range(4)]
        # the kernel filter (the FCC's identifiers only) kept 0x124 out
        assert fcc.recv(timeout=0.5) is None
    assert all(d is not None for d in got)
    first, repeat, error, short = got
    assert first.ok and first.values == {"step": 9, "delta_e": pytest.approx(-0.0349)}
    assert first.timestamp > 1e9
    assert (repeat.verdict, repeat.e2e) == (Verdict.E2E, E2EStatus.REPEATED)
    assert (error.verdict, error.e2e) == (Verdict.E2E, E2EStatus.ERROR)
    assert short.verdict is Verdict.WRONG_DLC
    assert fcc.codec.counters.wrong_dlc == 1
    assert fcc.codec.counters.e2e[E2EStatus.ERROR] == 1


def test_unfiltered_node_counts_unknown_ids() -> None:
    with BusNode(IFACE, FCC_NODE, filters=False) as fcc:
        subprocess.run(["cansend", IFACE, "124#00"], check=True)
        subprocess.run(["cansend", IFACE, "12345678#00"], check=True)  # extended identifier
        got = [fcc.recv(timeout=5.0) for _ in range(2)]
    assert [d.verdict for d in got if d is not None] == [Verdict.UNKNOWN_ID] * 2
    assert fcc.codec.counters.unknown_id == 2


def _start_echo(bin_path, *args: str) -> subprocess.Popen:
    proc = subprocess.Popen([str(bin_path("can_echo")), "-i", IFACE, *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    assert proc.stdout.readline().startswith(f"can_echo: ready on {IFACE}")
    return proc


def _summary(proc: subprocess.Popen) -> dict[str, int]:
    out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err
    line = out.strip().splitlines()[-1]
    fields = line.split("echoed ")[1].replace(";", ",").split(",")
    counts = {"echoed": int(fields[0])}
    for f in fields[1:]:
        *name, value = f.split()
        counts["_".join(name)] = int(value)
    return counts


def test_can_echo_exchanges_frames_with_python_can(sim: BusNode, bin_path) -> None:
    n = 50
    echo = _start_echo(bin_path, "-n", str(n), "-t", "20")
    rtts = []
    for seq in range(n):
        sim.send("SIM_TICK", {"app": 1, "step": seq})  # another identifier: filtered out
        t0 = time.perf_counter()
        sim.send("RIG_PING", {"seq": seq, "t_send_us": seq * 1000})
        pong = sim.wait_for("RIG_PONG", 5.0, match=lambda d, s=seq: d.values["seq"] == s)
        rtts.append(time.perf_counter() - t0)
        assert pong is not None, seq
        assert pong.values == {"seq": seq, "t_send_us": seq * 1000}
    c = _summary(echo)
    assert c["echoed"] == n and c["rx"] == n and c["tx"] == n  # the filter kept the ticks out
    assert c["tx_dropped"] == 0 and c["bus_errors"] == 0
    print(f"python-can -> can_echo -> python-can round trip: median "
          f"{statistics.median(rtts) * 1e6:.0f} us, max {max(rtts) * 1e6:.0f} us over {n}")


def test_can_echo_counts_error_frames_and_queue_overflows(bin_path) -> None:
    echo = _start_echo(bin_path, "-t", "3")
    # an error frame (CAN_ERR_FLAG | CAN_ERR_CRTL) on vcan: counted, not echoed
    subprocess.run(["cansend", IFACE, "20000004#0000000000000000"], check=True)
    time.sleep(0.2)
    os.kill(echo.pid, signal.SIGSTOP)  # the port stops reading: the kernel queue overflows
    n_flood = 3000
    with can.Bus(interface="socketcan", channel=IFACE) as bus:
        for i in range(n_flood):
            bus.send(can.Message(arbitration_id=0x7F0, data=i.to_bytes(8, "little"),
                                 is_extended_id=False))
        os.kill(echo.pid, signal.SIGCONT)
        time.sleep(0.5)
        # the kernel reports the drop count with the next frames queued
        for _ in range(5):
            bus.send(can.Message(arbitration_id=0x7F0, data=bytes(8), is_extended_id=False))
            time.sleep(0.05)
    c = _summary(echo)
    assert c["bus_errors"] == 1
    assert c["rx_overflows"] > 0
    assert c["rx"] + c["rx_overflows"] == n_flood + 5  # every frame received or counted lost
    assert c["echoed"] == c["rx"]


def test_can_echo_bad_arguments(bin_path) -> None:
    for args in (["-r", "0x800"], ["-n", "-1"], ["-x", "1"], ["-i"]):
        r = subprocess.run([str(bin_path("can_echo")), *args], capture_output=True, text=True)
        assert r.returncode == 2 and len(r.stderr.splitlines()) == 1, args
    r = subprocess.run([str(bin_path("can_echo")), "-i", "nocan9"], capture_output=True, text=True)
    assert r.returncode == 1 and "cannot open CAN interface 'nocan9'" in r.stderr


def test_diag_on_a_log_recorded_from_vcan(sim: BusNode, tmp_path: Path, repo: Path) -> None:
    dump = Candump(tmp_path / "run.log")
    dump.wait_ready(sim)
    for step in range(60):
        values = {"step": step, "alpha": 0.16}
        fid, data = sim.codec.encode("CDRW_AOA", values)
        sim.send("SIM_TICK", {"app": 0, "step": step})
        if step == 30:
            continue                                  # lost frame
        sim.send_raw(fid, data)
        if step == 40:
            sim.send_raw(fid, data)                   # duplicate
        if step == 45:
            sim.send_raw(fid, bytes([data[0] ^ 0xFF]) + data[1:])  # bad CRC
        if step == 50:
            sim.send_raw(fid, data[:5])               # wrong DLC
        time.sleep(0.02)
    sim.send_raw(0x124, bytes(8))
    time.sleep(0.3)
    frames = dump.stop()
    assert len(frames) == 59 + 3 + 60 + 1
    r = subprocess.run([str(repo / "scripts" / "diag"), "--log", str(dump.path), "--json"],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    rep = json.loads(r.stdout)
    by_name = {m["name"]: m for m in rep["messages"]}
    aoa, tick = by_name["CDRW_AOA"], by_name["SIM_TICK[cdrw]"]  # one stream per application
    assert aoa["count"] == 62 and tick["count"] == 60
    assert aoa["e2e"]["OK_SOME_LOST"] == 1 and aoa["e2e"]["REPEATED"] == 1
    assert aoa["e2e"]["ERROR"] == 1 and aoa["wrong_dlc"] == 1
    assert aoa["e2e"]["OK"] == 58  # 59 good frames, one of them OK_SOME_LOST
    assert tick["e2e"]["OK"] == 60
    assert rep["unknown_ids"] == {"124": 1, "7FF": 1} or rep["unknown_ids"] == {"124": 1}
    assert 10 < tick["rate_hz"] < 60 and tick["jitter_std_ms"] >= 0
    assert 0 < rep["load_exact_pct"] < rep["load_worst_pct"]
    text = subprocess.run([str(repo / "scripts" / "diag"), "--log", str(dump.path)],
                          capture_output=True, text=True, check=True).stdout
    print(text)
    assert "CDRW_AOA" in text and "bus load" in text


def test_diag_live_interface(sim: BusNode, tmp_path: Path, repo: Path) -> None:
    saved = tmp_path / "live.log"
    proc = subprocess.Popen([str(repo / "scripts" / "diag"), "--iface", IFACE, "--seconds", "3",
                             "--json", "--save", str(saved)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    assert proc.stderr is not None
    assert proc.stderr.readline().startswith(f"diag: capturing {IFACE}")
    for step in range(40):
        sim.send("SIM_TICK", {"app": 1, "step": step})
        time.sleep(0.01)
    out, _ = proc.communicate(timeout=30)
    assert proc.returncode == 0
    rep = json.loads(out)
    (tick,) = [m for m in rep["messages"] if m["name"] == "SIM_TICK[missile]"]
    assert 0 < tick["count"] <= 40 and tick["e2e"]["ERROR"] == 0
    assert len([f for f in read_log(saved) if f.frame_id == 0x020]) == tick["count"]


def test_link_send_many_batches_in_order() -> None:
    """hil.rig.link's batched send (sendmmsg): every frame, in its order, across more than one
    batch; the same frames as one send() each, and counted alike."""
    from hil.bus.mmsg import BatchSender
    from hil.rig.link import CanLink, pack_frame
    assert BatchSender.available()
    frames = [(0x100 + i % 7, bytes([i & 0xFF, i >> 8, 3])) for i in range(BatchSender.CAPACITY * 2 + 5)]
    with CanLink(IFACE, frame_ids=None) as rx, CanLink(IFACE, frame_ids=[]) as tx:
        assert tx.send_many([pack_frame(fid, d) for fid, d in frames]) == 0
        assert tx.send_many([pack_frame(0x123, b"x")]) == 0   # one frame: send_raw
        got = []
        while len(got) < len(frames) + 1 and (f := rx.recv_wait(1.0)) is not None:
            got.append(f)
    assert got == frames + [(0x123, b"x")]
    assert tx.tx_frames == len(frames) + 1 and tx.tx_dropped == 0


def test_link_recv_takes_a_burst_in_one_call_and_every_receive_hands_out_the_rest() -> None:
    """hil.rig.link's blocking receive (recvmmsg): a burst queued behind the first frame comes
    in the same call (read ahead, counted as received), and whichever receive comes next --
    recv, recv_wait, recv_stamped, drain -- hands out the frames read ahead first, in order."""
    from hil.bus.mmsg import BatchReceiver
    from hil.rig.link import CanLink, pack_frame
    assert BatchReceiver.available()
    frames = [(0x100 + i, bytes([i, 0xA5])) for i in range(6)]
    with CanLink(IFACE, frame_ids=None) as rx, CanLink(IFACE, frame_ids=[]) as tx:
        assert tx.send_many([pack_frame(fid, d) for fid, d in frames]) == 0
        assert rx.recv_wait(1.0) is not None   # the burst is there (polled; then one frame read)
        first = rx.recv()                      # the rest in one recvmmsg
        assert first == frames[1] and rx.rx_frames == len(frames) and len(rx._ahead) == 4
        assert rx.recv_wait(0.0) == frames[2]
        stamped = rx.recv_stamped(0.0)
        assert stamped is not None and stamped[:2] == frames[3]
        assert rx.recv() == frames[4]
        assert rx.drain() == [frames[5]]
        assert rx.recv() is None and rx.rx_frames == len(frames)   # one slice, nothing more
