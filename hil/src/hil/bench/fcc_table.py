"""scripts/bench.d/fcc's table: the numbers its parts left in OUT (callgrind.txt, wall.APP,
mac.txt, tsync.txt, hb.txt from part 1; vcan.json from hil.bench.fcc_bus; size.* from part 4), printed.

    python -m hil.bench.fcc_table OUT
"""
from __future__ import annotations

import argparse
import json
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from hil.bus.apps import APP_NAMES


def kv(text: str) -> dict[str, float]:
    """The KEY=NUMBER pairs of a line."""
    return {k: float(x) for k, x in re.findall(r"(\w+)=([-\d.]+)", text)}


#: callgrind's counter of each application's own maths (firmware/tools: the SID filters, the LQG)
MATHS_COUNTER = {"cdrw": "ir_sid", "missile": "ir_lqg"}
#: what an application's step authenticates besides the tick (both authenticate their outputs)
AUTH_NOTE = {"cdrw": "", "missile": ", command authenticated"}


def instructions(out: Path) -> None:
    """1. instructions per step (callgrind) and the cost of one authenticator."""
    print("fcc benchmark")
    print("\n1. instructions per step, frames in -> frames out (callgrind, host x86-64, double)")
    print(f"   {'app':<9}{'steps':>6}{'Ir/step':>10}{'maths':>10}{'rx+checks':>11}{'encode':>9}{'wall us':>9}")
    for line in (out / "callgrind.txt").read_text().splitlines():
        c = kv(line)
        app = line.split()[0].split("=")[1]
        w = kv((out / f"wall.{app}").read_text())
        maths = c[MATHS_COUNTER[app]]
        n = c["steps"]
        print(f"   {app:<9}{int(n):>6}{c['ir_total'] / n:>10.0f}{maths / n:>10.0f}{c['ir_receive'] / n:>11.0f}"
              f"{c['ir_encode'] / n:>9.0f}{w['wall_us_per_step']:>9.2f}")
        print(f"   {'':<9}{'':>6}{'':>10}  of which SecOC authentication (tick verified"
              f"{AUTH_NOTE[app]}): {c['ir_auth'] / n:.0f}")
    print("   (cdrw: MLS + KF + ZKF(q=1000) + AZKF on a pull-up with a 0.1 s spike at 4 s, 12 output frames;")
    print("    missile: Kalman update + LQR + D/A + propagation, 2 output frames + the command's authenticator;")
    print("    both + FCC_ACK; the SIM_TICK arrives with its authenticator)")
    m = kv((out / "mac.txt").read_text())
    print(f"   one authenticator (48-bit AES-128-CMAC over data ID + 8 bytes + 64-bit freshness, 2 AES blocks):"
          f" {m['ir_total'] / m['frames']:.0f} Ir per frame (CMAC {m['ir_cmac'] / m['frames']:.0f},"
          f" AES {m['ir_aes'] / m['frames'] / 2:.0f} per block)")
    tsync = out / "tsync.txt"
    for line in (tsync.read_text().splitlines() if tsync.exists() else []):
        t = kv(line)
        forged = "tsync-forged" in line
        print(f"   one sync interval (SYNC + FOLLOW_UP + TSYNC_AUTH -> servo"
              f"{', behind a forged pair: 4 MACs' if forged else ''}): {t['ir_total'] / t['n']:.0f} Ir"
              f" (authentication {t['ir_auth'] / t['n']:.0f}, servo {t['ir_servo'] / t['n']:.0f})")
    hb = out / "hb.txt"
    if hb.exists():
        h = kv(hb.read_text())
        print(f"   one heartbeat (9 frames + FCC_STATUS_AUTH): {h['ir_total'] / h['n']:.0f} Ir"
              f" (MAC {h['ir_mac'] / h['n']:.0f})")


def latency(v: dict[str, Any]) -> None:
    """2. lockstep latency on vcan0, fcc beside can_echo."""
    lock = v["lock"]
    print(f"\n2. latency on vcan0 (UML), lockstep, missile, {int(lock['missile']['steps'])} steps, "
          f"can_echo on the same bus in the same run [us]")
    print(f"   {'measure':<58}{'n':>6}{'p50':>8}{'p99':>8}")
    for key, label in (("tick_to_cmd", "SIM_TICK -> MSL_ELEV_CMD (kernel stamps)"),
                       ("sensor_to_cmd", "MSL_ACCELEROMETER -> MSL_ELEV_CMD (kernel stamps)"),
                       ("ping_to_pong", "RIG_PING -> RIG_PONG by can_echo (kernel stamps)")):
        r = v[key]
        print(f"   {label:<58}{r['n']:>6}{r['p50']:>8.0f}{r['p99']:>8.0f}")
    lat = lock["latency_us missile"]
    print(f"   {'fcc internal: sensor kernel rx stamp -> command sent':<58}"
          f"{int(lat['n']):>6}{lat['p50']:>8.0f}{lat['p99']:>8.0f}")
    ratio = v["tick_to_cmd"]["p50"] / v["ping_to_pong"]["p50"]
    print(f"   fcc turnaround / echo turnaround (p50): {ratio:.2f} (target <= 1.5)")
    print(f"   start-up, exec -> first heartbeat on the bus: {v['startup_ms']:.0f} ms")


def realtime(v: dict[str, Any]) -> None:
    """3. realtime jitter, execution time, data age."""
    rt = v["rt"]
    prio = "SCHED_FIFO " + str(v["rt_prio"]) if v["rt_prio"] != "0" else "normal scheduling"
    print(f"\n3. realtime, both applications at 50 Hz, {v['rt_seconds']:.0f} s, {prio}, fed by a python simulator [us]")
    print(f"   {'app':<9}{'steps':>7}{'overruns':>9}{'jit p50':>9}{'jit p99':>9}{'jit max':>9}"
          f"{'exec p50':>9}{'exec p99':>9}{'exec max':>9}")
    for app in (name for name in APP_NAMES if name in rt):
        j, e, a = rt[f"jitter_us {app}"], rt[f"exec_us {app}"], rt[app]
        print(f"   {app:<9}{int(a['steps']):>7}{int(a['overruns']):>9}{j['p50']:>9.0f}{j['p99']:>9.0f}{j['max']:>9.0f}"
              f"{e['p50']:>9.0f}{e['p99']:>9.0f}{e['max']:>9.0f}")
    age = rt["latency_us missile"]
    print(f"   data age at use (sensor rx -> command sent, time-triggered): p50 {age['p50']:.0f}, p99 {age['p99']:.0f}")


def size_rows(path: Path) -> list[tuple[int, int, int, str]]:
    """The rows of `size --format=berkeley`: (text, data, bss, file name)."""
    rows = []
    for line in path.read_text().splitlines()[1:]:
        f = line.split()
        if len(f) >= 6 and f[0].isdigit():
            rows.append((int(f[0]), int(f[1]), int(f[2]), f[5]))
    return rows
def by_module(rows: list[tuple[int, int, int, str]]) -> dict[str, list[int]]:
    """text, data, bss summed by the firmware's modules."""
    mods: dict[str, list[int]] = {}
    for t, d, b, name in rows:
        n = re.sub(r"\.c\.o(bj)?$", "", name)
        mod = ("app" if n in ("fcc_event", "fcc_sensor", "fcc_app_sid", "fcc_app_msl", "fcc_node") else
               "bus" if n in ("fcc_e2e", "fcc_bus", "fcc_hil", "fcc_bus_msgs", "fcc_secoc") else
               "crypto" if n in ("fcc_aes", "fcc_cmac") else
               "lqg" if n.startswith(("fcc_c2d", "fcc_dare", "fcc_lqg")) else
               "linalg" if n.startswith("fcc_mat") else "core" if n == "fcc_types" else "sid")
        m = mods.setdefault(mod, [0, 0, 0])
        m[0] += t
        m[1] += d
        m[2] += b
    return mods


def sizes(out: Path) -> None:
    """4. the firmware core's size by module, the Cortex-M4F image."""
    print("\n4. size of the firmware core [bytes] (text = flash, data + bss = static RAM)")
    for label, path in (("host x86-64 (double) fcc_core.a", out / "size.host"),
                        ("Cortex-M4F (float, -Os) fcc_core.a", out / "size.m4fcore")):
        if path.exists():
            mods = by_module(size_rows(path))
            tot = [sum(m[i] for m in mods.values()) for i in range(3)]
            print(f"   {label}: text {tot[0]}, data {tot[1]}, bss {tot[2]}  (" +
                  ", ".join(f"{k} {m[0]}" for k, m in sorted(mods.items())) + " text)")
    if (out / "size.m4f").exists():
        f = (out / "size.m4f").read_text().splitlines()[1].split()
        print(f"   Cortex-M4F image fcc_m4f.elf (both apps, node static): flash {int(f[0]) + int(f[1])}, "
              f"static RAM {int(f[1]) + int(f[2])} (text {f[0]}, data {f[1]}, bss {f[2]})")
    step = (out / "wall.cdrw").read_text()
    print(f"   node instance (host, double): {int(kv(step)['node_bytes'])} bytes, static (bss of the fcc executable)")


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.bench.fcc_table", description=__doc__.splitlines()[0])
    p.add_argument("out", type=Path, help="the directory scripts/bench.d/fcc's parts wrote into")
    out = p.parse_args(argv).out
    v = json.loads((out / "vcan.json").read_text())
    instructions(out)
    latency(v)
    realtime(v)
    sizes(out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
