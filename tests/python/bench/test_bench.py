"""The benchmarks' Python (hil.bench) on tiny inputs, and every scripts/bench.d part's --help:
each bench's code path runs here in seconds, without valgrind, QEMU or the bus (those are
the benches' own runs, `scripts/bench NAME`)."""
from __future__ import annotations

import importlib
import json
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO

import hil.bench
from hil.bench import fcc_bus, fcc_table, lqg, pil, sid

BENCH_MODULES = sorted(m.name for m in pkgutil.iter_modules(hil.bench.__path__))
PARTS = sorted(p for p in (REPO / "scripts" / "bench.d").iterdir() if p.is_file())


@pytest.mark.parametrize("name", BENCH_MODULES)
def test_module_helps(name: str) -> None:
    r = subprocess.run([sys.executable, "-m", f"hil.bench.{name}", "--help"], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("usage:"), r.stdout[:80]


@pytest.mark.parametrize("part", PARTS, ids=lambda p: p.name)
def test_part_helps(part: Path) -> None:
    r = subprocess.run([str(part), "--help"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith(f"{part.name} -- "), r.stdout[:80]


def test_every_module_is_importable() -> None:
    for name in BENCH_MODULES:
        importlib.import_module(f"hil.bench.{name}")


def test_sid_times_every_scenario(capsys: pytest.CaptureFixture[str]) -> None:
    assert sid.main(["2"]) == 0
    got = [line.split()[0] for line in capsys.readouterr().out.splitlines()]
    assert got == list(sid.SCENARIOS)


def test_fcc_bus_turnarounds_from_a_candump_log(tmp_path: Path) -> None:
    log = tmp_path / "bus.log"
    log.write_text(f"(1.000000) vcan0 {fcc_bus.MSL_ACCEL_ID:03X}#0000000000000000\n"
                   f"(1.000100) vcan0 {fcc_bus.TICK_ID:03X}#0000000000000000\n"
                   f"(1.000300) vcan0 {fcc_bus.CMD_ID:03X}#0000000000000000\n"
                   f"(1.001000) vcan0 {fcc_bus.PING_ID:03X}#0000000000000000\n"
                   f"(1.001050) vcan0 {fcc_bus.PONG_ID:03X}#0000000000000000\n")
    got = fcc_bus.turnarounds(fcc_bus.read_candump(log))
    assert fcc_bus.pct(got["tick_to_cmd"], 0.5) == pytest.approx(200.0)
    assert fcc_bus.pct(got["sensor_to_cmd"], 0.5) == pytest.approx(300.0)
    assert fcc_bus.pct(got["ping_to_pong"], 0.99) == pytest.approx(50.0)
    assert fcc_bus.summary("fcc summary: latency_us missile n=3 p50=10 p99=20") == \
        {"latency_us missile": {"n": 3.0, "p50": 10.0, "p99": 20.0}}


def test_fcc_table_prints_every_part(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "callgrind.txt").write_text(
        "app=cdrw steps=10 ir_total=1000 ir_sid=500 ir_lqg=0 ir_receive=100 ir_encode=50 ir_auth=30\n")
    (tmp_path / "wall.cdrw").write_text("wall_us_per_step=1.5 node_bytes=4096\n")
    (tmp_path / "mac.txt").write_text("frames=10 ir_total=100 ir_cmac=80 ir_aes=60\n")
    (tmp_path / "size.host").write_text("   text    data     bss     dec     hex filename\n"
                                        "    100       4       8     112      70 fcc_node.c.o\n")
    stats = {"n": 3, "p50": 10.0, "p99": 20.0, "max": 30.0}
    rt = {f"{k}_us {app}": stats for k in ("jitter", "exec") for app in ("cdrw", "missile")}
    rt.update({app: {"steps": 5, "overruns": 0} for app in ("cdrw", "missile")})
    rt["latency_us missile"] = stats
    (tmp_path / "vcan.json").write_text(json.dumps({
        "lock": {"missile": {"steps": 5}, "latency_us missile": stats}, "startup_ms": 12.0,
        **{k: {"n": 3, "p50": 10.0, "p99": 20.0} for k in ("tick_to_cmd", "sensor_to_cmd", "ping_to_pong")},
        "rt": rt, "rt_seconds": 1.0, "rt_prio": "0"}))
    assert fcc_table.main([str(tmp_path)]) == 0
    out = capsys.readouterr().out
    for part in ("1. instructions per step", "2. latency on vcan0", "3. realtime", "4. size"):
        assert part in out
    assert "app 100 text" in out


def test_pil_tables_from_a_bench_log(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "bench.log").write_text(
        "pil calib loop_insns=2000000 measured_insns=2000040\n"
        "pil cdrw_normal mean_insns=1000 max_insns=2000\npil cdrw_fault mean_insns=3000 max_insns=4000\n"
        "pil missile mean_insns=500 max_insns=600\n"
        "pil design t_ms=20 total_insns=900000 max_slice_insns=120000\n"
        "pil boot insns=50000\npil memory stack_used=4000 node_bytes=9000\npil done\n")
    rec, designs = pil.read_bench_log(tmp_path / "bench.log")
    pil.counts_table(rec, designs)
    pil.budget(rec, designs)
    (tmp_path / "size").write_text("   text    data     bss     dec     hex filename\n"
                                   "  60000    1000   30000   91000   16378 fcc_m4f.elf\n")
    pil.size_line(tmp_path / "size")
    out = capsys.readouterr().out
    assert "LQG re-design T = 0.02 s" in out and "fits" in out and "flash 61,000 B" in out


def test_lqg_reference_designs() -> None:
    gen = lqg.reference_module()
    poles, est = lqg.scipy_design(gen, 0.1)
    assert max(abs(poles)) < 1 and max(abs(est)) < 1
    cl, _ = lqg.control_design(gen, 0.1)
    assert sorted(abs(cl)) == pytest.approx(sorted(abs(poles)), rel=1e-6)


def test_lqg_speed_up_is_taken_against_one_solver(capsys: pytest.CaptureFixture[str],
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    ir = {"hamiltonian_design": 400, "hamiltonian_dbl": 100, "hamiltonian_c2d": 50,
          "hamiltonian_ham": 200, "hamiltonian_total": 900, "doubling_design": 450}
    assert lqg.one_solver(ir, 40e-6) == (300, pytest.approx(30e-6))
    for v in lqg.BLAS_THREAD_VARIABLES:
        monkeypatch.delenv(v, raising=False)
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "1")
    lqg.table(0.1, ir, 40e-6, 3e-3, 6e-3)
    out = capsys.readouterr().out
    assert "BLAS threads: OPENBLAS_NUM_THREADS=1" in out
    assert "over scipy: 100x, over python-control: 200x" in out
