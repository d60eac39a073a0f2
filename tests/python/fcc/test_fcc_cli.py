"""fcc's command line and image properties that need no bus (issue 6): help, bad
flags and values (one line, exit 2), a missing interface (one line, exit 1), the
identification options shared with sid_replay (same options, same usage block,
same error words), and no heap anywhere in the firmware objects or the
Cortex-M4F image.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from conftest import build_dir
from hil.bus.secoc import TEST_KEY_FILE

HEAP = ("malloc", "calloc", "realloc", "free", "_malloc_r", "_free_r", "_calloc_r",
        "_realloc_r", "aligned_alloc", "posix_memalign")


def run(binary: Path, *args: str, key: bool = True) -> subprocess.CompletedProcess[str]:
    """Run a program; fcc gets the published test key unless key=False or --help."""
    if key and binary.name == "fcc" and "--help" not in args:
        args = ("--key-file", str(TEST_KEY_FILE), *args)
    return subprocess.run([str(binary), *args], capture_output=True, text=True, timeout=10)


@pytest.mark.parametrize("key_text, words", [
    (None, "--key-file PATH is required"),
    ("0011\n", "one line of 32 hex digits"),
    ("00112233445566778899aabbccddeeff\n00112233445566778899aabbccddeeff\n", "one line"),
    ("zz112233445566778899aabbccddeeff\n", "one line"),
])
def test_key_file_required_and_checked(bin_path, tmp_path, key_text, words):
    args: tuple[str, ...] = ("--iface", "nosuch7")
    if key_text is not None:
        (tmp_path / "k").write_text(key_text)
        args = ("--key-file", str(tmp_path / "k"), *args)
    r = run(bin_path("fcc"), *args, key=False)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("fcc: ") and words in lines[0], r.stderr


def test_test_key_is_announced(bin_path, tmp_path):
    r = run(bin_path("fcc"), "--iface", "nosuch7")
    assert r.returncode == 1 and "WARNING: --key-file holds the published test key" in r.stderr
    (tmp_path / "k").write_text("# a real key\n" + "5a" * 16 + "\n")
    r = run(bin_path("fcc"), "--key-file", str(tmp_path / "k"), "--iface", "nosuch7", key=False)
    assert r.returncode == 1 and "WARNING" not in r.stderr


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
    (["--max-fault", "-2"], "--max-fault"),
    (["--prior", "1,0,0,1,0,0,0"], "6 or 8 finite numbers"),
    (["--no-arm-on-prior=1"], "takes no value"),
    (["--mls-intercept", "x"], "unexpected argument"),
])
def test_bad_command_line_is_one_line_and_exit_2(bin_path, args, words):
    r = run(bin_path("fcc"), *args)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("fcc: "), r.stderr
    assert words in lines[0]


@pytest.mark.parametrize("args, words", [
    (["--bogus"], "unknown option '--bogus'"),
    (["--lqg-period", "0.5"], "0.02..0.3"),
    (["--mode", "realtime", "--lqg-period", "0.05", "--lqg-delay", "0.06"], "shorter than the period"),
])
def test_check_args(bin_path, tmp_path, args, words):
    """--check-args: fcc's own option table judges the options, opens nothing (no interface,
    no key needed) and exits 0, or 2 with its one line."""
    ok = run(bin_path("fcc"), "--check-args", "--iface", "nosuch7", "--detector", "oracle", key=False)
    assert ok.returncode == 0 and ok.stdout == "" and ok.stderr == "", ok
    bad = run(bin_path("fcc"), "--check-args", "--iface", "nosuch7", *args, key=False)
    lines = bad.stderr.strip().splitlines()
    assert bad.returncode == 2 and len(lines) == 1 and lines[0].startswith("fcc: ") and words in lines[0], bad
    bad_key = run(bin_path("fcc"), "--check-args", "--key-file", str(tmp_path / "no-such-key"),
                  key=False)                                    # a key given is read (and refused)
    assert bad_key.returncode == 2 and "no-such-key" in bad_key.stderr


# The identification options sid_replay has and fcc had not: with a missing
# interface, fcc gets past the command line and the firmware's configuration
# check (exit 2) and stops only at the bus (exit 1).
NEW_SID_OPTIONS = (
    ["--mls-intercept"],
    ["--no-arm-on-prior"],
    ["--max-fault", "0"],
    ["--max-fault=25"],
    ["--prior", "0.97,0.02,-0.4,0.94,-0.004,-0.6,0.001,-0.002"],
    ["--mls-intercept", "--prior", "0.97,0.02,-0.4,0.94,-0.004,-0.6"],
    ["--window", "10"],  # the default min-transitions (20) follows the window, as in sid_replay
)


@pytest.mark.parametrize("args", NEW_SID_OPTIONS)
def test_accepts_the_identification_options_of_sid_replay(bin_path, args):
    r = run(bin_path("fcc"), "--iface", "nosuch7", "--duration", "1", *args)
    assert r.returncode == 1, r.stderr
    assert "cannot open CAN interface 'nosuch7'" in r.stderr


def identification_block(help_text: str) -> list[str]:
    """The shared usage block: its header line and the indented lines under it."""
    lines = help_text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("identification options"))
    end = start + 1
    while end < len(lines) and not lines[end].startswith("  --"):
        end += 1  # the header's own continuation line
    while end < len(lines) and lines[end].startswith("  "):
        end += 1
    return lines[start:end]


def test_both_help_texts_hold_the_same_identification_block(bin_path):
    fcc = run(bin_path("fcc"), "--help")
    replay = run(bin_path("sid_replay"), "--help")
    assert fcc.returncode == 0 and replay.returncode == 0
    block = identification_block(fcc.stdout)
    assert block == identification_block(replay.stdout)
    text = "\n".join(block)
    for flag in ("--window", "--min-transitions", "--ridge", "--max-cond", "--max-rho", "--prior",
                 "--mls-intercept", "--no-mls-hold", "--no-arm-on-prior", "--zkf-order",
                 "--q-normal", "--q-fault", "--fault-policy", "--detector", "--margin", "--raise",
                 "--hold", "--clear", "--max-fault", "--x0", "--p0", "--e", "--f"):
        assert flag + " " in text, flag
    assert "[,c1,c2]" in text  # the 8-value prior
    # the programs' own options stay out of it
    for flag in ("--iface", "--lqg-period", "--filter", "--mls-only", "--fixed-model"):
        assert flag not in text, flag


@pytest.mark.parametrize("args", [
    ["--window", "1000"], ["--window", "3"], ["--min-transitions", "x"], ["--ridge", "-1"],
    ["--max-cond", "nan"], ["--prior", "1,2,3"], ["--zkf-order", "5000"], ["--q-normal", "1"],
    ["--fault-policy", "drop"], ["--detector", "magic"], ["--margin", "0"], ["--raise", "0"],
    ["--max-fault", "x"], ["--x0", "1"], ["--p0", "1,2,3"], ["--e", ""], ["--no-mls-hold=1"],
])
def test_both_programs_refuse_a_bad_identification_option_in_the_same_words(bin_path, args):
    fcc = run(bin_path("fcc"), *args)
    replay = subprocess.run([str(bin_path("sid_replay")), *args], input="", capture_output=True,
                            text=True, timeout=10)
    assert fcc.returncode == 2 and replay.returncode == 2
    assert fcc.stderr.startswith("fcc: ") and replay.stderr.startswith("sid_replay: ")
    assert fcc.stderr.removeprefix("fcc: ") == replay.stderr.removeprefix("sid_replay: ")
    assert len(fcc.stderr.strip().splitlines()) == 1 and args[0].split("=")[0] in fcc.stderr


def test_missing_interface_at_start_up(bin_path, tmp_path):
    (tmp_path / "k").write_text("5a" * 16 + "\n")   # not the test key: no warning line
    r = run(bin_path("fcc"), "--key-file", str(tmp_path / "k"), "--iface", "nosuch7",
            "--duration", "1", key=False)
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
    cli = build / "firmware" / "cli" / "libfcc_cli_common.a"
    host = sorted((build / "firmware" / "port" / "linux").rglob("*.o"))
    assert core.exists() and port.exists() and cli.exists() and host, f"build {build} first"
    for path in (core, port, cli, *host):
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
            "fcc_lqg_design_delayed", "fcc_lqg_ctrl_step"} <= symbols
