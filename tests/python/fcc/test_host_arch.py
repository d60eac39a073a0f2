"""-DFCC_HOST_ARCH=x86-64-v3 (cmake/host-arch.cmake): the host tools built for AVX2/FMA give
the portable build's outputs bit for bit (no FMA contraction, no reordered sums); a CPU without
the level is refused in one line, at configure time and by every program at its start.

The v3 tools are built here (lqg_design and sid_replay only, the build type and real type of
FCC_BUILD_DIR) and compared with FCC_BUILD_DIR's.
"""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from hil.reference.flight import synthetic_flight

from conftest import REPO, build_dir

LEVEL = "x86-64-v3"
TOOLS = ("lqg_design", "sid_replay")


def cpu_flags(cpuinfo: Path = Path("/proc/cpuinfo")) -> set[str]:
    m = re.search(r"^flags\s*:(.*)$", cpuinfo.read_text(), re.M)
    return set(m.group(1).split()) if m else set()


def cache_value(name: str, default: str) -> str:
    m = re.search(rf"^{name}:\w+=(.*)$", (build_dir() / "CMakeCache.txt").read_text(), re.M)
    return m.group(1) if m else default


def configure(out: Path, *extra: str) -> subprocess.CompletedProcess:
    return subprocess.run(["cmake", "-S", str(REPO), "-B", str(out), "-G", "Ninja", *extra],
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def v3_bin(tmp_path_factory) -> Path:
    if not {"avx2", "fma", "bmi2"} <= cpu_flags():
        pytest.skip(f"this CPU has no {LEVEL} (AVX2, FMA, BMI2)")
    out = tmp_path_factory.mktemp("build-v3")
    r = configure(out, f"-DFCC_HOST_ARCH={LEVEL}",
                  f"-DCMAKE_BUILD_TYPE={cache_value('CMAKE_BUILD_TYPE', 'RelWithDebInfo')}",
                  f"-DFCC_REAL={cache_value('FCC_REAL', 'double')}")
    assert r.returncode == 0, r.stderr
    r = subprocess.run(["cmake", "--build", str(out), "--target", *TOOLS], capture_output=True,
                       text=True, timeout=900)
    assert r.returncode == 0, r.stdout[-2000:]
    return out / "bin"


def run(tool: Path, *args: str, stdin: str | None = None) -> str:
    r = subprocess.run([str(tool), *args], input=stdin, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_v3_tools_use_avx_and_no_fma(v3_bin):
    """The option reaches the compiler (256-bit registers), and no a*b+c became one FMA
    (-mno-fma: GCC 12 fuses vectorised complex products even with -ffp-contract=off)."""
    if shutil.which("objdump") is None:
        pytest.skip("no objdump")
    for tool in TOOLS:
        dis = subprocess.run(["objdump", "-d", str(v3_bin / tool)], capture_output=True,
                             text=True, check=True).stdout
        assert "%ymm" in dis, tool
        assert not re.search(r"\bvfn?m(add|sub)", dis), tool


@pytest.mark.parametrize("args", [("--period", "0.1"), ("--period", "0.05", "--bits", "8"),
                                  ("--period", "0.2", "--delay", "0.05"), ("--period", "0.02")])
def test_lqg_design_same_bits(v3_bin, bin_path, args):
    assert run(v3_bin / "lqg_design", *args) == run(bin_path("lqg_design"), *args)


@pytest.mark.parametrize("args", [(), ("--mls-intercept",), ("--filter", "azkf")])
def test_sid_replay_same_bits(v3_bin, bin_path, args):
    csv = synthetic_flight().csv()
    v3 = run(v3_bin / "sid_replay", *args, stdin=csv)
    assert v3 == run(bin_path("sid_replay"), *args, stdin=csv) and len(v3.splitlines()) > 100


def test_configure_refuses_a_cpu_without_the_level(tmp_path):
    fake = tmp_path / "cpuinfo"
    fake.write_text("processor\t: 0\nflags\t\t: fpu sse sse2 ssse3 sse4_1 sse4_2 popcnt\n")
    r = configure(tmp_path / "b", f"-DFCC_HOST_ARCH={LEVEL}", f"-DFCC_CPUINFO={fake}")
    err = " ".join(r.stderr.split())            # cmake wraps its messages
    assert r.returncode != 0
    assert f"FCC_HOST_ARCH={LEVEL}: this CPU ({fake}) lacks" in err and "avx2" in err
    r = configure(tmp_path / "c", "-DFCC_HOST_ARCH=pentium4")
    assert r.returncode != 0 and "must be x86-64-v2, x86-64-v3 or x86-64-v4" in " ".join(r.stderr.split())


def test_a_program_on_a_cpu_without_it_says_so_in_one_line(tmp_path):
    """The check every v3 program runs before main, built for a feature this CPU lacks (AMX:
    the level's own check cannot fail on a machine that builds it)."""
    if "amx_tile" in cpu_flags():
        pytest.skip("this CPU has AMX")
    main = tmp_path / "main.c"
    main.write_text("int main(void) { return 0; }\n")
    exe = tmp_path / "prog"
    subprocess.run(["cc", "-std=c99", "-pedantic", "-Wall", "-Wextra", "-Werror",
                    '-DFCC_HOST_ARCH_NAME="amx-tile"', str(REPO / "cmake" / "host_arch_check.c"),
                    str(main), "-o", str(exe)], check=True)
    r = subprocess.run([str(exe)], capture_output=True, text=True)
    assert r.returncode == 1 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and "built for amx-tile (-DFCC_HOST_ARCH)" in r.stderr
