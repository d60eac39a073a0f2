"""`--target qemu-m4f`: the Cortex-M4F image (firmware/port/mps2_an386/README.md) under qemu-system-arm,
its SLCAN serial line attached to the rig's CAN bus.

    qemu-system-arm (mps2-an386)   UART0 = SLCAN on a pty (via QEMU's multiplexer), UART1 = the log
        |  /dev/pts/N
    slcand -F -o -c -s6            the pty as a SocketCAN interface (slcNNNN, kernel slcan)
        |
    cangw slcNNNN -> IFACE (-e)    the kernel CAN gateway (can-gw), both directions;
    cangw IFACE -> slcNNNN         candump on IFACE records the whole bus as with the host fcc
                                   (--bus wire: IFACE is fcc's vxcan end of canbus, hil.rig.wirebus;
                                   the image is a FIFO node there, its line the FIFO)

The image has no command line: the run's fcc options go into its boot configuration record
(bootcfg.bin, loaded at 0x000FFF00 by QEMU's generic loader).  Lockstep runs with
`-icount shift=0,sleep=on` (1 ns of virtual time per instruction: FCC_ACK.exec_us is the
instruction count / 1000); realtime without -icount (virtual time = the host's clock).

A link loss -- QEMU gone, slcand gone, the interface gone -- is seen by `poll()` and is a rig
error of one line; a UART that stops while QEMU runs is the lockstep timeout.  No frame is lost
silently: the slcan interface queues LINE_QUEUE frames (a step's burst from the rig waits there
while the UART takes one byte at a time); a frame the full queue drops (its queueing
discipline's drop count, read over rtnetlink every LINE_CHECK_S while the line is up) and a
byte the image's receive ring could not take (its summary's `board rx_overflows`, also
FCC_BUS_COUNTS.rx_overflows on the bus) end the run with one line naming the loss.  Needs root
for slcand, `ip link` and cangw (the User-Mode Linux guest of scripts/with-vcan runs as root),
the kernel modules slcan and can-gw (with-vcan loads them) and a devpts at /dev/pts.
"""
from __future__ import annotations

import os
import re
import shutil
import signal
import struct
import subprocess
import time
from collections.abc import Sequence
from pathlib import Path

from hil.bus.secoc import TEST_KEY_FILE
from hil.targets import qdisc
from hil.targets.board import PTY_LINE, command as qemu_command
from hil.targets.bootcfg import BootConfig
from hil.targets.device import ArgsRefused, Device, DeviceStart
from hil.targets.m4f_image import PilError, build_image, m4f_build_dir

#: the trip of the Cortex-M4F PIL image (firmware/port/mps2_an386/m4f_main.c: no entropy on the board)
PIL_TRIP = 0x4D344631
#: the SLCAN bitrate command slcand sends (S6 = 500 kbit/s, the bus's DBC bitrate)
SLCAN_SPEED = "6"
#: QEMU's start-up inside the UML guest takes ~3 s on an idle machine
PTY_TIMEOUT_S = 60.0
IFACE_TIMEOUT_S = 20.0
#: how long a link loss waits for QEMU's own exit before it counts as a loss
LINK_GRACE_S = 2.0
#: frames the slcan interface queues toward the UART (the kernel's default for slcan is 10:
#: a step's burst plus the heartbeat or an attacker's frames overflowed it, losing ticks)
LINE_QUEUE = 256
#: how often poll() reads the interface's drop count (hil.targets.qdisc, over rtnetlink)
LINE_CHECK_S = 1.0
#: realtime: QEMU's main loop at fcc's SCHED_FIFO priority (hil.rig.config.FCC_RT_PRIORITY)
LINE_RT_PRIORITY = 50
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
            raise PilError("--target qemu-m4f needs a SocketCAN interface (slcand and can-gw)")
        self.iface = iface
        self.run_dir = run_dir
        self.log_path = log_path
        self.qemu_log = run_dir / "qemu.log"
        self.slcan = f"slc{os.getpid() % 100000}"
        self.returncode: int | None = None
        self._lost: str | None = None
        self._line_checked = 0.0
        self._routes: list[list[str]] = []
        self.qemu: subprocess.Popen[bytes] | None = None
        self.slcand: subprocess.Popen[bytes] | None = None
        _tool("qemu-system-arm", "qemu-system-arm")
        self._slcand_exe = _tool("slcand", "can-utils")
        self._cangw = _tool("cangw", "can-utils")
        image = image or build_image()
        cfg = boot_record(fcc_args)
        self.realtime = cfg.mode == "realtime"
        self.cmd = qemu_command(image, log=log_path, bootcfg_file=cfg.write(run_dir / "bootcfg.bin"),
                                lockstep=not self.realtime)
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
        with open(self.qemu_log, "wb") as err:
            try:
                self.qemu = subprocess.Popen(self.cmd, stdin=subprocess.DEVNULL,
                                             stdout=err, stderr=subprocess.STDOUT)
            except OSError as e:
                raise PilError(f"cannot start qemu-system-arm: {e.strerror}") from None
        pty = self._wait_pty()
        self.slcand = subprocess.Popen([self._slcand_exe, "-F", "-o", "-c", f"-s{SLCAN_SPEED}",
                                        pty, self.slcan], stdin=subprocess.DEVNULL,
                                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        self._wait_iface()
        if self.realtime:
            self._realtime_line()
        _run(["ip", "link", "set", self.slcan, "txqueuelen", str(LINE_QUEUE), "up"],
             f"ip link set {self.slcan} up")
        for route in (["-s", self.slcan, "-d", self.iface, "-e"], ["-s", self.iface, "-d", self.slcan]):
            _run([self._cangw, "-A", *route], f"cangw -A {' '.join(route)} (is can-gw loaded?)")
            self._routes.append(route)

    def _realtime_line(self) -> None:
        """In realtime, QEMU's main loop (the thread that moves the line's bytes from the pty
        into the UART, one byte per round) at fcc's SCHED_FIFO priority and its other threads (the
        vCPU: the image itself) just below, as the host fcc runs: the line's bytes no longer wait
        behind the rig's own processes in the guest (measured: firmware/port/mps2_an386/README.md,
        "Time sync over the line").  Where the system refuses, QEMU runs as before."""
        assert self.qemu is not None
        try:
            for tid in sorted(int(t) for t in os.listdir(f"/proc/{self.qemu.pid}/task")):
                prio = LINE_RT_PRIORITY if tid == self.qemu.pid else LINE_RT_PRIORITY - 1
                os.sched_setscheduler(tid, os.SCHED_FIFO, os.sched_param(prio))
        except OSError:
            return

    def _wait_pty(self) -> str:
        assert self.qemu is not None
        deadline = time.monotonic() + PTY_TIMEOUT_S
        while time.monotonic() < deadline:
            text = self.qemu_log.read_text(errors="replace")
            m = PTY_LINE.search(text)
            if m:
                return m.group(1)
            if self.qemu.poll() is not None:
                last = [ln for ln in text.splitlines() if ln.strip()]
                raise PilError(f"qemu-system-arm stopped at start-up ({_exit_text(self.qemu.returncode)})"
                               + (f": {last[-1]}" if last else ""))
            time.sleep(0.05)
        raise PilError(f"qemu-system-arm opened no serial pty within {PTY_TIMEOUT_S:g} s")

    def _wait_iface(self) -> None:
        assert self.slcand is not None
        deadline = time.monotonic() + IFACE_TIMEOUT_S
        while time.monotonic() < deadline:
            if Path(f"/sys/class/net/{self.slcan}").exists():
                return
            if self.slcand.poll() is not None:
                err = self.slcand.stderr.read().decode(errors="replace").strip() if self.slcand.stderr else ""
                raise PilError(f"slcand stopped ({_exit_text(self.slcand.returncode)})"
                               + (f": {err.splitlines()[-1]}" if err else "")
                               + " (is the slcan module loaded? run as root)")
            time.sleep(0.02)
        raise PilError(f"slcand made no {self.slcan} within {IFACE_TIMEOUT_S:g} s")

    # -- the Device interface
    def local_pids(self) -> tuple[int, ...]:
        """Every thread of QEMU (a scheduling policy is per thread: its main loop, its vCPU)
        and of slcand, for the rig's SCHED_BATCH in lockstep."""
        tids: list[int] = []
        for proc in (self.qemu, self.slcand):
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
        if rc is None and (lost := self._line_loss()) is not None:
            self._lost = lost
            rc = 1
        elif rc is None and (lost := self._link_gone()) is not None:
            try:  # QEMU exiting (after a shutdown frame) closes the pty, which ends the link first
                rc = self.qemu.wait(LINK_GRACE_S)
            except subprocess.TimeoutExpired:
                self._lost = lost
                rc = 1
        self.returncode = rc
        return rc

    def _link_gone(self) -> str | None:
        """Why the serial link is gone (slcand ended, the interface vanished), or None."""
        if self.slcand is not None and self.slcand.poll() is not None:
            return f"slcand {_exit_text(self.slcand.returncode)}"
        if not Path(f"/sys/class/net/{self.slcan}").exists():
            return f"interface {self.slcan} gone"
        return None

    def _line_loss(self, force: bool = False) -> str | None:
        """Frames the full slcan queue dropped (at most every LINE_CHECK_S unless forced), or
        None; None too once the interface is gone (QEMU's exit closes the line)."""
        now = time.monotonic()
        if not force and now - self._line_checked < LINE_CHECK_S:
            return None
        self._line_checked = now
        if not Path(f"/sys/class/net/{self.slcan}").exists():
            return None
        try:
            drops = qdisc.drops(self.slcan)
        except OSError as e:
            if not Path(f"/sys/class/net/{self.slcan}").exists():
                return None
            return f"cannot read {self.slcan}'s queue statistics ({e})"
        if drops == 0:
            return None
        return (f"{drops} frames dropped on their way to the image ({self.slcan}'s queue of "
                f"{LINE_QUEUE} frames was full: the UART is slower than the bus traffic)")

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
        the link (the routes go with the interface)."""
        rc = self.returncode
        if self._lost is None and Path(f"/sys/class/net/{self.slcan}").exists():
            self._lost = self._line_loss(force=True)
        if self.qemu is not None:
            rc = _end(self.qemu, grace)
            if self.returncode is None or self._lost is None:
                self.returncode = rc
        if self._lost is None:
            self._lost = self._image_loss()
        if self._lost is not None and self.returncode == 0:
            self.returncode = 1
        for route in self._routes:
            subprocess.run([self._cangw, "-D", *route], stdin=subprocess.DEVNULL, capture_output=True)
        self._routes = []
        if self.slcand is not None:
            _end(self.slcand, 0.0)
            if self.slcand.stderr:
                self.slcand.stderr.close()
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
