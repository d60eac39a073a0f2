"""`--target qemu-m4f`: the Cortex-M4F image (firmware/port/mps2_an386/README.md) under qemu-system-arm,
its SLCAN serial line attached to the rig's CAN bus.

    qemu-system-arm (mps2-an386)   UART0 = SLCAN on a Unix socket (via QEMU's multiplexer, QEMU
        |  RUN/uart0.sock          its client), UART1 = the log
    slcan_bridge -i IFACE -u SOCK  (firmware/tools/slcan_bridge) a raw CAN socket on IFACE and the
        |                          line, joined in user space: a frame on IFACE is written to the
    IFACE                          line as its SLCAN line at once, a frame line from the image is
                                   sent on IFACE; candump on IFACE records the whole bus as with
                                   the host fcc (--bus wire: IFACE is fcc's vxcan end of canbus,
                                   hil.rig.wirebus; the image is a FIFO node there, its line the FIFO)

The bridge replaced slcand + the kernel's slcan + a pty + can-gw (2026-12-02): their deferred
work paced frames at 2.5-3.75 ms each and delayed a time SYNC by 0 or 1.5-7 ms, too much for the
image's time sync to lock (the README's "Time sync over the line").  In realtime the bridge
stamps each line with the frame's time on IFACE (-z, the kernel's receive stamp) and the image
takes it as the frame's receive stamp, as from a CAN controller.

The image has no command line: the run's fcc options go into its boot configuration record
(bootcfg.bin, loaded at 0x000FFF00 by QEMU's generic loader).  Lockstep runs with
`-icount shift=0,sleep=on` (1 ns of virtual time per instruction: FCC_ACK.exec_us is the
instruction count / 1000); realtime without -icount (virtual time = the host's clock).

A link loss -- QEMU gone, the bridge gone, the interface gone -- is seen by `poll()` and is a
rig error of one line; a UART that stops while QEMU runs is the lockstep timeout.  No frame is
lost silently: the bridge queues LINE_QUEUE frames toward the UART behind the socket's
LINE_BUFFER bytes (a step's burst from the rig waits there while the UART takes one byte at a
time); a frame the full queue drops, a frame the
kernel dropped from the bridge's receive queue, or a frame of the image the interface refused
ends the bridge (exit 3) with one line naming the loss, and the run with that line; a byte the
image's receive ring could not take (its summary's `board rx_overflows`, also
FCC_BUS_COUNTS.rx_overflows on the bus) ends the run with one line too.
"""
from __future__ import annotations

import os
import re
import select
import shutil
import signal
import struct
import subprocess
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

from hil.bus.secoc import TEST_KEY_FILE
from hil.targets.board import command as qemu_command
from hil.targets.bootcfg import BootConfig
from hil.targets.device import ArgsRefused, Device, DeviceStart
from hil.targets.m4f_image import PilError, build_image, m4f_build_dir
from hil.io.paths import ToolNotFound, tool

#: the trip of the Cortex-M4F PIL image (firmware/port/mps2_an386/m4f_main.c: no entropy on the board)
PIL_TRIP = 0x4D344631
#: QEMU's start-up inside the UML guest takes ~3 s on an idle machine
QEMU_TIMEOUT_S = 60.0
#: the bridge's start-up (it prints its ready line once it listens on the line's socket)
BRIDGE_TIMEOUT_S = 20.0
#: how long a link loss waits for QEMU's own exit before it counts as a loss
LINK_GRACE_S = 2.0
#: frames the bridge queues toward the UART (a step's burst plus the heartbeat or an attacker's
#: frames: the kernel slcan's default of 10 lost ticks that way)
LINE_QUEUE = 256
#: bytes of lines the socket's kernel buffer holds ahead of the queue, as a pty's 64 kB: the line
#: stalls for up to seconds while QEMU is starved in a loaded guest
LINE_BUFFER = 65536
#: realtime: QEMU's main loop at fcc's SCHED_FIFO priority (hil.rig.config.FCC_RT_PRIORITY),
#: its vCPU just below
LINE_RT_PRIORITY = 50
#: slcan_bridge's exit status when a frame was lost (firmware/tools/slcan_bridge)
BRIDGE_LOST = 3
#: the image's summary line with its receive ring's overflows (m4f_main.c)
RX_OVERFLOWS = re.compile(r"fcc summary: board .*\brx_overflows=(\d+)")


#: the fcc options the boot configuration record carries (firmware/port/mps2_an386/README.md)
BOOT_OPTIONS = ("--mode", "--apps", "--stale-limit", "--status-rate", "--lqg-period", "--lqg-bits",
                "--lqg-delay", "--gyro-var", "--accel-var", "--detector", "--fault-policy")


def boot_options(fcc_args: Sequence[str]) -> dict[str, str]:
    """fcc's command line as {option: value} (the last one wins, as in fcc), refusing options
    the image does not take."""
    opts: dict[str, str] = {}
    it = iter(fcc_args)
    for opt in it:
        if opt not in BOOT_OPTIONS:
            raise PilError(f"the M4F image takes no {opt} (its boot configuration has "
                           f"{', '.join(BOOT_OPTIONS)})")
        val = next(it, None)
        if val is None:
            raise PilError(f"{opt} needs a value")
        opts[opt] = val
    return opts


def boot_record(fcc_args: Sequence[str]) -> BootConfig:
    """The image's boot configuration record for this fcc command line."""
    opts = boot_options(fcc_args)
    fields: dict[str, object] = {}
    try:
        for opt, val in opts.items():
            name = opt[2:].replace("-", "_")
            if name == "apps":
                fields[name] = tuple(a for a in val.split(",") if a)
            elif name in ("stale_limit", "lqg_bits"):
                fields[name] = int(val)
            elif name == "lqg_delay" and val == "auto":
                raise PilError("the M4F image takes --lqg-delay in seconds, not auto (the rig "
                               "gives it the delay it resolved for the run)")
            elif name in ("status_rate", "lqg_period", "lqg_delay", "gyro_var", "accel_var"):
                fields[name] = float(val)
            else:
                fields[name] = val
        cfg = BootConfig(**fields)  # type: ignore[arg-type]
        cfg.encode()
    except (ValueError, KeyError, struct.error) as e:
        raise PilError(f"the M4F image's boot configuration refuses {' '.join(fcc_args)}: {e}") from None
    return cfg


def _tool(name: str, package: str) -> str:
    exe = shutil.which(name)
    if exe is None:
        raise PilError(f"{name} not found: install {package} (scripts/setup does)")
    return exe


def _run(cmd: Sequence[str], what: str) -> None:
    r = subprocess.run(list(cmd), stdin=subprocess.DEVNULL, capture_output=True, text=True)
    if r.returncode != 0:
        err = (r.stderr or r.stdout).strip().splitlines()
        raise PilError(f"{what}: {err[-1] if err else f'exit status {r.returncode}'}")


def _exit_text(rc: int | None) -> str:
    if rc is None:
        return "running"
    if rc < 0:
        try:
            return f"killed by {signal.Signals(-rc).name}"
        except ValueError:
            return f"killed by signal {-rc}"
    return f"exit status {rc}"


class QemuM4f(Device):
    """The emulated board and its serial link, for the duration of a session."""

    target = "qemu-m4f"
    label = "the M4F image"
    startup_timeout = 60.0

    def __init__(self, run_dir: Path, fcc_args: Sequence[str], iface: str, log_path: Path, *,
                 image: Path | None = None, interface: str = "socketcan") -> None:
        if interface != "socketcan":
            raise PilError("--target qemu-m4f needs a SocketCAN interface (slcan_bridge)")
        self.iface = iface
        self.run_dir = run_dir
        self.log_path = log_path
        self.qemu_log = run_dir / "qemu.log"
        self.bridge_log = run_dir / "slcan_bridge.log"
        self.returncode: int | None = None
        self._lost: str | None = None
        self.qemu: subprocess.Popen[bytes] | None = None
        self.bridge: subprocess.Popen[bytes] | None = None
        _tool("qemu-system-arm", "qemu-system-arm")
        try:
            self._bridge_exe = str(tool("slcan_bridge"))
        except ToolNotFound as e:
            raise PilError(str(e)) from None
        image = image or build_image()
        cfg = boot_record(fcc_args)
        self.realtime = cfg.mode == "realtime"
        # a short path of its own: a Unix socket's path has at most 107 characters
        self._line_dir = Path(tempfile.mkdtemp(prefix="fcc-m4f-"))
        self.line_socket = self._line_dir / "uart0.sock"
        self.cmd = qemu_command(image, log=log_path, bootcfg_file=cfg.write(run_dir / "bootcfg.bin"),
                                lockstep=not self.realtime, line_socket=self.line_socket)
        try:
            self._start()
        except BaseException:
            self.stop(grace=0.0)
            raise

    @classmethod
    def start(cls, how: DeviceStart) -> QemuM4f:
        return cls(how.run_dir, how.fcc_args, how.iface, how.log_path, image=how.firmware,
                   interface=how.interface)

    @classmethod
    def check_args(cls, given: Path | None, extra: Sequence[str], mode: str) -> None:
        """The image's boot configuration record takes them (boot_record)."""
        try:
            boot_record(["--mode", mode, *extra])
        except PilError as e:
            raise ArgsRefused(str(e)) from None

    @classmethod
    def firmware(cls, given: Path | None, progress: bool) -> Path | None:
        """The image given (--fcc), else the cross build's, brought up to date now."""
        return given or build_image(progress=progress)

    @classmethod
    def bus_key_file(cls, requested: Path | None) -> Path | None:
        """The image carries the published test key (firmware/port/mps2_an386/README.md)."""
        return TEST_KEY_FILE

    @classmethod
    def choose_trip(cls) -> int | None:
        return PIL_TRIP

    # -- start-up
    def _start(self) -> None:
        """The bridge first (it listens on the line's socket), then QEMU (it connects there)."""
        stamps = ["-z"] if self.realtime else []
        with open(self.bridge_log, "wb") as err:
            try:
                self.bridge = subprocess.Popen(
                    [self._bridge_exe, "-i", self.iface, "-u", str(self.line_socket),
                     "-n", str(LINE_QUEUE), "-b", str(LINE_BUFFER), *stamps],
                    stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=err)
            except OSError as e:
                raise PilError(f"cannot start slcan_bridge: {e.strerror}") from None
        self._wait_bridge()
        with open(self.qemu_log, "wb") as err:
            try:
                self.qemu = subprocess.Popen(self.cmd, stdin=subprocess.DEVNULL,
                                             stdout=err, stderr=subprocess.STDOUT)
            except OSError as e:
                raise PilError(f"cannot start qemu-system-arm: {e.strerror}") from None
        self._wait_connected()
        if self.realtime:
            self._realtime_line()

    def _wait_connected(self) -> None:
        """Until QEMU has connected to the line (the bridge's second line on stdout), or why not."""
        assert self.qemu is not None and self.bridge is not None and self.bridge.stdout is not None
        deadline = time.monotonic() + QEMU_TIMEOUT_S
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.bridge.stdout], [], [], 0.05)
            if ready and self.bridge.stdout.readline().strip() == b"slcan_bridge: connected":
                return
            if self.qemu.poll() is not None:
                text = self.qemu_log.read_text(errors="replace")
                last = [ln for ln in text.splitlines() if ln.strip()]
                raise PilError(f"qemu-system-arm stopped at start-up ({_exit_text(self.qemu.returncode)})"
                               + (f": {last[-1]}" if last else ""))
            if (gone := self._link_gone()) is not None:
                raise PilError(f"slcan_bridge stopped at start-up: {gone}")
        raise PilError(f"qemu-system-arm did not connect to its line within {QEMU_TIMEOUT_S:g} s")

    def _wait_bridge(self) -> None:
        """Until the bridge says it listens (its one line on stdout), or why not (its stderr)."""
        assert self.bridge is not None and self.bridge.stdout is not None
        ready, _, _ = select.select([self.bridge.stdout], [], [], BRIDGE_TIMEOUT_S)
        line = self.bridge.stdout.readline().decode(errors="replace").strip() if ready else ""
        if line == "slcan_bridge: ready":
            return
        if self.bridge.poll() is None:
            raise PilError(f"slcan_bridge did not listen on {self.line_socket} within "
                           f"{BRIDGE_TIMEOUT_S:g} s")
        raise PilError(f"slcan_bridge stopped at start-up ({_exit_text(self.bridge.returncode)})"
                       + (f": {said}" if (said := self._bridge_said()) else ""))

    def _bridge_said(self) -> str:
        """The bridge's last line on stderr that is not its summary ('' if none)."""
        try:
            lines = self.bridge_log.read_text(errors="replace").splitlines()
        except OSError:
            return ""
        said = [ln.strip() for ln in lines if ln.strip() and " summary " not in ln]
        return said[-1] if said else ""

    def _realtime_line(self) -> None:
        """In realtime, QEMU's main loop (the thread that moves the line's bytes from the socket
        into the UART) at fcc's SCHED_FIFO priority and its other threads (the vCPU: the image
        itself) just below, as the host fcc runs: the line's bytes wait behind none of the rig's
        own processes in the guest.  The bridge stays at normal priority: at fcc's, its bursts
        starved the vCPU (measured: firmware/port/mps2_an386/README.md, "Time sync over the
        line"), and the time sync no longer needs it early (its frames carry their bus time).
        Where the system refuses, they run as before."""
        assert self.qemu is not None
        try:
            for tid in sorted(int(t) for t in os.listdir(f"/proc/{self.qemu.pid}/task")):
                prio = LINE_RT_PRIORITY if tid == self.qemu.pid else LINE_RT_PRIORITY - 1
                os.sched_setscheduler(tid, os.SCHED_FIFO, os.sched_param(prio))
        except OSError:
            return

    # -- the Device interface
    def local_pids(self) -> tuple[int, ...]:
        """Every thread of QEMU (a scheduling policy is per thread: its main loop, its vCPU)
        and the bridge, for the rig's SCHED_BATCH in lockstep."""
        tids: list[int] = []
        for proc in (self.qemu, self.bridge):
            try:
                tids += sorted(int(t) for t in os.listdir(f"/proc/{proc.pid}/task")) if proc else []
            except OSError:  # gone meanwhile: poll() reports it
                pass
        return tuple(tids)

    def poll(self) -> int | None:
        if self.returncode is not None:
            return self.returncode
        assert self.qemu is not None
        rc = self.qemu.poll()
        if rc is None and (lost := self._link_gone()) is not None:
            try:  # QEMU exiting (after a shutdown frame) closes the line, which ends the bridge
                rc = self.qemu.wait(0.0 if self._frames_lost() else LINK_GRACE_S)
            except subprocess.TimeoutExpired:
                self._lost = lost
                rc = 1
        self.returncode = rc
        return rc

    def _frames_lost(self) -> bool:
        return self.bridge is not None and self.bridge.poll() == BRIDGE_LOST

    def _link_gone(self) -> str | None:
        """Why the serial link is gone (the bridge ended: its own line, e.g. the frames it
        lost or the interface gone), or None."""
        if self.bridge is None or self.bridge.poll() is None:
            return None
        said = self._bridge_said()
        return said.removeprefix("slcan_bridge: ") if said else \
            f"slcan_bridge {_exit_text(self.bridge.returncode)}"

    def _image_loss(self) -> str | None:
        """Bytes the image's receive ring could not take (its summary on the log), or None."""
        try:
            m = RX_OVERFLOWS.search(self.log_path.read_text(errors="replace"))
        except OSError:
            return None
        if m is None or int(m.group(1)) == 0:
            return None
        return f"the image's UART receive ring overflowed ({m.group(1)} bytes lost)"

    def describe_exit(self) -> str:
        rc = self.poll()
        if self._lost is not None:
            return f"serial link lost: {self._lost}"
        last = ""
        for path in (self.log_path, self.qemu_log):
            try:
                lines = [ln.strip() for ln in path.read_text(errors="replace").splitlines() if ln.strip()]
            except OSError:
                lines = []
            if lines:
                last = lines[-1]
                break
        return f"qemu-system-arm {_exit_text(rc)}" + (f"; its last words: {last}" if last else "")

    def stop(self, grace: float = 2.0) -> int | None:
        """Wait up to grace s for QEMU's own exit (after a shutdown frame), then end it; then
        the bridge (QEMU's exit closed its line), reporting a frame it lost."""
        rc = self.returncode
        if self.qemu is not None:
            rc = _end(self.qemu, grace)
            if self.returncode is None or self._lost is None:
                self.returncode = rc
        if self.bridge is not None:
            _end(self.bridge, 0.0 if self.qemu is None else LINK_GRACE_S)
            if self.bridge.stdout:
                self.bridge.stdout.close()
            if self._lost is None and self.bridge.returncode == BRIDGE_LOST:
                self._lost = self._link_gone()
        if self._lost is None:
            self._lost = self._image_loss()
        if self._lost is not None and self.returncode == 0:
            self.returncode = 1
        shutil.rmtree(self._line_dir, ignore_errors=True)
        return self.returncode


def _end(proc: subprocess.Popen[bytes], grace: float) -> int | None:
    """Wait up to grace s, then SIGTERM, then SIGKILL."""
    try:
        return proc.wait(grace)
    except subprocess.TimeoutExpired:
        pass
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            proc.send_signal(sig)
        except ProcessLookupError:
            pass
        try:
            return proc.wait(2.0)
        except subprocess.TimeoutExpired:
            continue
    return proc.poll()


__all__ = ["PilError", "QemuM4f", "build_image", "m4f_build_dir"]
