"""Python side of the shared bus vectors (the C side is tests/c/test_codec.c, test_e2e.c).

The vectors are what cantools makes of the DBC; the Python codec must decode them
to the same values, re-encode them byte for byte and reject the bad ones with the
same verdict -- as the C codec does, which proves the two byte-compatible.
"""
from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest

from hil.bus import dbc
from hil.bus.codec import FrameCodec, Verdict, decode_values, pack
from hil.bus.e2e import E2EReceiver, E2EStatus, crc8_j1850, protect

VEC = Path(__file__).resolve().parents[2] / "vectors" / "bus"


def _lines(name: str) -> list[list[str]]:
    return [ln.split() for ln in (VEC / name).read_text().splitlines()
            if ln.strip() and not ln.startswith("#")]


@pytest.fixture(scope="module")
def spec() -> dbc.BusSpec:
    return dbc.load()


def test_vectors_are_up_to_date(repo: Path, tmp_path: Path) -> None:
    spec_ = importlib.util.spec_from_file_location("gen_bus_vectors", repo / "tests" / "gen_bus_vectors.py")
    gen = importlib.util.module_from_spec(spec_)
    assert spec_.loader is not None
    spec_.loader.exec_module(gen)
    for path in gen.generate(tmp_path):
        assert path.read_text() == (VEC / path.name).read_text(), (
            f"tests/vectors/bus/{path.name} is stale: run tests/gen_bus_vectors.py")


def test_frames_decode_and_reencode(spec: dbc.BusSpec) -> None:
    seen = set()
    for ident, counter, hex_bytes, name, *pairs in _lines("frames.txt"):
        msg = spec.by_id(int(ident, 16))
        assert msg is not None and msg.name == name
        data = bytes.fromhex(hex_bytes)
        expected = {k: float(v) if "." in v or "e" in v else int(v)
                    for k, v in (p.split("=") for p in pairs)}
        values = decode_values(msg, data)
        assert values is not None
        assert set(values) == set(expected)
        for k, v in expected.items():
            assert math.isclose(values[k], v, rel_tol=0, abs_tol=1e-12), (name, k)
        for source in (values, expected):
            out, clamped = pack(msg, source)
            assert not clamped
            if msg.protected:
                assert counter != "-"
                out = protect(msg.data_id, out, int(counter))
            assert out == data, (name, source)
        seen.add(name)
    assert seen == {m.name for m in spec.messages}


def test_rejects(spec: dbc.BusSpec) -> None:
    n = 0
    for ident, dlc, hex_bytes, verdict, e2e in _lines("rejects.txt"):
        codec = FrameCodec(spec)  # every message, fresh state
        data = bytes.fromhex(hex_bytes)
        assert len(data) == int(dlc)
        d = codec.decode(int(ident, 16), data)
        assert d.verdict is Verdict[verdict], (ident, hex_bytes)
        assert d.e2e is E2EStatus[e2e]
        assert (d.values is not None) == (d.verdict is Verdict.PASS)
        c = codec.counters
        assert c.unknown_id == (verdict == "UNKNOWN_ID")
        assert c.wrong_dlc == (verdict == "WRONG_DLC")
        assert c.out_of_range == (verdict == "OUT_OF_RANGE")
        n += 1
    assert n >= 3 * len(spec.messages)


def test_e2e_sequences() -> None:
    rx: E2EReceiver | None = None
    frames = 0
    for fields in _lines("e2e_seq.txt"):
        if fields[0] == "RESET":
            rx = E2EReceiver(0x1000 | int(fields[1], 16))
        elif fields[0] == "PERIOD":
            assert rx is not None and rx.end_period() == (fields[2] == "1")
        elif fields[0] == "COUNTS":
            assert rx is not None
            assert [rx.counts[s] for s in E2EStatus] == [int(x) for x in fields[2:]]
        else:
            assert rx is not None
            assert rx.check(bytes.fromhex(fields[1])) is E2EStatus[fields[2]]
            frames += 1
    assert frames >= 100


def test_crc_vectors() -> None:
    for hex_data, crc in _lines("crc.txt"):
        data = b"" if hex_data == "-" else bytes.fromhex(hex_data)
        assert crc8_j1850(data) == int(crc, 16)
