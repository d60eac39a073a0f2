"""One rig session: the bus recorder, the firmware process and the simulator's socket.

    with RigSession(run_dir, fcc_args, config) as rig:   # recorder, then fcc, then "listening"
        ... lockstep or realtime flights (rig.link, rig.codec, rig.send_message) ...
        rig.shutdown()                                     # SIM_CONTROL shutdown, fcc exits 0

Order matters: the socket is opened first (so fcc's first heartbeat is seen), then the bus
recorder, candump or canrec (ready when it sleeps waiting for frames), then fcc (ready when its
first FCC_STATUS arrives).  On any error the session still stops both programs and keeps
bus.log and fcc.log.  With config.bus "wire" in realtime (hil.rig.wirebus) canbus is started
before all of them, each on its own vxcan end, and stopped after them (its statistics:
self.bus_stats); in lockstep the bus model runs in simulated time (hil.rig.lockstep_wire).

Why this module is long: the session's life cycle, its key and trip, and the checks on who
else is on the bus (another fcc before the start, a second fcc's heartbeats during the run)
share its state; split, each part would reach into the others.
"""
from __future__ import annotations

import re
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

from hil.bus import SIM_NODES, E2EReceiver, FrameCodec, load
from hil.bus.codec import decode_values
from hil.bus.dbc import BusSpec
from hil.bus.protocol import (
    COMMAND_GROUND,
    COMMAND_NONE,
    COMMAND_RESET,
    COMMAND_SHUTDOWN,
    MODE_CODES,
    MODE_NAMES,
)
from hil.bus.secoc import Endpoint, KeyFileError, load_cmac, mac, read_key_file, same_mac, write_key_file
from hil.rig.config import RigConfig
from hil.rig.errors import FccDied, FccTimeout, RigError
from hil.rig.inject import InjectChannel
from hil.rig.link import CanLink, LinkError, LinkRecorder, pack_frame
from hil.rig.status import STATUS_FRAMES, StatusCounters
from hil.rig.recorder import RECORDERS, BusRecorder
from hil.rig.txsched import SEND_LOG
from hil.rig.wirebus import WireBus
from hil.scenario.faults import Fault
from hil.targets.device import Device, DeviceStart
from hil.targets.registry import device_class, target as target_of
from hil.util.processes import run_as_batch

if TYPE_CHECKING:  # realtime's (hil.rig.realtime makes them): not imported for lockstep
    from hil.rig.timesync import TimeMaster
    from hil.rig.txsched import TimedSender

STARTUP_TIMEOUT_S = 10.0
#: before fcc is started, the bus is listened to this long for another fcc's frames (its
#: heartbeat comes at 10 Hz by default)
LEFTOVER_LISTEN_S = 0.25
#: the session's random key, kept in the run directory (owner-only): `hil replay` reads the
#: recording with it (only authenticated frames are replayed); a --key-file is never copied
KEPT_KEY = "session.key"
#: RIG_PING.seq of the last frame of every bus log
END_MARKER_SEQ = 0xFFFFFFFF


#: Only what the simulator acts on comes to its socket: the acknowledge, the missile's command
#: and estimate, the heartbeat.  The identification outputs (12 frames per CDRW step) are read
#: back from bus.log after the run: the recorder gets every frame anyway, and in the UML guest
#: every frame received costs a slow system call.
RX_NAMES = ("FCC_ACK", "MSL_ELEV_CMD", "MSL_ELEV_CMD_AUTH", "MSL_STATE_EST", "RIG_PONG",
            *STATUS_FRAMES, "FCC_STATUS_AUTH")


def received_ids(spec: BusSpec) -> tuple[int, ...]:
    """The identifiers of RX_NAMES in `spec`: what the session's socket receives."""
    return tuple(spec.by_name(n).frame_id for n in RX_NAMES)


#: a session's socket opened ahead, listening since (a warm rig's next command: listen_ahead)
_opened_ahead: tuple[CanLink, float, tuple[int, ...]] | None = None
#: what is told that a session has stopped its device (on_device_stopped)
_device_stopped: Callable[[], object] | None = None


def on_device_stopped(hook: Callable[[], object]) -> None:
    """hook() once each session of this process (and of those forked from it) has stopped its
    device: a warm rig's loop then opens the next command's socket (listening_ahead) while
    this command evaluates its flight (hil.parallel.warmup)."""
    global _device_stopped  # noqa: PLW0603 - one hook for the process
    _device_stopped = hook


@contextmanager
def listening_ahead(iface: str) -> Iterator[None]:
    """The next session's socket on SocketCAN `iface` (the default DBC's identifiers) opened
    for the block: a session started in it -- or in a process forked in it, which keeps the
    socket -- takes the socket and with it the time it has listened for another fcc
    (LEFTOVER_LISTEN_S) instead of listening then.  A warm rig's loop forks its next
    command's process in it as the previous command ends (hil.parallel.warmup); a frame heard
    meanwhile fails that session as one heard in its own listen does.  A socket that cannot
    be opened now: the session opens its own (and says why then)."""
    global _opened_ahead  # noqa: PLW0603 - this process's one socket opened ahead
    ids = received_ids(load())
    try:
        _opened_ahead = CanLink(iface, ids), time.monotonic(), ids
    except (LinkError, OSError):
        _opened_ahead = None
    try:
        yield
    finally:   # (a forked process never leaves the block: the socket stays its own)
        ahead, _opened_ahead = _opened_ahead, None
        if ahead is not None:
            ahead[0].close()


def _socket(iface: str, ids: tuple[int, ...]) -> tuple[CanLink, float]:
    """A SocketCAN socket on iface receiving ids, and since when it listens: the one opened
    ahead when it is that (listen_ahead), else a new one."""
    global _opened_ahead  # noqa: PLW0603 - taken once, by the first session that fits
    ahead, _opened_ahead = _opened_ahead, None
    if ahead is not None and ahead[0].channel == iface and ahead[2] == ids:
        return ahead[0], ahead[1]
    if ahead is not None:
        ahead[0].close()
    return CanLink(iface, ids), time.monotonic()


_SUMMARY = re.compile(r"^fcc summary: (\w+) steps=\d+ degraded=\d+ errors=(\d+)")


def step_errors(fcc_log: Path) -> dict[str, int]:
    """fcc's failed steps per application, from its exit summary (fcc.log)."""
    try:
        text = fcc_log.read_text(errors="replace")
    except OSError:
        return {}
    return {m[1]: int(m[2]) for m in map(_SUMMARY.match, text.splitlines()) if m}


class RigSession:
    """Bus recorder + fcc + the simulator's socket, for the duration of a ``with`` block."""

    def __init__(self, run_dir: Path, fcc_args: Sequence[str], config: RigConfig, *,
                 record: bool = True, spec: BusSpec | None = None,
                 prepare: Callable[[RigSession], object] | None = None) -> None:
        """config: the run's (its interface, python-can's interface and bitrate, the device
        under test and its firmware, the mode checked against the device's FCC_STATUS.mode,
        the answer timeout of an external device, the bus key file (default: a random one for
        this session; the device may have its own, hil.targets), the bus recorder on SocketCAN
        (hil.rig.recorder.RECORDERS; the link's own log writer otherwise)); record: keep
        bus.log; prepare: work for the time the bus is listened to before fcc starts (`hil
        run`'s imports of the simulator and the evaluation, the flights' precomputation: the
        listen is a wait otherwise), its result in ``self.prepared``."""
        self.run_dir = Path(run_dir)
        self.config = config
        self.iface = config.iface
        self.interface = config.interface
        self.bitrate = config.bitrate
        self.target = config.target
        self.device_class = device_class(config.target)
        #: the run's mode, checked against the device's FCC_STATUS.mode
        self.mode = config.mode
        #: an external device must answer (its heartbeat) within this many seconds
        self.answer_timeout = config.timeout
        self.spec = spec or load()
        self.codec = FrameCodec(self.spec, SIM_NODES)
        self.fcc_ids = received_ids(self.spec)
        #: fcc's other frames (the identification outputs, read back from bus.log): lockstep on
        #: the wire-time bus reads them too, for the bus model only (hil.rig.lockstep_wire)
        self.model_only_ids = frozenset(
            m.frame_id for m in self.spec.messages if "FCC" in m.senders and m.frame_id not in self.fcc_ids)
        self.fcc_binary = config.fcc_binary
        self._key_dir: Path | None = None
        self.security, key_file = self._bus_key(self.device_class.bus_key_file(config.key_file))
        # the device's trip, when the rig knows it before the device starts (the high half
        # of every freshness value); else from its first heartbeat that verifies
        trip = self.device_class.choose_trip()
        if trip is not None:
            self.security.set_trip(trip)
        self.fcc_args = [*self.device_class.key_args(key_file, trip), *fcc_args]
        self.record = record
        if config.recorder not in RECORDERS:
            raise ValueError(f"recorder must be one of {', '.join(RECORDERS)}, not {config.recorder!r}")
        self.recorder = config.recorder
        self._prepare = prepare
        self.prepared: object = None
        self.link: CanLink | None = None
        self.bus_recorder: BusRecorder | LinkRecorder | None = None
        #: why bus.log is incomplete, when the recorder said so (e.g. frames it lost)
        self.recorder_error = ""
        self.fcc: Device | None = None
        self.status_frames: list[tuple[int, bytes]] = []
        self.link_stats: dict[str, int] = {}
        self.log_complete = False
        # fcc's E2E receiver of SIM_TICK, mirrored: tells whether fcc will act on a tick
        tick = self.spec.by_name("SIM_TICK")
        self._tick_msg = tick
        self.tick_rx = E2EReceiver(tick.data_id, tick.max_delta_counter)
        self.fcc_exit: int | None = None
        # a second fcc on the bus: its heartbeat carries another trip (FCC_SEC_SESSION)
        hb_auth = self.spec.by_name("FCC_STATUS_AUTH")
        self._hb_auth = (hb_auth.frame_id, hb_auth.secoc_data_id,
                         tuple(self.spec.by_name(p).frame_id for p in hb_auth.secoc_pdus))
        self._hb_latest: dict[int, bytes] = {}
        self.t_start = 0.0
        #: lockstep: the simulator, fcc and the recorder in SCHED_BATCH (hil.util.processes.run_as_batch)
        self.batch_scheduled = False
        #: realtime: the bus's time master (hil.rig.timesync), started by the first flight
        self.time_master: TimeMaster | None = None
        self.time_master_stats: dict[str, int] = {}
        #: realtime: the simulator's time-triggered transmitter (hil.rig.txsched), with the master
        self.transmitter: TimedSender | None = None
        self.transmitter_stats: dict[str, object] = {}
        #: `hil inject`'s channel into this run (hil.rig.inject; realtime flights read it)
        self.inject: InjectChannel | None = None
        #: --bus wire: canbus between the nodes' own vxcan ends (hil.rig.wirebus); the
        #: simulator's end is self.iface, the recorder's and fcc's are their own
        self.wire: WireBus | None = None
        #: --bus wire: the scenarios' wire faults (canbus's; hil.rig.wirefaults)
        self.wire_faults: tuple[Fault, ...] = ()
        #: the seed of the scenario the wire faults came from (a background load's frames)
        self.wire_seed = 0
        self.recorder_iface = self.fcc_iface = self.iface
        #: where the time master reads its SYNC back as the bus delivered it (None: its echo)
        self.bus_echo_iface: str | None = None
        #: --bus wire: canbus's statistics when it stopped, or why it failed
        self.bus_stats: dict = {}
        #: --bus wire on a real bus (an external device): where the simulator's transmitter
        #: writes each frame's send time (hil.rig.txsched; hil.results.busstats_real)
        self.send_log: Path | None = None
        self.bus_error = ""

    def _bus_key(self, key_file: Path | None) -> tuple[Endpoint, Path]:
        """The bus key: the given file, or a fresh random key for this session only (a file
        readable by its owner, handed to the device, deleted when the session closes)."""
        if key_file is None:
            self._key_dir = Path(tempfile.mkdtemp(prefix="hil-key-"))
            key_file = self._key_dir / "session.key"
            key = write_key_file(key_file)
        else:
            try:
                key = read_key_file(key_file)
            except KeyFileError as e:
                raise RigError(str(e)) from None
        return Endpoint(self.spec, key, SIM_NODES), key_file

    @staticmethod
    def dbc_frames() -> tuple:
        """The DBC's messages (for validating frame names in scenarios)."""
        return load().messages

    # -- life cycle
    def __enter__(self) -> RigSession:
        self.run_dir.mkdir(parents=True, exist_ok=True)
        try:
            # lockstep on the wire: the model runs in simulated time in the runner (hil.rig.simbus)
            if self.config.bus == "wire" and self.mode == "realtime":
                if target_of(self.target).wire == "model":
                    self._start_wire()
                else:   # a real bus: the simulator's send times recorded
                    self.send_log = self.run_dir / SEND_LOG
            socketcan = CanLink.is_raw(self.interface)
            if socketcan:
                self.link, t_open = _socket(self.iface, self.fcc_ids)
            else:
                self.link = CanLink(self.iface, self.fcc_ids, interface=self.interface, bitrate=self.bitrate,
                                    log_path=self.run_dir / "bus.log" if self.record else None)
                t_open = time.monotonic()
            if self.record and self._key_dir is not None:  # the run's own key: hil replay reads it
                write_key_file(self.run_dir / KEPT_KEY, self.security.key)
            if self.record:
                self._start_recorder() if socketcan else self._start_link_recorder()
            # work for the listen and the recorder's start, waits otherwise (frames meanwhile
            # wait in the socket's queue)
            load_cmac()
            if self._prepare is not None:
                self.prepared = self._prepare(self)
            if isinstance(self.bus_recorder, BusRecorder):
                self._await_recorder(self.bus_recorder)
            if self.device_class.owned:  # an external device is on the bus by design
                self._check_bus_idle(t_open + LEFTOVER_LISTEN_S)
            self.fcc = self.device_class.start(DeviceStart(
                self.run_dir, self.fcc_args, self.fcc_iface, self.fcc_binary, self.interface))
            self._wait_listening()
            if self.record:
                self.inject = InjectChannel(self.run_dir, self.mode, self.security.key)
            if self.mode == "lockstep":
                self.batch_scheduled = run_as_batch(self._lockstep_pids())
        except BaseException:
            self.close()
            raise
        self.t_start = time.monotonic()
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _start_wire(self) -> None:
        """canbus first (its ready line), then the nodes are pointed at their ends."""
        self.wire = WireBus(self.run_dir, self.bitrate or self.spec.baudrate, self.wire_faults,
                            self.spec, self.wire_seed).__enter__()
        self.iface = self.wire.end("sim")
        self.recorder_iface = self.wire.end("recorder")
        self.fcc_iface = self.wire.end("fcc")
        self.bus_echo_iface = self.recorder_iface

    def _start_recorder(self) -> None:
        """The recorder program started (listening once _await_recorder has returned)."""
        self.bus_recorder = RECORDERS[self.recorder](self.recorder_iface, self.run_dir / "bus.log")

    @staticmethod
    def _await_recorder(rec: BusRecorder) -> None:
        """Until the recorder listens (before fcc starts: every frame of fcc's is in bus.log)."""
        if not rec.wait_idle(STARTUP_TIMEOUT_S):
            if not rec.alive():
                raise RigError(f"{rec.label} stopped: {rec.error()}")
            raise RigError(f"{rec.label} did not start listening within {STARTUP_TIMEOUT_S:g} s")

    def _check_bus_idle(self, until: float) -> None:
        """No other fcc may be on the bus: its commands and acknowledgements would mix with
        this run's (a leftover of a killed rig, or a second rig on the same interface)."""
        assert self.link is not None
        while True:
            left = until - time.monotonic()
            got = self.link.recv_wait(max(left, 0.0))  # left <= 0: a last look at the queue
            if got is None:
                if left <= 0:
                    return
                continue
            msg = self.spec.by_id(got[0])
            raise RigError(f"another fcc is already on {self.iface} (heard its "
                           f"{msg.name if msg else hex(got[0])} before this run started fcc); "
                           f"stop it first")

    def _start_link_recorder(self) -> None:
        assert self.link is not None
        self.bus_recorder = LinkRecorder(self.link)

    def _lockstep_pids(self) -> list[int]:
        """This process and the local ones that answer or record its frames."""
        assert self.fcc is not None
        pids = [0, *self.fcc.local_pids()]
        if isinstance(self.bus_recorder, BusRecorder):  # a program (not the link's own recorder)
            pids.append(self.bus_recorder.pid)
        return pids

    def _wait_listening(self) -> None:
        """Until the device's first authenticated heartbeat: it has opened its socket, listens,
        shares our key (and trip), in the run's mode (an external device: its next heartbeat)."""
        assert self.link is not None and self.fcc is not None
        dev = self.fcc
        timeout = dev.startup_timeout if dev.owned else self.answer_timeout
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            got = self.link.recv()
            if got is None:
                if dev.poll() is not None:  # a start-up failure: exit 1 (RigError)
                    raise RigError(f"{dev.label} stopped at start-up ({dev.describe_exit()})")
                continue
            self.note_frame(*got)
            if self.status_frames:
                mode = int(self.status.last.get("FCC_STATUS", {}).get("mode", 0))
                if self.mode is not None and mode != MODE_CODES[self.mode]:
                    raise RigError(f"{dev.label} runs in {MODE_NAMES.get(mode, mode)} mode, "
                                   f"the run is {self.mode}")
                return
        if not dev.owned:
            raise RigError(f"nothing answered on {self.iface} within {timeout:g} s (no authenticated "
                           f"heartbeat): is the device under test running, connected, at the bus's "
                           f"bitrate and with the same --key-file?")
        raise FccTimeout(f"{dev.label} did not send an authenticated heartbeat within {timeout:g} s "
                         f"(a key different from fcc's?)")

    def accept(self, frame_id: int, data: bytes) -> list[tuple[int, bytes]]:
        """fcc's frames to act on: secured ones only after their authenticator verified."""
        return self.security.receive(frame_id, data)

    def note_frame(self, frame_id: int, data: bytes) -> None:
        """Keep authenticated heartbeat frames (decoded after the run, off the hot path); a
        heartbeat of another fcc under this run's key fails the run (RigError)."""
        auth_id, _, members = self._hb_auth
        if frame_id in members:
            self._hb_latest[frame_id] = bytes(data)
        got = self.accept(frame_id, data)
        if frame_id == auth_id:
            if not got:
                self._check_second_fcc(data)
            self._hb_latest = {}
        for fid, d in got:
            if fid >= 0x700:
                self.status_frames.append((fid, d))

    def _check_second_fcc(self, auth: bytes) -> None:
        """A heartbeat that failed under our fcc's trip but verifies under the trip it
        announces: a second fcc with this run's key answers on the bus (no race: every
        heartbeat of the run is looked at, not a listen before the start)."""
        trip = self.security.trip
        _, data_id, members = self._hb_auth
        latest = self._hb_latest
        session = latest.get(self.security.session_id)
        if trip is None or session is None or len(auth) != 8 or not all(m in latest for m in members):
            return
        other = int.from_bytes(session[:4], "little")
        if other == trip:
            return
        fv = (other << 32) | int.from_bytes(auth[:2], "little")
        if same_mac(mac(self.security.key, data_id, b"".join(latest[m] for m in members), fv), auth[2:8]):
            raise RigError(f"a second fcc is on {self.iface} (its heartbeat announces trip "
                           f"{other:#010x} and verifies under this run's key; this run's fcc has "
                           f"trip {trip:#010x}): stop it; the run is not evaluated")

    def secure(self, frame_id: int, data: bytes) -> list[tuple[int, bytes]]:
        """A frame to send, followed by its authenticator when it commands or configures."""
        return self.security.protect(frame_id, data)

    @property
    def status(self) -> StatusCounters:
        """fcc's counters as of the last heartbeat received."""
        return StatusCounters.from_frames(self.spec, self.status_frames)

    # -- sending
    def message_frames(self, name: str, values: Mapping[str, float | int]) -> list[tuple[int, bytes]]:
        """One message of the simulator as it goes on the bus: E2E-protected, followed by its
        authenticator when it commands or configures."""
        frame_id, data = self.codec.encode(name, values)
        return self.secure(frame_id, data)

    def send_message(self, name: str, values: Mapping[str, float | int]) -> None:
        assert self.link is not None
        for fid, d in self.message_frames(name, values):
            self.link.send_raw(pack_frame(fid, d))

    def control(self, command: int = COMMAND_NONE, period: float = 0.0, bits: int = 0) -> None:
        """SIM_CONTROL: 0 none / 1 shutdown / 2 reset / 3 flight / 4 ground; a new LQG period
        and/or D/A bits (fcc accepts reset, designs and shutdown on the ground only)."""
        self.send_message("SIM_CONTROL", {"command": command, "lqg_period": period, "da_bits": bits})
        if command == COMMAND_RESET:  # fcc resynchronises its E2E receivers on a reset
            self.tick_rx.reset()

    def fcc_accepts_tick(self, data: bytes, app: int, k: int) -> bool:
        """Will fcc run step k of app on this tick frame?  The checks fcc makes, in its order
        (length, E2E, range), on a mirror of its receiver state (which this call updates)."""
        if len(data) != 8:
            return False
        if not self.tick_rx.check(data).data_usable:
            return False
        vals = decode_values(self._tick_msg, data)
        return vals is not None and int(vals["app"]) == app and int(vals["step"]) == k

    def check_alive(self, what: str) -> None:
        assert self.fcc is not None
        if self.fcc.poll() is not None:
            raise FccDied(f"{self.fcc.label} died {what} ({self.fcc.describe_exit()})")

    def shutdown(self, timeout: float = 5.0) -> int:
        """SIM_CONTROL shutdown; wait for fcc's exit and its last heartbeat.  A device the rig
        does not own (external) is left running: the rig waits for its next heartbeat, so that
        the counters include the last step."""
        assert self.fcc is not None and self.link is not None
        if not self.fcc.owned:
            self._next_heartbeat(timeout)
            return 0
        if self.fcc.poll() is None:
            self.control(COMMAND_GROUND)
            self.control(COMMAND_SHUTDOWN)
            deadline = time.monotonic() + timeout
            while self.fcc.poll() is None and time.monotonic() < deadline:
                got = self.link.recv()
                if got is not None:
                    self.note_frame(*got)
        for got in self.link.drain():
            self.note_frame(*got)
        rc = self.fcc.stop()
        self.fcc_exit = rc
        if rc != 0:
            raise FccDied(f"{self.fcc.label} did not exit cleanly after the shutdown command "
                          f"({self.fcc.describe_exit()})")
        failed = {app: n for app, n in step_errors(self.run_dir / "fcc.log").items() if n}
        if failed:  # an estimate or command of a failed step is stale: no results from it
            raise RigError("fcc reported failed steps (" + ", ".join(
                f"{app} {n}" for app, n in failed.items()) + "); its step error lines are in "
                "fcc.log; the run is not evaluated")
        return rc

    def _next_heartbeat(self, timeout: float) -> bool:
        """Until a whole heartbeat (FCC_BUS_COUNTS is its last frame) has come."""
        assert self.link is not None
        last_id = self.spec.by_name(STATUS_FRAMES[-1]).frame_id
        for got in self.link.drain():
            self.note_frame(*got)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            frame = self.link.recv()
            if frame is not None:
                self.note_frame(*frame)
                if frame[0] == last_id:
                    return True
        return False

    def close(self) -> None:
        """Stop the time master and fcc, then the recorder (bus.log is moved into place on
        every path, also when the interface is gone), then close the socket."""
        try:
            if self.inject is not None:
                self.inject.close()
                self.inject = None
            if self.transmitter is not None:
                self.transmitter_stats = self.transmitter.close()
                self.transmitter = None
            if self.time_master is not None:
                self.time_master.stop()
                self.time_master_stats = self.time_master.stats()
                self.time_master = None
            if self.fcc is not None:
                self.fcc.stop(grace=0.0)
                if self.fcc_exit is None:
                    self.fcc_exit = self.fcc.returncode
                if self.fcc.owned and _device_stopped is not None:
                    _device_stopped()
        finally:
            if self.batch_scheduled:  # the simulator's own process: back to the default policy
                run_as_batch([0], batch=False)
            self._stop_recorder()
            self._close_link()
            self._stop_wire()

    def _stop_wire(self) -> None:
        """canbus stopped (SIGTERM), its statistics kept, the pairs deleted."""
        if self.wire is None:
            return
        wire, self.wire = self.wire, None
        try:
            self.bus_stats = wire.stop()
        except RigError as e:
            self.bus_error = str(e)
        finally:
            wire.close()

    def _stop_recorder(self) -> None:
        if self.bus_recorder is None:
            return
        marker = None
        if self.link is not None:  # the end marker: the recorder has seen everything before it
            ping = self.spec.by_name("RIG_PING")
            data = ping.encode({"seq": END_MARKER_SEQ, "t_send_us": 0})
            try:
                if self.link.send(ping.frame_id, data):
                    marker = f"{ping.frame_id:03X}#{data.hex().upper()}".encode()
            except (OSError, LinkError):  # the interface is down: the log ends where it ends
                marker = None
        if marker is not None and self.wire is not None:
            try:  # the marker is on the wire: the recorder has it once canbus has delivered it
                self.wire.drain()
            except RigError as e:
                self.bus_error = str(e)
        recorder, self.bus_recorder = self.bus_recorder, None
        self.log_complete = recorder.stop(marker)
        if not self.log_complete and isinstance(recorder, BusRecorder):
            self.recorder_error = recorder.error()

    def _close_link(self) -> None:
        if self._key_dir is not None:
            shutil.rmtree(self._key_dir, ignore_errors=True)
            self._key_dir = None
        if self.link is not None:
            self.link_stats = {"tx_frames": self.link.tx_frames, "rx_frames": self.link.rx_frames,
                               "tx_retries": self.link.tx_retries, "tx_dropped": self.link.tx_dropped}
            self.link.close()
            self.link = None
