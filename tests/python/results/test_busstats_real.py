"""A real bus's section (hil.results.busstats_real): the simulator's frame k sent is paired with
frame k of its identifier recorded; counts that differ or a recording before the send are not
paired at a guess; the device's frames are counted and bounded, not measured; a sensor frame
whose response time exceeds its bound fails the run as on the modelled bus."""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from hil.bus import load
from hil.bus.candump import LogFrame
from hil.results.busstats import ABOVE, WITHIN, bus_failure
from hil.results.busstats_table import format_bus
from hil.results.busstats_real import DEVICE_WHY, OTHER_WHY, read_sends, real_bus_section, response_times
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.txsched import SEND_LOG, SEND_LOG_HEADER
from hil.runs import evaluate
from hil.scenario.file import load_default_scenario

SPEC = load()
GYRO, ACC, CMD, SYNC = (SPEC.by_name(n).frame_id for n in ("MSL_RATE_GYRO", "MSL_ACCELEROMETER",
                                                            "MSL_ELEV_CMD", "TSYNC_SYNC"))
T0 = 1_700_000_000.0


def frame(t: float, fid: int) -> LogFrame:
    return LogFrame(T0 + t, "vcan0", fid, bytes(8))


def send_log(tmp: Path, sends: list[tuple[float, int]]) -> Path:
    p = tmp / "sim_sends.csv"
    p.write_text(SEND_LOG_HEADER + "\n" + "".join(f"{round((T0 + t) * 1e9)},{i}\n" for t, i in sends))
    return p


def test_pairs_the_kth_sent_with_the_kth_recorded(tmp_path: Path) -> None:
    # gyro sent every 0.1 s, each recorded 0.3 ms later but the third 1.2 ms; accelerometer
    # recorded once less than sent; fcc's command and the master's SYNC only recorded
    sends = [(k * 0.1, GYRO) for k in range(5)] + [(k * 0.1 + 2e-5, ACC) for k in range(5)]
    log = [frame(k * 0.1 + (1.2e-3 if k == 2 else 3e-4), GYRO) for k in range(5)]
    log += [frame(k * 0.1 + 5e-4, ACC) for k in range(4)]
    log += [frame(k * 0.1 + 0.01, CMD) for k in range(5)] + [frame(0.05, SYNC)]
    s = real_bus_section(log, read_sends(send_log(tmp_path, sends)), SPEC, [load_default_scenario("missile")],
                         250_000)
    assert s["model"] == "real" and s["bitrate"] == 250_000 and s["frames_on_bus"] == 15
    g = s["frames"]["MSL_RATE_GYRO"]
    assert g["n"] == 5 and g["p50_s"] == pytest.approx(3e-4, abs=2e-6)
    assert g["max_s"] == pytest.approx(1.2e-3, abs=2e-6) and g["p99_s"] == g["max_s"]
    assert g["verdict"] == WITHIN and g["wcrt_s"] > g["max_s"] and g["queue"] == "prio"
    nm = s["not_measured"]
    assert nm["MSL_ACCELEROMETER"]["why"] == "5 sent, 4 recorded: not paired"
    # the device's policy unknown, it is bounded as a FIFO node (hil.rig.wirebus.FIFO_SENDERS)
    assert nm["MSL_ELEV_CMD"] == {"id": CMD, "n": 5, "wcrt_s": pytest.approx(19.98e-3), "why": DEVICE_WHY}
    assert nm["TSYNC_SYNC"]["why"] == OTHER_WHY and bus_failure(s) == ""
    # the table a run prints: measured frames by identifier, then the others, each reason once
    table = format_bus(s).splitlines()
    assert table[0].startswith("Bus at 250000 bit/s (a real bus, utilisation ")
    assert table[2].split() == ["0x040", "MSL_RATE_GYRO", "prio", "5", "0.300", "1.200", "1.200", "5.400", "within"]
    assert [ln.split()[1] for ln in table[3:6]] == ["TSYNC_SYNC", "MSL_ELEV_CMD", "MSL_ACCELEROMETER"]
    assert table[-3:] == [f"[1] {OTHER_WHY}", f"[2] {DEVICE_WHY}", "[3] 5 sent, 4 recorded: not paired"]


def test_a_recording_before_its_send_is_not_paired() -> None:
    r = response_times(np.array([1.0, 2.0]), np.array([1.001, 1.990]))
    assert r == "recorded 10.000 ms before it was sent: not paired"


def test_above_its_bound_on_a_real_bus_fails_the_run(tmp_path: Path) -> None:
    sends = [(k * 0.1, GYRO) for k in range(3)]
    log = [frame(k * 0.1 + (9e-3 if k == 1 else 3e-4), GYRO) for k in range(3)]   # bound 5.40 ms
    s = real_bus_section(log, read_sends(send_log(tmp_path, sends)), SPEC, [load_default_scenario("missile")],
                         250_000)
    assert s["frames"]["MSL_RATE_GYRO"]["verdict"] == ABOVE
    assert bus_failure(s).startswith("MSL_RATE_GYRO's response time above its bound: 9.000 ms > 5.400 ms")


@pytest.mark.parametrize("text", [None, "t,id\n1,2\n", SEND_LOG_HEADER + "\n12x,64\n"])
def test_a_missing_or_malformed_send_log_is_one_rig_error(tmp_path: Path, text: str | None) -> None:
    """The run's evaluation says the real bus is not judged, in one line (exit 1), no traceback."""
    (tmp_path / "bus.log").write_text(f"({T0:.6f}) vcan0 040#0000000000000000\n")
    if text is not None:
        (tmp_path / SEND_LOG).write_text(text)
    cfg = RigConfig(out_dir=tmp_path, mode="realtime", target="external", bus="wire")
    flown = SimpleNamespace(bus={}, transmitter={})
    with pytest.raises(RigError, match=r"^sim_sends.csv: the simulator's send times are not readable \(.+\); "
                                       r"the real bus is not judged$"):
        evaluate._bus(tmp_path, cfg, flown, [load_default_scenario("missile")])  # type: ignore[arg-type]
