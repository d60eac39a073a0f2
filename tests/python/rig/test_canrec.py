"""canrec (firmware/tools/canrec), the campaigns' bus recorder: its command line on the host;
on vcan0 (inside scripts/with-vcan) the same log as the real candump, line for line, for every
kind of frame and for a whole lockstep flight recorded by both at once; frames the kernel drops
are counted, reported and fail the log; SIGTERM writes out what was read, and a stop during the
gathering wait (-w) what was queued.

    scripts/with-vcan .venv/bin/python -m pytest -m vcan tests/python/rig/test_canrec.py
"""
from __future__ import annotations

import os
import re
import signal
import socket
import struct
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from hil.bus import load
from hil.parallel.flights import fly_campaign_flights
from hil.rig.recorder import Candump, Canrec
from hil.rig.config import RigConfig
from hil.rig.session import END_MARKER_SEQ
from rig_helpers import CDRW_1S, scenario

IFACE = "vcan0"
vcan = pytest.mark.vcan


def run(binary: Path, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(binary), *args], capture_output=True, text=True, timeout=30)


# ---- the command line (no bus needed) ---------------------------------------------------------
def test_help_says_what_it_writes(bin_path) -> None:
    r = run(bin_path("canrec"), "--help")
    assert r.returncode == 0 and r.stderr == ""
    assert r.stdout.startswith("usage: canrec [options] IFACE")
    for words in ("candump log format", "recvmmsg", "-r, --rcvbuf BYTES", "-w, --wait MS", "SO_RXQ_OVFL",
                  "exit 3"):
        assert words in r.stdout


@pytest.mark.parametrize("args, code, words", [
    ((), 2, "no interface given"),
    (("vcan0", "vcan1"), 2, "records one interface"),
    (("-b", "0", "vcan0"), 2, "-b: 0 is outside 1..256"),
    (("-w", "101", "vcan0"), 2, "-w: 101 is outside 0..100"),
    (("-x", "vcan0"), 2, "unknown option '-x'"),
    (("nosuch7",), 1, "no CAN interface nosuch7"),
])
def test_bad_command_lines_are_one_line(bin_path, args, code, words) -> None:
    r = run(bin_path("canrec"), *args)
    assert r.returncode == code
    assert r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("canrec: ") and words in r.stderr


# ---- on the bus --------------------------------------------------------------------------------
@pytest.fixture()
def fd_iface() -> Iterator[str]:
    """A vcan of this test's own with CAN FD (MTU 72), removed afterwards."""
    name = f"vcanrec{os.getpid() % 1000}"
    subprocess.run(["ip", "link", "add", "dev", name, "type", "vcan"], check=True)
    try:
        subprocess.run(["ip", "link", "set", name, "mtu", "72"], check=True)
        subprocess.run(["ip", "link", "set", name, "up"], check=True)
        yield name
    finally:
        subprocess.run(["ip", "link", "delete", name], check=False)


#: canrec as a user without CAP_NET_RAW: no packet socket, its CAN_RAW socket instead
UNPRIVILEGED = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"]


def packet_socket_inodes() -> set[str]:
    """The inodes of the packet sockets open now (/proc/net/packet's last column)."""
    with open("/proc/net/packet") as fh:
        return {ln.split()[-1] for ln in fh.read().splitlines()[1:]}


def reads_a_ring(pid: int) -> bool:
    """The process holds a packet socket (canrec's receive ring)."""
    sockets = {os.readlink(f"/proc/{pid}/fd/{fd}")[8:-1] for fd in os.listdir(f"/proc/{pid}/fd")
               if os.readlink(f"/proc/{pid}/fd/{fd}").startswith("socket:[")}
    return bool(sockets & packet_socket_inodes())


class Recorders:
    """candump -L and canrec on one interface at once, each into its own file (canrec's on its
    stdout when it runs unprivileged: it may not create a file here)."""

    def __init__(self, tmp: Path, iface: str, canrec: Path, privileged: bool = True) -> None:
        self.a, self.b = tmp / f"candump-{iface}.log", tmp / f"canrec-{iface}.log"
        self._fa = open(self.a, "w")  # noqa: SIM115 - candump writes it until it is closed after the run
        self._fb = open(self.b, "w")  # noqa: SIM115 - the same, for canrec's stdout
        self.candump = subprocess.Popen(["candump", "-L", iface], stdout=self._fa)
        cmd = [str(canrec), "-o", str(self.b), iface] if privileged else [*UNPRIVILEGED, str(canrec), iface]
        self.canrec = subprocess.Popen(cmd, stdout=subprocess.DEVNULL if privileged else self._fb,
                                       stderr=subprocess.PIPE, text=True)

    def stop(self, marker: str) -> tuple[list[str], list[str], str]:
        """After a last frame `marker` was sent: wait until both have logged it, stop both
        (canrec by SIGTERM: it must write out what it read), return both logs."""
        for _ in range(3000):  # canrec writes its file at the end: candump's tells the pace
            if self.a.read_text().rstrip().endswith(marker):
                break
            assert self.candump.poll() is None and self.canrec.poll() is None
            time.sleep(0.01)
        wait_listening(self.canrec)  # and canrec has read it
        self.candump.send_signal(signal.SIGINT)
        self.canrec.send_signal(signal.SIGTERM)
        assert self.candump.wait(10) == 0
        err = self.canrec.communicate(timeout=10)[1]
        self._fa.close()
        self._fb.close()
        assert self.canrec.returncode == 0, err
        return self.a.read_text().splitlines(), self.b.read_text().splitlines(), err


def wait_listening(proc: subprocess.Popen, timeout_loops: int = 2000) -> None:
    """Until the process sleeps (waiting on its socket) three looks in a row."""
    seen = 0
    for _ in range(timeout_loops):
        assert proc.poll() is None, "recorder exited"
        with open(f"/proc/{proc.pid}/stat", "rb") as fh:
            state = fh.read().rsplit(b")", 1)[1].split()[0]
        seen = seen + 1 if state == b"S" else 0
        if seen >= 3:
            return
        time.sleep(0.005)
    raise AssertionError("recorder did not start listening")


FRAMES = ["123#DEADBEEF", "7FF#", "000#00", "1ABCDEF0#0102", "00000005#R", "321#R", "321#R4",
          "100#0102030405060708", "1FFFFFFF#FFFFFFFFFFFFFFFF"]
FD_FRAMES = ["123##1DEAD", "7FF##0", "12345678##3" + "".join(f"{i:02X}" for i in range(16)),
             "001##2" + "AB" * 64]


@vcan
@pytest.mark.parametrize("privileged", [True, False], ids=["ring", "can_raw"])
@pytest.mark.parametrize("fd", [False, True], ids=["classic", "fd"])
def test_same_lines_as_candump_for_every_kind_of_frame(bin_path, tmp_path, request, fd, privileged) -> None:
    """With CAP_NET_RAW canrec reads a packet socket's ring, without it a CAN_RAW socket: the
    same lines either way, the receive times included."""
    iface = request.getfixturevalue("fd_iface") if fd else IFACE
    rec = Recorders(tmp_path, iface, bin_path("canrec"), privileged)
    wait_listening(rec.candump)
    wait_listening(rec.canrec)
    assert reads_a_ring(rec.canrec.pid) == privileged
    sent = FRAMES + (FD_FRAMES if fd else []) + ["7F0#FFFFFFFF00000000"]
    for f in sent:
        subprocess.run(["cansend", iface, f], check=True)
    a, b, err = rec.stop(sent[-1])
    assert err == ""
    assert len(a) == len(sent)
    assert b == a
    assert all(re.fullmatch(rf"\(\d{{10}}\.\d{{6}}\) {iface} [0-9A-F#R]+", ln) for ln in b)


@vcan
def test_count_stops_after_n_frames_to_stdout(bin_path) -> None:
    """-n N: exit 0 by itself after N frames; without -o the lines go to stdout."""
    proc = subprocess.Popen([str(bin_path("canrec")), "-n", "2", "-b", "1", IFACE],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_listening(proc)
    for f in ("0AA#01", "0AB#02", "0AC#03"):
        subprocess.run(["cansend", IFACE, f], check=True)
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0 and err == ""
    assert [ln.split()[1:] for ln in out.splitlines()] == [[IFACE, "0AA#01"], [IFACE, "0AB#02"]]


def end_marker() -> str:
    ping = load().by_name("RIG_PING")
    data = ping.encode({"seq": END_MARKER_SEQ, "t_send_us": 0})
    return f"{ping.frame_id:03X}#{data.hex().upper()}"


@vcan
def test_a_flight_recorded_by_candump_and_canrec_at_once_is_the_same_log(tmp_path) -> None:
    """The rig flies a campaign session recorded by canrec (as campaigns do) while candump,
    started before and stopped after, records the same bus: the logs are equal."""
    dump = Candump(IFACE, tmp_path / "candump.log")
    assert dump.wait_idle(10.0)
    cfg = RigConfig(out_dir=tmp_path / "rig", progress=False, plots=False, recorder="canrec")
    done = fly_campaign_flights(scenario(CDRW_1S), [(0, 0.5), (1, 0.3)], cfg)
    assert len(done.flights) == 2
    marker = end_marker().encode()
    assert dump.stop(marker)
    ours = (tmp_path / "rig" / "bus.log").read_text().splitlines()
    theirs = (tmp_path / "candump.log").read_text().splitlines()
    assert len(ours) > 2 * 51 * 12   # two flights of 51 steps, 12 identification frames a step
    assert ours[-1].endswith(marker.decode())
    assert ours == theirs


def send_frames(n: int, can_id: int = 0x555) -> int:
    """n classic frames from a raw socket of this process; how many the kernel took."""
    s = socket.socket(socket.PF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
    try:
        s.bind((IFACE,))
        s.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 1 << 22)
        sent = 0
        for i in range(n):
            frame = struct.pack("=IB3x8s", can_id, 8, i.to_bytes(8, "big"))
            try:
                s.send(frame)
                sent += 1
            except OSError:
                pass
        return sent
    finally:
        s.close()


@vcan
def test_a_stop_during_the_gathering_wait_writes_what_is_queued(bin_path, tmp_path) -> None:
    """-w 100: after a read that emptied its queue canrec sleeps 100 ms; SIGINT then makes it read
    the queue before it exits, so nothing sent before the stop is missing (the rig's end marker
    among it).  (On a slow machine the wait may be over before the signal: the same log.)"""
    log = tmp_path / "bus.log"
    proc = subprocess.Popen([str(bin_path("canrec")), "-w", "100", "-o", str(log), IFACE],
                            stderr=subprocess.PIPE, text=True)
    wait_listening(proc)
    subprocess.run(["cansend", IFACE, "0AA#01"], check=True)  # one read, then the wait
    sent = send_frames(20)
    proc.send_signal(signal.SIGINT)
    err = proc.communicate(timeout=10)[1]
    assert proc.returncode == 0 and err == ""
    lines = log.read_text().splitlines()
    assert lines[0].endswith(f" {IFACE} 0AA#01")
    assert [ln.split("#")[1] for ln in lines[1:]] == [i.to_bytes(8, "big").hex().upper() for i in range(20)]
    assert sent == 20


@vcan
def test_the_interface_going_down_during_the_wait_loses_nothing_queued(bin_path, tmp_path) -> None:
    """The kernel reports ENETDOWN before the frames still queued: canrec writes those frames,
    then says why it stopped in one line, exit 1.  (On a slow machine the wait may be over
    before the interface goes down: the same log and the same exit.)"""
    log = tmp_path / "bus.log"
    proc = subprocess.Popen([str(bin_path("canrec")), "-w", "100", "-o", str(log), IFACE],
                            stderr=subprocess.PIPE, text=True)
    try:
        wait_listening(proc)
        subprocess.run(["cansend", IFACE, "0AA#01"], check=True)  # one read, then the wait
        sent = send_frames(20)
        subprocess.run(["ip", "link", "set", IFACE, "down"], check=True)
        err = proc.communicate(timeout=10)[1]
    finally:
        subprocess.run(["ip", "link", "set", IFACE, "up"], check=True)
    assert proc.returncode == 1
    assert err == f"canrec: cannot receive from {IFACE}: Network is down\n"
    lines = log.read_text().splitlines()
    assert lines[0].endswith(f" {IFACE} 0AA#01")
    assert [ln.split("#")[1] for ln in lines[1:]] == [i.to_bytes(8, "big").hex().upper() for i in range(20)]
    assert sent == 20


class TinyCanrec(Canrec):
    """canrec with the smallest receive ring (a page: 25 frames)."""

    RING = 4096


@vcan
def test_lost_frames_are_counted_reported_and_fail_the_log(tmp_path) -> None:
    rec = TinyCanrec(IFACE, tmp_path / "bus.log")
    assert rec.wait_idle(10.0)
    os.kill(rec.pid, signal.SIGSTOP)  # it reads nothing while the frames come
    try:
        sent = send_frames(300)
    finally:
        os.kill(rec.pid, signal.SIGCONT)
    assert rec.wait_idle(10.0)  # the queue read: the marker finds room
    marker = end_marker()
    subprocess.run(["cansend", IFACE, marker], check=True)
    complete = rec.stop(marker.encode())
    assert not complete                               # the session would refuse the log
    m = re.fullmatch(r"canrec: vcan0: (\d+) frames lost in all: the log is incomplete.*",
                     rec.error())
    assert m, rec.error()
    lines = (tmp_path / "bus.log").read_text().splitlines()
    recorded = sum(1 for ln in lines if " 555#" in ln)
    assert 0 < recorded < sent == 300
    assert recorded + int(m.group(1)) == sent       # every frame: in the log or counted lost


@vcan
def test_lost_frames_of_the_can_raw_socket_are_counted_too(bin_path, tmp_path) -> None:
    """Without CAP_NET_RAW (no ring): the smallest socket buffer, the same accounting."""
    log = tmp_path / "bus.log"
    with open(log, "w") as out:
        proc = subprocess.Popen([*UNPRIVILEGED, str(bin_path("canrec")), "-r", "1", IFACE],
                                stdout=out, stderr=subprocess.PIPE, text=True)
        wait_listening(proc)
        assert not reads_a_ring(proc.pid)
        os.kill(proc.pid, signal.SIGSTOP)
        try:
            sent = send_frames(300)
        finally:
            os.kill(proc.pid, signal.SIGCONT)
        wait_listening(proc)
        proc.send_signal(signal.SIGINT)
        err = proc.communicate(timeout=10)[1]
    assert proc.returncode == 3
    m = re.search(r"canrec: vcan0: (\d+) frames lost in all: the log is incomplete", err)
    assert m, err
    recorded = sum(1 for ln in log.read_text().splitlines() if " 555#" in ln)
    assert 0 < recorded < sent == 300
    assert recorded + int(m.group(1)) == sent


# ---- the rig's choice -----------------------------------------------------------------------------
@pytest.mark.parametrize("argv, recorder", [
    (["campaign", "cdrw"], "canrec"),
    (["campaign", "cdrw", "--recorder", "candump"], "candump"),
    (["campaign", "cdrw", "--recorder", "canrec", "--workers", "2"], "canrec"),
    (["run", "cdrw"], "canrec"),
    (["demo"], "canrec"),
])
def test_every_run_records_with_canrec_unless_told(tmp_path, argv, recorder) -> None:
    from hil.cli.common import rig_config
    from hil.cli.parser import build

    assert rig_config(build().parse_args(argv), tmp_path).recorder == recorder


def test_an_unknown_recorder_is_one_line(capsys) -> None:
    from rig_helpers import cli

    rc, out, err = cli(capsys, "campaign", "cdrw", "--recorder", "cat")
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and "--recorder" in err and "canrec" in err
