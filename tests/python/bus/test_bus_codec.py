"""FrameCodec (the Python twin of fcc_bus.c), bus-load arithmetic, candump logs, scripts/diag."""
from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import pytest

from hil.bus import FCC_NODE, SIM_NODES, dbc
from hil.bus import busload
from hil.bus.candump import LogFormatError, format_line, parse_line
from hil.bus.codec import EncodeError, FrameCodec, Verdict, decode_values
from hil.bus.diag import main as diag_main
from hil.bus.e2e import E2EStatus


@pytest.fixture()
def sim() -> FrameCodec:
    return FrameCodec(nodes=SIM_NODES)


@pytest.fixture()
def fcc() -> FrameCodec:
    return FrameCodec(nodes=FCC_NODE)


def test_node_message_sets(sim: FrameCodec, fcc: FrameCodec) -> None:
    assert {"SIM_TICK", "CDRW_AOA", "MSL_RATE_GYRO", "SIM_CONTROL"} <= sim.produces
    assert {"FCC_ACK", "MSL_ELEV_CMD", "SID_KF_MODEL_B", "FCC_STATUS"} <= sim.consumes
    assert fcc.consumes >= {"SIM_TICK", "CDRW_AOA", "SIM_EVENT"}
    assert "FCC_ACK" not in fcc.consumes
    with pytest.raises(ValueError):
        FrameCodec(nodes="NOBODY")


def test_round_trip_sim_to_fcc(sim: FrameCodec, fcc: FrameCodec) -> None:
    for step in range(20):
        fid, data = sim.encode("CDRW_AOA", {"step": step, "alpha": 0.157 + 1e-6 * step})
        d = fcc.decode(fid, data, timestamp=1.0)
        assert d.ok and d.name == "CDRW_AOA" and d.e2e is E2EStatus.OK
        assert d.values == {"step": step, "alpha": pytest.approx(0.157 + 1e-6 * step, abs=5e-7)}
    assert fcc.counters.e2e[E2EStatus.OK] == 20


def test_encode_refusals_keep_the_counter(fcc: FrameCodec) -> None:
    good = {"alpha_hat": 0.1, "q_hat": 0.0, "order": 2, "fault": 0, "degraded": 0, "step": 1}
    for bad in ({"q_hat": math.nan}, {"q_hat": math.inf}, {"q_hat": 5.3}, {"q_hat": 1e300},
                {"step": 4096}, {"order": 1.5}, {"fault": "yes"}):
        with pytest.raises(EncodeError):
            fcc.encode("SID_AZKF_STATE", {**good, **bad})
    with pytest.raises(EncodeError):
        fcc.encode("SID_AZKF_STATE", {k: v for k, v in good.items() if k != "step"})
    with pytest.raises(EncodeError):
        fcc.encode("SID_AZKF_STATE", {**good, "bogus": 1})
    with pytest.raises(EncodeError):
        fcc.encode("SIM_TICK", {"app": 0, "step": 0})  # not the FCC's
    assert fcc.counters.tx_refused == 10
    cmd = {"degraded": 0, "saturated": 0, "step": 3, "da_code": -128, "da_bits": 8}
    for bits in (0, 17):
        with pytest.raises(EncodeError):
            fcc.encode("MSL_ELEV_CMD", {**cmd, "da_bits": bits})
    _, f0 = fcc.encode("MSL_ELEV_CMD", cmd)
    _, f1 = fcc.encode("MSL_ELEV_CMD", cmd)
    assert (f0[1] & 0xF, f1[1] & 0xF) == (0, 1)


def test_saturating_encode(fcc: FrameCodec, sim: FrameCodec) -> None:
    fid, data = fcc.encode("SID_KF_BOUNDS", {"alpha_lo": -7.0, "alpha_hi": 7.0, "q_lo": -0.5,
                                             "q_hi": 0.5}, saturate=True)
    d = sim.decode(fid, data)
    assert d.values == pytest.approx({"alpha_lo": -3.2768, "alpha_hi": 3.2767,
                                      "q_lo": -0.5, "q_hi": 0.5})
    assert fcc.counters.tx_saturated == 1
    with pytest.raises(EncodeError):
        fcc.encode("SID_KF_BOUNDS", {"alpha_lo": math.nan, "alpha_hi": 0, "q_lo": 0, "q_hi": 0},
                   saturate=True)


def test_rounding_is_half_away_from_zero_like_c() -> None:
    sig = dbc.load().by_name("CDRW_AOA").data_signals[-1]
    assert sig.to_raw(2.5e-6) == 3 and sig.to_raw(-2.5e-6) == -3  # Python round() gives 2
    assert dbc.round_half_away(0.49999999999999994) == 0
    assert dbc.round_half_away(-0.5) == -1


def test_e2e_classes_and_rejections(fcc: FrameCodec, sim: FrameCodec) -> None:
    cmd = {"degraded": 0, "saturated": 1, "step": 41, "da_code": -77, "da_bits": 8}
    frames = [fcc.encode("MSL_ELEV_CMD", cmd) for _ in range(6)]
    seq = [(frames[0], E2EStatus.OK), (frames[0], E2EStatus.REPEATED),
           (frames[2], E2EStatus.OK_SOME_LOST), (frames[1], E2EStatus.WRONG_SEQUENCE),
           (frames[2], E2EStatus.OK)]
    for (fid, data), expected in seq:
        assert sim.decode(fid, data).e2e is expected
    fid, data = frames[3]
    assert sim.decode(fid, bytes([data[0] ^ 1]) + data[1:]).e2e is E2EStatus.ERROR
    assert sim.decode(fid, data[:6]).verdict is Verdict.WRONG_DLC
    assert sim.decode(0x124, bytes(8)).verdict is Verdict.UNKNOWN_ID
    assert fcc.decode(*frames[5]).verdict is Verdict.UNKNOWN_ID  # FCC does not consume it
    d = sim.decode(*frames[5])
    assert d.ok and d.e2e is E2EStatus.OK_SOME_LOST and d.values == cmd
    c = sim.counters
    assert (c.e2e[E2EStatus.OK], c.e2e[E2EStatus.REPEATED], c.e2e[E2EStatus.OK_SOME_LOST],
            c.e2e[E2EStatus.WRONG_SEQUENCE], c.e2e[E2EStatus.ERROR]) == (2, 1, 2, 1, 1)
    assert (c.wrong_dlc, c.unknown_id) == (1, 1)


def test_out_of_range_rejected(fcc: FrameCodec) -> None:
    msg = dbc.load().by_name("CDRW_AOA")
    raw = msg.message.encode({"crc": 0, "counter": 0, "step": 5, "alpha": 1570801},
                             scaling=False, strict=False)
    from hil.bus.e2e import protect
    d = fcc.decode(msg.frame_id, protect(msg.data_id, bytes(raw), 0))
    assert d.verdict is Verdict.OUT_OF_RANGE and d.e2e is E2EStatus.OK and d.values is None
    assert fcc.counters.out_of_range == 1


def test_no_new_data(fcc: FrameCodec, sim: FrameCodec) -> None:
    for step in range(10):
        fid, data = sim.encode("CDRW_AOA", {"step": step, "alpha": 0.15})
        if step % 3:
            fcc.decode(fid, data)
        assert fcc.end_period("CDRW_AOA") == (step % 3 == 0)
        assert fcc.end_period("CDRW_PITCH_RATE")
    assert fcc.counters.e2e[E2EStatus.NO_NEW_DATA] == 14
    assert fcc.counters.stale_now == 2
    assert not fcc.end_period("FCC_ACK")


# ---- bus load ------------------------------------------------------------------

def test_frame_lengths() -> None:
    assert busload.nominal_bits(8) == 111
    assert busload.worst_case_bits(8) == 135
    assert busload.worst_case_bits(0) == 55
    for fid, data in [(0x000, bytes(8)), (0x7FF, b"\xff" * 8), (0x555, bytes([0x55] * 8)),
                      (0x020, bytes(range(8))), (0x100, b"")]:
        bits = busload.frame_bits(fid, data)
        assert busload.nominal_bits(len(data)) <= bits <= busload.worst_case_bits(len(data))
    # alternating bits need no stuffing at all
    assert busload.frame_bits(0x555, bytes([0x55] * 8)) - busload.nominal_bits(8) < 4
    with pytest.raises(ValueError):
        busload.frame_bits(0x1, bytes(9))


def test_crc15_of_frame_with_its_crc_is_zero() -> None:
    body = [0] + busload._bits(0x123, 11) + [0, 0, 0] + busload._bits(2, 4) + busload._bits(0xBEEF, 16)
    crc = busload._crc15(body)
    assert busload._crc15(body + busload._bits(crc, 15)) == 0


def test_stuff_count() -> None:
    assert busload._stuff_count([0] * 5) == 1
    assert busload._stuff_count([0] * 9) == 1   # 00000 s 0000: the stuff bit ends the run
    assert busload._stuff_count([0] * 10) == 2  # 00000 s 00000 s
    assert busload._stuff_count([0, 0, 0, 0, 1, 1, 1, 1]) == 0
    # a stuff bit counts in the next run: 00000 (s=1) 1111 -> 5 ones -> another stuff bit
    assert busload._stuff_count([0] * 5 + [1] * 4) == 2
    assert busload._stuff_count([1, 0] * 20) == 0


# ---- candump -------------------------------------------------------------------

def test_candump_lines() -> None:
    f = parse_line("(1700000000.123456) vcan0 050#3105070048650200")
    assert (f.frame_id, f.data.hex(), f.channel, f.extended) == (0x50, "3105070048650200", "vcan0", False)
    assert parse_line("(1.5) vcan0 20000080#0000000000000000").error
    assert parse_line("(1.5) vcan0 12345678#11").extended
    assert parse_line("(1.5) vcan0 123#R").remote
    assert parse_line("(1.5) vcan0 123##1AABB").fd
    for bad in ("vcan0 123#00", "(1.0) vcan0 12#00", "(1.0) vcan0 123#0", "(1.0) vcan0 123#" + "00" * 9):
        with pytest.raises(LogFormatError):
            parse_line(bad)
    line = format_line(12.5, "vcan0", 0x50, bytes.fromhex("3105070048650200"))
    assert line == "(12.500000) vcan0 050#3105070048650200"
    assert parse_line(line).data == bytes.fromhex("3105070048650200")


# ---- diag on a synthetic log -----------------------------------------------------

def _write_log(path: Path) -> None:
    sim = FrameCodec(nodes=SIM_NODES)
    lines = []
    t = 1000.0
    for step in range(100):
        t = 1000.0 + 0.02 * step + (0.001 if step % 2 else 0.0)  # 1 ms jitter
        fid, data = sim.encode("CDRW_AOA", {"step": step, "alpha": 0.1})
        if step == 50:
            continue  # one lost AoA frame: OK_SOME_LOST next, one NO_NEW_DATA period
        lines.append(format_line(t, "vcan0", fid, data))
        if step == 70:
            lines.append(format_line(t + 0.0001, "vcan0", fid, data))  # repeated
        if step == 80:
            lines.append(format_line(t + 0.0002, "vcan0", fid, bytes([data[0] ^ 1]) + data[1:]))
    lines.append(format_line(t + 0.001, "vcan0", 0x124, bytes(8)))
    lines.append("(%.6f) vcan0 20000080#0000000000000000" % (t + 0.002))
    path.write_text("\n".join(lines) + "\n")


def test_diag_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = tmp_path / "run.log"
    _write_log(log)
    assert diag_main(["--log", str(log), "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    (aoa,) = [m for m in rep["messages"] if m["name"] == "CDRW_AOA"]
    assert aoa["count"] == 101  # 99 + 1 repeat + 1 bad CRC
    assert aoa["e2e"] == {"OK": 98, "REPEATED": 1, "OK_SOME_LOST": 1, "WRONG_SEQUENCE": 0,
                          "ERROR": 1, "NO_NEW_DATA": 1}
    assert rep["unknown_ids"] == {"124": 1}
    assert rep["error_frames"] == 1
    assert 0 < rep["load_exact_pct"] <= rep["load_worst_pct"]
    assert aoa["jitter_std_ms"] > 0.3
    assert diag_main(["--log", str(log)]) == 0
    text = capsys.readouterr().out
    assert "CDRW_AOA" in text and "bus load at 500 kbit/s" in text


def test_diag_bad_input(repo: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.log"
    bad.write_text("(1.0) vcan0 050#31\nthis is not candump\n")
    cases = [["--log", str(tmp_path / "missing.log")], ["--log", str(bad)], [],
             ["--log", str(bad), "--bogus"], ["--iface", "vcan0", "--seconds", "-1"],
             ["--log", str(bad), "--dbc", str(tmp_path / "none.dbc")]]
    for args in cases:
        r = subprocess.run([str(repo / "scripts" / "diag"), *args], capture_output=True,
                           text=True, check=False)
        assert r.returncode == 2, args
        assert r.stdout == ""
        assert len(r.stderr.strip().splitlines()) == 1, (args, r.stderr)
        assert r.stderr.startswith("diag: ")


def test_decode_values_is_decode_raw_range_checked_and_scaled() -> None:
    """The one-pass decode of the data signals (hil.bus.codec.decode_values, over the message's
    field table) gives what decoding every raw value, checking its range and scaling it gives,
    value types included; on random frames and on random in-range frames of every message."""
    import random
    rng = random.Random(26)
    for m in dbc.load().messages:
        for i in range(200):
            if i % 2:
                data = bytes(rng.randrange(256) for _ in range(8))
            else:
                data = m.encode_raw({s.name: rng.randint(s.raw_min, s.raw_max) if s in m.data_signals
                                     else 0 for s in m.signals})
            raw = m.decode_raw(data)
            in_range = all(s.raw_min <= raw[s.name] <= s.raw_max for s in m.data_signals)
            want = {s.name: s.to_phys(raw[s.name]) for s in m.data_signals} if in_range else None
            got = decode_values(m, data)
            assert got == want, m.name
            assert got is None or all(type(got[k]) is type(want[k]) for k in got), m.name  # type: ignore[index]
