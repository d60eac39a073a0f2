"""scripts/bench.d/pil's Python half: the on-target instruction counts the bench image wrote
(OUT/bench.log, m4f_bench.elf under -icount shift=0) as a table with times at 168 MHz and the
hardest case's budget; then fcc_m4f.elf in lockstep over its pty (wall ms per CDRW step); then in realtime under
QEMU with a re-design requested every 0.5 s; then the image's flash and static RAM (OUT/size).

    python -m hil.bench.pil OUT IMAGE.elf [--rt-seconds S] [--lockstep-steps N]
"""
from __future__ import annotations

import argparse
import re
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from hil.bus import SIM_NODES, load
from hil.bus.codec import FrameCodec
from hil.bus.protocol import COMMAND_FLIGHT, COMMAND_GROUND, COMMAND_RESET, COMMAND_SHUTDOWN
from hil.bus.secoc import TEST_KEY_FILE, Endpoint, read_key_file
from hil.targets.board import Board, SlcanLink
from hil.targets.bootcfg import BootConfig
from hil.targets.qemu_m4f import PIL_TRIP

MHZ = 168.0
PERIOD_US = 20000.0
REQUEST_EVERY_S = 0.5
Record = dict[str, dict[str, int]]


def kv(line: str) -> dict[str, int]:
    """The KEY=WHOLE_NUMBER pairs of a line."""
    return {k: int(v) for k, v in re.findall(r"(\w+)=(\d+)", line)}


def us(insns: float) -> float:
    """Instructions as microseconds at 168 MHz, one cycle each."""
    return insns / MHZ


def read_bench_log(path: Path) -> tuple[Record, dict[int, dict[str, int]]]:
    """The bench image's "pil NAME k=v ..." lines: the records by name, the designs by T (ms)."""
    rec: Record = {}
    designs = {}
    for line in path.read_text().splitlines():
        m = re.match(r"pil (\w+)(.*)", line)
        if not m:
            continue
        name, rest = m.groups()
        if name == "design":
            d = kv(rest)
            designs[d["t_ms"]] = d
        else:
            rec.setdefault(name, {}).update(kv(rest))
    assert "done" in rec, "the bench image did not finish"
    return rec, designs


def counts_table(rec: Record, designs: dict[int, dict[str, int]]) -> None:
    calib = rec["calib"]
    print(f"instruction counter check: a {calib['loop_insns']:,}-instruction loop measured "
          f"{calib['measured_insns']:,} (timer resolution 40)")
    print()
    print("| on the emulated Cortex-M4F (-icount shift=0) | mean instructions | max instructions | max at 168 MHz |")
    print("|---|---|---|---|")
    rows = [("CDRW step, normal flight (AZKF q = 2, ZKF q = 1000, KF), frames in -> 12 frames out", "cdrw_normal"),
            ("CDRW step, fault held (AZKF q = 1000 too)", "cdrw_fault"),
            ("missile step (Kalman + LQR + D/A, frames in -> out)", "missile")]
    for label, key in rows:
        r = rec[key]
        print(f"| {label} | {r['mean_insns']:,} | {r['max_insns']:,} | {us(r['max_insns']):,.0f} µs |")
    for t_ms, d in sorted(designs.items()):
        print(f"| LQG re-design T = {t_ms / 1000:g} s, whole (8 slices, software double) | "
              f"{d['total_insns']:,} | max slice {d['max_slice_insns']:,} | "
              f"{us(d['total_insns']):,.0f} µs whole, {us(d['max_slice_insns']):,.0f} µs max slice |")
    print(f"| boot (both applications initialised, first design) | {rec['boot']['insns']:,} | | "
          f"{us(rec['boot']['insns']):,.0f} µs |")


def budget(rec: Record, designs: dict[int, dict[str, int]]) -> None:
    """The hardest case, T = 0.02 s: worst CDRW step + missile step + the longest slice."""
    worst_design = max(d["total_insns"] for d in designs.values())
    worst_slice = max(d["max_slice_insns"] for d in designs.values())
    step = rec["cdrw_fault"]["max_insns"] + rec["missile"]["max_insns"]
    print()
    print(f"hardest case, T = 0.02 s at 168 MHz: one whole re-design {us(worst_design):,.0f} µs "
          f"{'>' if us(worst_design) > PERIOD_US else '<='} the {PERIOD_US:,.0f} µs period, so it runs in slices "
          f"between steps; worst CDRW step + missile step + longest slice = {us(step):,.0f} + "
          f"{us(worst_slice):,.0f} = {us(step + worst_slice):,.0f} µs "
          f"({100 * us(step + worst_slice) / PERIOD_US:.0f} % of the period: "
          f"{'fits' if us(step + worst_slice) < PERIOD_US else 'DOES NOT FIT'}; "
          f"at 1.5 cycles per instruction {1.5 * us(step + worst_slice):,.0f} µs)")
    print(f"stack used {rec['memory']['stack_used']:,} B of 16,384; node {rec['memory']['node_bytes']:,} B")


class Commander:
    """SIM_CONTROL to the image: it refuses unauthenticated commands, so with its published
    test key and fixed trip."""

    def __init__(self, link: SlcanLink) -> None:
        self.link = link
        self.codec = FrameCodec(nodes=SIM_NODES)
        self.security = Endpoint(load(), read_key_file(TEST_KEY_FILE), SIM_NODES)
        self.security.set_trip(PIL_TRIP)

    def control(self, command: int, lqg_period: float = 0) -> None:
        values = {"command": command, "lqg_period": lqg_period, "da_bits": 0}
        for f in self.security.protect(*self.codec.encode("SIM_CONTROL", values)):
            self.link.send(*f)


def lockstep(out: Path, elf: Path, steps: int) -> tuple[float, dict[str, int]]:
    """fcc_m4f.elf in lockstep over the bare pty (no slcand): `steps` CDRW steps, each its
    sensor frames, SIM_TICK and its authenticator in one write, then until its FCC_ACK;
    (wall ms per step, the image's board summary)."""
    run = out / "lockstep"
    run.mkdir()
    with Board(elf, run, config=BootConfig(apps=("cdrw",))) as board:
        cmd = Commander(board.link())
        ack = cmd.codec.spec.by_name("FCC_ACK").frame_id
        cmd.control(COMMAND_FLIGHT)
        t0 = time.perf_counter()
        for k in range(steps):
            for name, values in (("CDRW_AOA", {"alpha": 0.1}), ("CDRW_PITCH_RATE", {"q": 0.01 * (k % 7)}),
                                 ("CDRW_ELEVATOR", {"delta_e": -0.05}), ("SIM_TICK", {"app": 0})):
                for f in cmd.security.protect(*cmd.codec.encode(name, {"step": k, **values})):
                    cmd.link.send(*f)
            answer = _until_ack(cmd.link, ack)
            acked = cmd.codec.decode(ack, answer[-1][1]).values if answer else None
            if acked is None or int(acked["step"]) != k:
                raise RuntimeError(f"the image did not answer lockstep step {k}")
        wall = time.perf_counter() - t0
        cmd.control(COMMAND_GROUND)
        cmd.control(COMMAND_SHUTDOWN)
        status = board.exit_status(60)
        log = board.log()
    assert status == 0, log
    board_line = re.search(r"fcc summary: board(.*)", log)
    assert board_line is not None, log
    return 1e3 * wall / steps, kv(board_line.group(1))


def _until_ack(link: SlcanLink, ack: int) -> list[tuple[int, bytes]]:
    """The frames up to and including the next FCC_ACK (empty after 20 s without one)."""
    got = []
    for fid, data in link.frames(20.0):
        got.append((fid, data))
        if fid == ack:
            return got
    return []


def lockstep_line(steps: int, ms: float, board: dict[str, int]) -> None:
    print()
    print(f"lockstep on QEMU (-icount shift=0,sleep=on) over the bare pty, no slcand, {steps} CDRW "
          f"steps: {ms:.1f} ms a step on this machine ({board['rx_bytes'] / steps:.0f} bytes to the "
          f"image and {board['tx_bytes'] / steps:.0f} from it per step, one QEMU main-loop round "
          f"per received byte; the rig in the UML guest adds its system calls' cost)")


def redesigns(cmd: Commander, seconds: float) -> int:
    """A re-design every 0.5 s for `seconds` (T alternating 0.025 / 0.02 s); how many."""
    requests = 0
    t0 = time.monotonic()
    next_req = t0 + REQUEST_EVERY_S
    while (now := time.monotonic()) < t0 + seconds:
        for _ in cmd.link.frames(min(0.05, max(0.0, next_req - now))):
            pass
        if time.monotonic() >= next_req:
            period = 0.02 if requests % 2 else 0.025
            # a design is accepted on the ground only: land, reset with the new period, fly on
            cmd.control(COMMAND_GROUND)
            cmd.control(COMMAND_RESET, period)
            cmd.control(COMMAND_FLIGHT)
            requests += 1
            next_req += REQUEST_EVERY_S
    return requests


def realtime(out: Path, elf: Path, seconds: float) -> tuple[int, str]:
    """fcc_m4f.elf in realtime under QEMU with re-designs; (requests, the image's log)."""
    run = out / "rt"
    run.mkdir()
    config = BootConfig(mode="realtime", lqg_period=0.02, status_rate=10.0)
    with Board(elf, run, config=config, lockstep=False) as board:
        cmd = Commander(board.link())
        requests = redesigns(cmd, seconds)
        cmd.control(COMMAND_GROUND)   # ground, then shutdown
        cmd.control(COMMAND_SHUTDOWN)
        for _ in cmd.link.frames(2.0):
            pass
        status = board.exit_status(60)
        log = board.log()
    assert status == 0, log
    return requests, log


def realtime_line(seconds: float, requests: int, log: str) -> None:
    summary: dict[str, Any] = {m.group(1): kv(m.group(2)) for m in re.finditer(r"fcc summary: (\w+)(.*)", log)}
    c, m, lqg, b = summary["cdrw"], summary["missile"], summary["lqg"], summary["board"]
    print()
    print(f"realtime on QEMU (no -icount: virtual time = host clock, TCG speed), both apps, T = 0.02/0.025 s, "
          f"{seconds:g} s, {requests} re-designs requested: designs applied {lqg['designs_applied']}, "
          f"failed {lqg['designs_failed']}; overruns CDRW {c['overruns']} / missile {m['overruns']} "
          f"in {c['steps']} / {m['steps']} steps; worst step {c['worst_exec_us']} / {m['worst_exec_us']} µs; "
          f"longest design slice {b['design_slice_worst_us']} µs, slices run without room "
          f"{b['design_slices_forced']} (host-speed emulation, not 168 MHz)")


def size_line(path: Path) -> None:
    size = path.read_text().split("\n")[1].split()
    text, data, bss = (int(x) for x in size[:3])
    print(f"fcc_m4f.elf: flash {text + data:,} B (text {text:,} + data {data:,}), static RAM {data + bss:,} B "
          f"(incl. the 16 kB stack and 8 kB of UART rings); linked for 1 MB flash / 128 kB RAM")


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.bench.pil", description=__doc__.splitlines()[0])
    p.add_argument("out", type=Path, help="holds bench.log and size; the realtime run goes to OUT/rt")
    p.add_argument("elf", type=Path, help="fcc_m4f.elf")
    p.add_argument("--rt-seconds", type=float, default=10.0)
    p.add_argument("--lockstep-steps", type=int, default=200)
    a = p.parse_args(argv)
    rec, designs = read_bench_log(a.out / "bench.log")
    counts_table(rec, designs)
    budget(rec, designs)
    ms, board = lockstep(a.out, a.elf, a.lockstep_steps)
    lockstep_line(a.lockstep_steps, ms, board)
    requests, log = realtime(a.out, a.elf, a.rt_seconds)
    realtime_line(a.rt_seconds, requests, log)
    size_line(a.out / "size")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
