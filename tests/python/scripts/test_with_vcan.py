"""scripts/with-vcan's User-Mode Linux path: output as it is written, the exit status, and no
process of the guest left behind whichever signal stops it."""
from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
WITH_VCAN = ROOT / "scripts" / "with-vcan"
UML = Path(os.environ.get("WITH_VCAN_UML_DIR") or ROOT / ".uml")

pytestmark = pytest.mark.skipif(not (UML / "linux.uml").exists(),
                                reason="no User-Mode Linux provisioned (scripts/setup)")


def start(*cmd: str) -> subprocess.Popen[str]:
    return subprocess.Popen([str(WITH_VCAN), "--uml", *cmd], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True)


def guest_group(with_vcan_pid: int) -> int:
    """The process group of the guest (its kernel's pid: with-vcan starts it with setsid)."""
    for proc in Path("/proc").iterdir():
        if proc.name.isdigit():
            try:
                args = (proc / "cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if f"umid=wv{with_vcan_pid}".encode() in args:
                return int(proc.name)
    raise AssertionError("no UML kernel of this with-vcan")


def live_members(group: int) -> list[int]:
    """Processes of the group that still run (a zombie waits only for its reaper)."""
    out = []
    for proc in Path("/proc").iterdir():
        if proc.name.isdigit():
            try:
                fields = (proc / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[2]) == group and fields[0] != "Z":
                out.append(int(proc.name))
    return out


def test_output_arrives_while_the_command_runs_and_the_status_comes_back(tmp_path):
    go = tmp_path / "go"
    p = start("sh", "-c", f'echo first; echo to-stderr >&2; while [ ! -e {go} ]; do sleep 0.05; done; '
                          f'[ -t 1 ] || echo "not a terminal"; echo "$WITH_VCAN_UML"; exit 7')
    try:
        assert p.stdout is not None and p.stderr is not None
        assert p.stdout.readline() == "first\n"      # before the command can end: it waits for go
        go.touch()
        rest = p.stdout.read().splitlines()
        assert p.wait(120) == 7
    finally:
        p.kill()
    assert rest[0] == "not a terminal"               # ours is a pipe: so is the command's
    release, mode = rest[1].split()
    assert release == (UML / "release").read_text().strip() and mode in ("seccomp", "ptrace")
    assert "to-stderr" in p.stderr.read()


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_a_signal_stops_the_guest_and_everything_in_it(sig):
    p = start("sh", "-c", "sleep 300 & sleep 300 & echo started; wait")
    try:
        assert p.stdout is not None and p.stdout.readline() == "started\n"
        group = guest_group(p.pid)
        assert len(live_members(group)) >= 3            # the kernel and its processes
        p.send_signal(sig)
        assert p.wait(60) == 128 + sig
        deadline = time.monotonic() + 30
        while live_members(group) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert live_members(group) == []
    finally:
        if p.poll() is None:
            p.kill()


def boot_log() -> str:
    out = subprocess.run([str(WITH_VCAN), "--uml", "dmesg"], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_the_boot_skips_the_measurements_the_guest_does_not_need():
    """The RAID-6 benchmark is never run; the delay loop is calibrated once per CPU model (lpj
    kept in the kernel's directory), and a kept value that is not a number is not used."""
    kept = UML / "lpj"
    before = kept.read_bytes() if kept.exists() else None
    try:
        kept.write_text("not-a-number whatever CPU\n")
        first = boot_log()
        assert "initcall raid6_init blacklisted" in first and "raid6: using" not in first
        assert "Calibrating delay loop... " in first and "preset value" not in first
        lpj = kept.read_text().split()[0]
        assert lpj.isdigit() and f"lpj={lpj})" in first
        second = boot_log()
        assert "Calibrating delay loop (skipped) preset value.. " in second and f"lpj={lpj})" in second
    finally:
        if before is None:
            kept.unlink(missing_ok=True)
        else:
            kept.write_bytes(before)
