"""The Cortex-M4F image under QEMU (mps2-an386), spoken to over its SLCAN pty.

No vcan: the test is the host end of the serial line (what slcand would be),
with the project's own frame codec (hil.bus) for the frames and E2E.  It boots
the real image (build-m4f/bin/fcc_m4f.elf, cross-built here if missing), opens
the channel, flies lockstep steps of both applications and checks the outputs
against sid_replay (the host identification, double precision), feeds the line
garbage, and shuts the image down through SIM_CONTROL; then the boot
configuration record (realtime mode; a corrupted record refused).
"""
from __future__ import annotations

import csv
import io
import os
import subprocess
import time
from pathlib import Path

import pytest
from fcc_harness import flight, missile_sensors

from hil.bus import SIM_NODES, load
from hil.bus.codec import Decoded, FrameCodec
from hil.bus.secoc import TEST_KEY_FILE, Endpoint, read_key_file
from hil.targets import board as qemu
from hil.targets.bootcfg import BootConfig

pytestmark = pytest.mark.skipif(qemu.available() is None,
                                reason="qemu-system-arm is not installed (scripts/setup installs it)")

REPO = Path(__file__).resolve().parents[3]
STATUS = tuple(range(0x700, 0x709))  # the authenticated heartbeat group, FCC_SYNC_STATUS (0x705) and
#                                      FCC_SYNC_REFUSALS (0x708) in it
FILTER_PREFIX = {"azkf": "SID_AZKF", "zkf": "SID_ZKF", "kf": "SID_KF"}
TIMEOUT = 20.0  # generous: a loaded 2-core machine, TCG


@pytest.fixture(scope="module")
def elf() -> Path:
    build = Path(os.environ.get("FCC_M4F_BUILD_DIR", REPO / "build-m4f"))
    image = build / "bin" / "fcc_m4f.elf"
    subprocess.run(["cmake", "-S", str(REPO), "-B", str(build), "-G", "Ninja",
                    f"-DCMAKE_TOOLCHAIN_FILE={REPO / 'cmake/arm-none-eabi-cortex-m4f.cmake'}"],
                   check=True, capture_output=True)
    subprocess.run(["cmake", "--build", str(build), "--target", "fcc_m4f.elf"], check=True,
                   capture_output=True)
    assert image.exists()
    return image


class Sim:
    """The simulator's side over the SLCAN link (commands authenticated with the image's key,
    the published test key; its secured frames taken only once authenticated)."""

    def __init__(self, link: qemu.SlcanLink) -> None:
        self.link = link
        self.codec = FrameCodec(nodes=SIM_NODES)
        self.sec = Endpoint(load(), read_key_file(TEST_KEY_FILE), SIM_NODES)
        self.status: dict[str, dict] = {}

    def send(self, name: str, values: dict) -> None:
        for fid, data in self.sec.protect(*self.codec.encode(name, values)):
            self.link.send(fid, data)

    def _authentic(self, timeout: float):
        for frame_id, data in self.link.frames(timeout):
            yield from self.sec.receive(frame_id, data)

    def frames(self, timeout: float):
        for frame_id, data in self._authentic(timeout):
            d = self.codec.decode(frame_id, data)
            if frame_id in STATUS:
                if d.ok and d.name is not None:
                    self.status[d.name] = d.values
                continue
            yield d

    def until_ack(self, app: int, k: int) -> tuple[dict[str, dict], Decoded]:
        got: dict[str, dict] = {}
        order: list[str] = []
        for d in self.frames(TIMEOUT):
            assert d.ok, d
            if d.name == "FCC_ACK" and d.values["app"] == app and d.values["step"] == k:
                assert len(order) == len(set(order)), order
                return got, d
            got[d.name] = d.values
            order.append(d.name)
        raise AssertionError(f"no FCC_ACK({app}, {k}) within {TIMEOUT} s")

    def wait_status(self) -> dict[str, dict]:
        """The next complete heartbeat (the eight status frames); other frames dropped."""
        self.status.clear()
        for frame_id, data in self._authentic(TIMEOUT):
            d = self.codec.decode(frame_id, data)
            if frame_id in STATUS and d.ok and d.name is not None:
                self.status[d.name] = d.values
                if len(self.status) == len(STATUS):
                    return self.status
        raise AssertionError(f"no complete heartbeat within {TIMEOUT} s: {self.status}")

    def cdrw_step(self, k: int) -> tuple[dict[str, dict], Decoded]:
        alpha, q, de = flight(k)
        self.send("CDRW_AOA", {"step": k, "alpha": alpha})
        self.send("CDRW_PITCH_RATE", {"step": k, "q": q})
        self.send("CDRW_ELEVATOR", {"step": k, "delta_e": de})
        self.send("SIM_TICK", {"app": 0, "step": k})
        return self.until_ack(0, k)

    def missile_step(self, k: int) -> tuple[dict[str, dict], Decoded]:
        q_g, n_a = missile_sensors(k)
        self.send("MSL_RATE_GYRO", {"step": k, "q_g": q_g})
        self.send("MSL_ACCELEROMETER", {"step": k, "n_a": n_a})
        self.send("SIM_TICK", {"app": 1, "step": k})
        return self.until_ack(1, k)


def test_lockstep_flight_bad_input_and_shutdown(elf, tmp_path, bin_path):
    n = 20
    with qemu.Board(elf, tmp_path) as board:
        link = board.link()
        sim = Sim(link)
        status = sim.wait_status()  # the heartbeat on open: "listening", authenticated
        assert status["FCC_STATUS"]["mode"] == 0 and status["FCC_STATUS"]["op_mode"] == 0
        assert status["FCC_SYNC_STATUS"]["state"] == 0   # authenticated; no time master here: free-run
        sim.send("SIM_CONTROL", {"command": 3, "lqg_period": 0, "da_bits": 0})  # FLIGHT
        assert link.command(b"V") == b"V0110"
        assert link.command(b"S4") == b"\a"  # no bitrate change while open

        outputs = []
        for k in range(n):
            frames, ack = sim.cdrw_step(k)
            assert ack.values["degraded"] == 0
            assert sorted(frames) == sorted(f"{p}_{s}" for p in FILTER_PREFIX.values()
                                            for s in ("STATE", "BOUNDS", "MODEL_A", "MODEL_B"))
            outputs.append(frames)
        for k in range(5):
            frames, ack = sim.missile_step(k)
            assert list(frames) == ["MSL_ELEV_CMD", "MSL_STATE_EST"]  # the command authenticated
            assert frames["MSL_ELEV_CMD"]["step"] == k and frames["MSL_ELEV_CMD"]["da_bits"] == 8

        # garbage on the line: every bad line answered BEL and counted, the flight goes on
        # (Ctrl-A x is QEMU's multiplexer escape for "exit" unless -echr moves it off the bytes)
        garbage = [b"t12\r", b"x" * 300 + b"\r", b"t0101\x00\xffAA\r", b"T1FFFFFFF0\r", b"\xfe\r",
                   b"\x01x\r"]
        for g in garbage:
            link.write(g)
        frames, ack = sim.cdrw_step(n)
        assert len(frames) == 12 and ack.values["degraded"] == 0
        bus = sim.wait_status()["FCC_BUS_COUNTS"]
        assert bus["bus_errors"] == 1 + 5  # S4 above + five bad lines (the T frame is only ignored)
        assert link.answers.count(b"\a") >= 5

        sim.send("SIM_CONTROL", {"command": 1, "lqg_period": 0, "da_bits": 0})  # refused in flight
        assert sim.wait_status()["FCC_SEC_COUNTS"]["mode_refused"] == 1
        sim.send("SIM_CONTROL", {"command": 4, "lqg_period": 0, "da_bits": 0})  # GROUND
        sim.send("SIM_CONTROL", {"command": 1, "lqg_period": 0, "da_bits": 0})
        assert board.exit_status(TIMEOUT) == 0
        log = board.log()
    assert "fcc summary: cdrw steps=21 degraded=0" in log, log
    assert "fcc summary: missile steps=5" in log, log
    assert "overlong=1 noise=3" in log, log

    # the same identification as the host's sid_replay (double) to float resolution
    # (sid_replay wants a whole MLS window of data; the filters are causal)
    data = io.StringIO()
    w = csv.writer(data)
    w.writerow(["t", "alpha", "q", "de"])
    w.writerows((0.02 * k, *flight(k)) for k in range(120))
    replay = subprocess.run([str(bin_path("sid_replay")), "--filter", "all"], input=data.getvalue(),
                            capture_output=True, text=True, check=True)
    rows = [r for r in csv.DictReader(io.StringIO(replay.stdout)) if float(r["t"]) < 0.02 * n - 0.01]
    assert len(rows) == 3 * n
    for row in rows:
        k = round(float(row["t"]) / 0.02)
        st = outputs[k][f"{FILTER_PREFIX[row['filter']]}_STATE"]
        assert st["alpha_hat"] == pytest.approx(float(row["alpha_hat"]), abs=2e-5)
        assert st["q_hat"] == pytest.approx(float(row["q_hat"]), abs=2e-5)
        assert st["order"] == int(row["order"])


def test_boot_record_realtime(elf, tmp_path):
    config = BootConfig(mode="realtime", apps=("missile",), lqg_period=0.1, lqg_bits=12, lqg_delay=0.005)
    with qemu.Board(elf, tmp_path, config=config, lockstep=False) as board:
        sim = Sim(board.link())
        assert sim.wait_status()["FCC_STATUS"]["mode"] == 1
        sim.send("SIM_CONTROL", {"command": 3, "lqg_period": 0, "da_bits": 0})  # FLIGHT
        commands = []
        for d in sim.frames(TIMEOUT):
            if d.name == "MSL_ELEV_CMD":
                commands.append(d.values)
                if len(commands) == 5:
                    break
        first = commands[0]["step"]
        assert [c["step"] for c in commands] == list(range(first, first + 5))  # its own clock
        assert all(c["da_bits"] == 12 and c["degraded"] == 1 for c in commands)  # no sensors
    assert "boot configuration record applied" in board.log()


def test_time_sync_is_authenticated_on_the_image(elf, tmp_path):
    """The image follows only authenticated time-master pairs (TSYNC_AUTH, under its key and
    trip): 30 intervals, each the red team's forgery first -- SYNC + FOLLOW_UP of the master's
    next sequence number with its alive counters, 50 ms behind, and a TSYNC_AUTH with a guessed
    MAC -- then the master's pair and its authenticator.  Realtime board (its clock is the
    host's), the stamp taken when the SLCAN line is decoded."""
    from hil.bus.e2e import protect

    config = BootConfig(mode="realtime", apps=("missile",), lqg_period=0.1, lqg_bits=12,
                        lqg_delay=0.005)
    spec = load()
    sync_msg, fup_msg = spec.by_name("TSYNC_SYNC"), spec.by_name("TSYNC_FOLLOW_UP")
    auth_id = spec.by_name("TSYNC_AUTH").frame_id

    def frames(seq: int, m_us: int, counter: int) -> tuple[bytes, bytes]:
        sec = m_us // 1_000_000
        s_raw = sync_msg.message.encode({"crc": 0, "counter": 0, "master": 1, "seq": seq,
                                         "interval_ms": 100, "sec": sec})
        f_raw = fup_msg.message.encode({"crc": 0, "counter": 0, "master": 1, "seq": seq,
                                        "sec_carry": 0, "ns": (m_us % 1_000_000) * 1000})
        return protect(sync_msg.data_id, s_raw, counter), protect(fup_msg.data_id, f_raw, counter)

    n = 30
    with qemu.Board(elf, tmp_path, config=config, lockstep=False) as board:
        link = board.link()
        sim = Sim(link)
        sim.wait_status()   # fcc's trip, for the master's authenticator
        sender = sim.sec.group_sender("TSYNC_AUTH")
        t0 = time.monotonic() - 5.0
        for i in range(n):
            m = int((time.monotonic() - t0) * 1e6)
            fs, ff = frames(i, m - 50_000, i % 16)     # the forger, first, same counters
            link.send(sync_msg.frame_id, fs)
            link.send(fup_msg.frame_id, ff)
            link.send(auth_id, (i + 1).to_bytes(2, "little") + bytes(6))
            m = int((time.monotonic() - t0) * 1e6)
            gs, gf = frames(i, m, i % 16)
            link.send(sync_msg.frame_id, gs)
            link.send(fup_msg.frame_id, gf)
            link.send(auth_id, sender.protect(gs + gf))
            for _ in sim.frames(0.1):
                pass
        for _ in sim.frames(0.5):   # the last interval's frames handled before the heartbeat
            pass
        status = sim.wait_status()
        sim.send("SIM_CONTROL", {"command": 1, "lqg_period": 0, "da_bits": 0})  # SHUTDOWN
        assert board.exit_status(TIMEOUT) == 0
        log = board.log()
    r = status["FCC_SYNC_REFUSALS"]
    assert r["unauthenticated"] == 2 * n and r["mac_failed"] == n and r["freshness_failed"] == 0
    assert status["FCC_SYNC_STATUS"]["syncs"] >= 1   # the master's pairs reach its servo
    assert f"fcc summary: sync_refused mac_failed={n} freshness_failed=0 unauthenticated={2 * n}" in log, log


def test_corrupt_boot_record_is_refused(elf, tmp_path):
    good = BootConfig().encode()
    for name, record in [("crc", good[:20] + bytes([good[20] ^ 1]) + good[21:]),
                         ("lqg_bits", BootConfig(lqg_bits=17).encode()),
                         ("lqg_delay", BootConfig(lqg_period=0.05, lqg_delay=0.05).encode())]:
        path = tmp_path / f"{name}.bin"
        path.write_bytes(record)
        cmd = qemu.command(elf, log=tmp_path / f"{name}.log", bootcfg_file=path)
        assert subprocess.run(cmd, capture_output=True, timeout=TIMEOUT).returncode == 2
        assert f"boot configuration refused: field {name}" in (tmp_path / f"{name}.log").read_text()
