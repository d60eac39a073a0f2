"""fcc's command line and image properties that need no bus (issue 6): help, bad
flags and values (one line, exit 2), a missing interface (one line, exit 1), and
no heap anywhere in the firmware objects or the Cortex-M4F image.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from conftest import build_dir

HEAP = ("malloc", "calloc", "realloc", "free", "_malloc_r", "_free_r", "_calloc_r",
        "_realloc_r", "aligned_alloc", "posix_memalign")


def run(binary: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(binary), *args], capture_output=True, text=True, timeout=10)


def test_help(bin_path):
    r = run(bin_path("fcc"), "--help")
    assert r.returncode == 0
    for flag in ("--iface", "--mode", "--apps", "--duration", "--lqg-period", "--lqg-bits",
                 "--stale-limit", "--window", "--ridge", "--q-normal", "--q-fault", "--zkf-order",
                 "--fault-policy", "--detector", "--margin", "--x0", "--p0", "--e", "--f",
                 "--status-rate"):
        assert flag in r.stdout, flag


@pytest.mark.parametrize("args, words", [
    (["--bogus"], "unknown option '--bogus'"),
    (["--mode", "fast"], "--mode"),
    (["--apps", "cdrw,boat"], "--apps"),
    (["--apps", ""], "--apps"),
    (["--lqg-period", "0.5"], "0.02..0.3"),
    (["--lqg-period", "nan"], "not a finite number"),
    (["--lqg-bits", "1"], "2..16"),
    (["--lqg-bits", "17"], "2..16"),
    (["--stale-limit", "-1"], "non-negative integer"),
    (["--window", "1000"], "--window"),
    (["--zkf-order", "5000"], "--zkf-order"),
    (["--detector", "magic"], "--detector"),
    (["--fault-policy", "ignore"], "--fault-policy"),
    (["--x0", "1,2,3"], "--x0"),
    (["--p0", "1,2,3"], "--p0"),
    (["--f", "0"], "configuration refused"),
    (["--duration", "-1"], "--duration"),
    (["--gyro-var", "-0.8"], "--gyro-var"),
    (["--window"], "needs a value"),
    (["stray"], "unexpected argument"),
])
def test_bad_command_line_is_one_line_and_exit_2(bin_path, args, words):
    r = run(bin_path("fcc"), *args)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("fcc: "), r.stderr
    assert words in lines[0]


def test_missing_interface_at_start_up(bin_path):
    r = run(bin_path("fcc"), "--iface", "nosuch7", "--duration", "1")
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "cannot open CAN interface 'nosuch7'" in lines[0]


def undefined_symbols(nm: str, path: Path) -> set[str]:
    out = subprocess.run([nm, "-u", str(path)], capture_output=True, text=True, check=True).stdout
    return {line.split()[-1] for line in out.splitlines() if line.strip()}


def test_no_heap_in_the_firmware_objects_and_the_fcc_image():
    build = build_dir()
    core = build / "firmware" / "libfcc_core.a"
    port = build / "firmware" / "port" / "linux" / "libfcc_port_linux.a"
    host = sorted((build / "firmware" / "host").rglob("*.o"))
    assert core.exists() and port.exists() and host, f"build {build} first"
    for path in (core, port, *host):
        assert not undefined_symbols("nm", path) & set(HEAP), path
    # the linked executable: glibc's own stdio may use the heap, but nothing of ours asks for it
    assert not undefined_symbols("nm", build / "bin" / "fcc") & set(HEAP)


def test_no_heap_in_the_cortex_m4f_image(repo):
    m4f = Path(os.environ.get("FCC_M4F_BUILD_DIR", repo / "build-m4f")) / "bin" / "fcc_m4f.elf"
    nm = shutil.which("arm-none-eabi-nm")
    if nm is None or not m4f.exists():
        pytest.skip(f"no Cortex-M4F image at {m4f} (scripts/test cross builds it)")
    out = subprocess.run([nm, str(m4f)], capture_output=True, text=True, check=True).stdout
    symbols = {line.split()[-1] for line in out.splitlines() if line.strip()}
    assert not symbols & (set(HEAP) | {"_sbrk", "sbrk"})
    # and the image really holds both applications
    assert {"fcc_node_run_step", "fcc_app_sid_step", "fcc_app_msl_step", "fcc_sid_step",
            "fcc_lqg_design", "fcc_lqg_ctrl_step"} <= symbols
