"""scripts/bench.d/fcc, parts 2 and 3, inside scripts/with-vcan: fcc on vcan0 in lockstep
beside can_echo (one bus, one recorder's log: both turnarounds seen by the same observer; a step's
frames go out in one sendmmsg, as hil.rig.lockstep sends them to the host fcc, so that the tick's
authenticator follows the tick at once, as the echo's answer needs only its ping), then
fcc in realtime with both applications at 50 Hz fed by a python simulator.  Writes
OUT/vcan.json (hil.bench.fcc_table prints it) and leaves bus.log, lock.err and rt.err in OUT.

    python -m hil.bench.fcc_bus BUILD OUT [--rt-seconds S] [--lock-steps N] [--rt-priority P]
"""
from __future__ import annotations

import argparse
import json
import math
import re
import signal
import subprocess
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from hil.bus import SIM_NODES, load
from hil.bus.codec import Decoded
from hil.bus.mmsg import BatchSender
from hil.bus.node import BusNode
from hil.bus.protocol import COMMAND_FLIGHT, COMMAND_GROUND, COMMAND_SHUTDOWN
from hil.bus.secoc import TEST_KEY_FILE, Endpoint, read_key_file
from hil.rig.link import pack_frame
from hil.rig.recorder import BusRecorder

#: the frames whose kernel time stamps give the turnarounds
MSL_ACCEL_ID = load().by_name("MSL_ACCELEROMETER").frame_id
TICK_ID = load().by_name("SIM_TICK").frame_id
CMD_ID = load().by_name("MSL_ELEV_CMD").frame_id
PING_ID = load().by_name("RIG_PING").frame_id
PONG_ID = load().by_name("RIG_PONG").frame_id
PERIOD_S = 0.02
Frame = tuple[float, int, bytes]


def summary(text: str) -> dict[str, dict[str, float]]:
    """fcc's exit summary lines ("fcc summary: KEY [SUBKEY] k=v ..."), by key."""
    s = {}
    for line in text.splitlines():
        m = re.match(r"^fcc summary: (\S+)(?: (\S+))? (.*)$", line)
        if m:
            key = m.group(1) if m.group(2) is None or "=" in m.group(2) else m.group(1) + " " + m.group(2)
            s[key] = {k: float(v) for k, v in re.findall(r"(\w+)=([-\d.]+)", (m.group(2) or "") + " " + m.group(3))}
    return s


def send(node: BusNode, sec: Endpoint, name: str, values: dict[str, Any]) -> None:
    """A frame of the simulator with its authenticator."""
    fid, data = node.encode(name, values)
    for f, d in sec.protect(fid, data):
        node.send_raw(f, d)


def control(node: BusNode, sec: Endpoint, command: int) -> None:
    send(node, sec, "SIM_CONTROL", {"command": command, "lqg_period": 0.0, "da_bits": 0})


def attach(node: BusNode, fcc: subprocess.Popen) -> Endpoint:
    """A SecOC endpoint with fcc's trip (from its first authenticated heartbeat), fcc in FLIGHT."""
    sec = Endpoint(load(), read_key_file(TEST_KEY_FILE), SIM_NODES)
    deadline = time.monotonic() + 5.0
    while sec.trip is None and time.monotonic() < deadline and fcc.poll() is None:
        d = node.recv(0.1)
        if d is not None:
            sec.receive(d.frame_id, d.data)
    assert sec.trip is not None, "no authenticated heartbeat from fcc"
    control(node, sec, COMMAND_FLIGHT)
    return sec


def sensors(k: int) -> tuple[float, float]:
    """The missile's gyro and accelerometer readings of step k (a fixed test signal)."""
    return (round(0.1 * math.cos(0.7 * k) + 0.3 * math.sin(2.1 * k), 5),
            round((-3 + 40 * math.sin(0.45 * k)) / 0.002) * 0.002)


def fcc_process(build: Path, args: Sequence[str], err: Path) -> subprocess.Popen:
    return subprocess.Popen([str(build / "bin" / "fcc"), "--key-file", str(TEST_KEY_FILE), *args],
                            stderr=open(err, "w"))  # noqa: SIM115 - the child keeps it


def send_batch(batch: BatchSender, frames: list[tuple[int, bytes]]) -> None:
    """frames in one sendmmsg, as the rig sends a step's frames to the host fcc (hil.rig.lockstep)."""
    n = batch.load([pack_frame(fid, data) for fid, data in frames])
    sent = 0
    while sent < n:
        got = batch.send(sent, n)
        assert got > 0, f"sendmmsg failed: errno {-got}"
        sent += got


def _equals(name: str, value: int) -> Callable[[Decoded], bool]:
    """A wait_for match: the frame's signal `name` has this value."""
    return lambda d: d.values is not None and d.values[name] == value


def lockstep_steps(node: BusNode, sec: Endpoint, steps: int) -> None:
    """Each step: sensors and the tick (with its authenticator) in one batch, FCC_ACK; then a
    RIG_PING that can_echo answers."""
    batch = BatchSender(node.bus.fileno())  # socketcan: its socket's
    for k in range(steps):
        q_g, n_a = sensors(k)
        frames = [node.encode("MSL_RATE_GYRO", {"step": k & 0xFFFF, "q_g": q_g}),
                  node.encode("MSL_ACCELEROMETER", {"step": k & 0xFFFF, "n_a": n_a}),
                  *sec.protect(*node.encode("SIM_TICK", {"app": 1, "step": k}))]
        send_batch(batch, frames)
        assert node.wait_for("FCC_ACK", 2.0, _equals("step", k)) is not None, k
        node.send("RIG_PING", {"seq": k, "t_send_us": int(time.monotonic() * 1e6) & 0xFFFFFFFF})
        assert node.wait_for("RIG_PONG", 2.0, _equals("seq", k)) is not None, k


def lockstep_run(build: Path, out: Path, steps: int, res: dict[str, Any]) -> None:
    """fcc in lockstep and can_echo on one bus, recorded into OUT/bus.log by canrec, the rig's
    recorder (candump's lines, the kernel's receive stamps; one read for a step's frames where
    candump reads and writes each: an observer that would delay a batch more than a ping)."""
    dump = subprocess.Popen([str(build / "bin" / "canrec"), "-r", str(BusRecorder.RCVBUF), "-o",
                             str(out / "bus.log"), "vcan0"])
    echo = subprocess.Popen([str(build / "bin" / "can_echo"), "-i", "vcan0", "-q"], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    node = BusNode("vcan0", SIM_NODES)
    time.sleep(0.3)
    t0 = time.monotonic()
    fcc = fcc_process(build, ["--apps", "missile"], out / "lock.err")
    sec = attach(node, fcc)
    res["startup_ms"] = (time.monotonic() - t0) * 1e3
    lockstep_steps(node, sec, steps)
    control(node, sec, COMMAND_GROUND)
    control(node, sec, COMMAND_SHUTDOWN)
    fcc.wait(10)
    node.close()
    echo.send_signal(signal.SIGINT)
    echo.wait(5)
    time.sleep(0.2)
    dump.send_signal(signal.SIGINT)
    dump.wait(5)
    res["lock"] = summary((out / "lock.err").read_text())


def read_candump(path: Path) -> list[Frame]:
    frames = []
    for line in path.read_text().splitlines():
        m = re.match(r"\((\d+\.\d+)\) vcan0 ([0-9A-F]+)#([0-9A-F]*)", line)
        if m:
            frames.append((float(m.group(1)), int(m.group(2), 16), bytes.fromhex(m.group(3))))
    return frames


def turnarounds(frames: Sequence[Frame]) -> dict[str, list[float]]:
    """sensor -> command, tick -> command and ping -> pong, from the kernel's time stamps."""
    got: dict[str, list[float]] = {"sensor_to_cmd": [], "tick_to_cmd": [], "ping_to_pong": []}
    last_accel = last_tick = last_ping = None
    for t, fid, data in frames:
        if fid == MSL_ACCEL_ID:
            last_accel = t
        elif fid == TICK_ID and len(data) == 8:
            last_tick = t
        elif fid == CMD_ID and last_tick is not None:
            got["tick_to_cmd"].append(t - last_tick)
            got["sensor_to_cmd"].append(t - last_accel)  # type: ignore[operator]
            last_tick = None
        elif fid == PING_ID:
            last_ping = t
        elif fid == PONG_ID and last_ping is not None:
            got["ping_to_pong"].append(t - last_ping)
            last_ping = None
    return got


def pct(xs: Sequence[float], p: float) -> float:
    """The p quantile of xs in microseconds (nearest rank; NaN when empty)."""
    xs = sorted(xs)
    return xs[min(len(xs) - 1, max(0, math.ceil(p * len(xs)) - 1))] * 1e6 if xs else float("nan")


def realtime_feed(node: BusNode, fcc: subprocess.Popen, seconds: float,
                  now: Callable[[], float] = time.monotonic) -> None:
    """Both applications' sensor frames every 20 ms until fcc ends (or seconds + 5 s)."""
    start = now()
    nxt, k = start, 0
    while fcc.poll() is None and now() < start + seconds + 5:
        if now() >= nxt:
            t = PERIOD_S * k
            node.send("CDRW_AOA", {"step": k & 0xFFFF, "alpha": round(0.16 + 0.1 * math.sin(0.9 * t), 6)})
            node.send("CDRW_PITCH_RATE", {"step": k & 0xFFFF, "q": round(0.09 * math.cos(0.9 * t), 6)})
            node.send("CDRW_ELEVATOR", {"step": k & 0xFFFF, "delta_e": round(-0.05 - 0.08 * math.sin(1.3 * t), 6)})
            q_g, n_a = sensors(k)
            node.send("MSL_RATE_GYRO", {"step": k & 0xFFFF, "q_g": q_g})
            node.send("MSL_ACCELEROMETER", {"step": k & 0xFFFF, "n_a": n_a})
            k += 1
            nxt += PERIOD_S
        while node.recv(0) is not None:
            pass
        time.sleep(max(0.0, nxt - now()))


def realtime_run(build: Path, out: Path, seconds: float, prio: str, res: dict[str, Any]) -> None:
    """fcc in realtime, both applications at 50 Hz."""
    node = BusNode("vcan0", SIM_NODES)
    fcc = fcc_process(build, ["--mode", "realtime", "--lqg-period", "0.02", "--duration", str(seconds),
                              "--rt-priority", prio], out / "rt.err")
    attach(node, fcc)
    realtime_feed(node, fcc, seconds)
    fcc.wait(10)
    node.close()
    res["rt"] = summary((out / "rt.err").read_text())
    res["rt_seconds"] = seconds
    res["rt_prio"] = prio


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.bench.fcc_bus", description=__doc__.splitlines()[0])
    p.add_argument("build", type=Path, help="the build with bin/fcc and bin/can_echo")
    p.add_argument("out", type=Path, help="where vcan.json and the logs go")
    p.add_argument("--rt-seconds", type=float, default=60.0)
    p.add_argument("--lock-steps", type=int, default=3000)
    p.add_argument("--rt-priority", default="50", help="fcc's SCHED_FIFO priority (0: normal)")
    a = p.parse_args(argv)
    res: dict[str, Any] = {}
    lockstep_run(a.build, a.out, a.lock_steps, res)
    for name, xs in turnarounds(read_candump(a.out / "bus.log")).items():
        res[name] = {"n": len(xs), "p50": pct(xs, 0.5), "p99": pct(xs, 0.99)}
    realtime_run(a.build, a.out, a.rt_seconds, a.rt_priority, res)
    (a.out / "vcan.json").write_text(json.dumps(res))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
