"""`hil bus wcrt`: the JSON's schema, the bit rate's sources and forms, a scenario's periods,
the jitter, and the exit statuses (0 all deadlines met, 1 a frame misses or has no bound,
2 a bad command line, DBC or scenario: one line)."""
from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest

from hil.bus import dbc
from hil.bus.wcrt import cyclic_frames
from hil.cli import main
from hil.cli.usage import EXIT_FAILED, EXIT_USAGE

FRAME_KEYS = {"id": int, "name": str, "period_s": float, "c_s": float, "deadline_met": bool}


@pytest.fixture(autouse=True)
def _packaged_dbc(monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:
    """--dbc holds for the process (hil.bus.dbc.set_default): each test starts without one."""
    monkeypatch.setenv(dbc.DBC_ENV, "")  # recorded, so restored after the test as it was
    monkeypatch.delenv(dbc.DBC_ENV)
    dbc.set_default(None)
    yield
    dbc.set_default(None)


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    rc = main(["bus", "wcrt", *argv])
    out, err = capsys.readouterr()
    return rc, out, err


def as_json(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict, str]:
    rc, out, err = run(capsys, "--json", *argv)
    return rc, json.loads(out), err


def one_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith("hil: ")
    return lines[0]


def test_json_schema_at_the_dbcs_bit_rate(capsys: pytest.CaptureFixture[str]) -> None:
    rc, doc, err = as_json(capsys)
    assert (rc, err) == (0, "")
    assert set(doc) == {"bitrate", "utilisation", "frames"}
    assert doc["bitrate"] == dbc.load().baudrate == 500_000  # the DBC's Baudrate
    assert isinstance(doc["utilisation"], float) and 0 < doc["utilisation"] < 1
    names = [f.name for f in cyclic_frames(dbc.load())]
    assert sorted(f["name"] for f in doc["frames"]) == sorted(names)
    for f in doc["frames"]:
        assert set(f) == {*FRAME_KEYS, "wcrt_s", "queue"}
        assert f["queue"] == ("fifo" if list(dbc.load().by_name(f["name"]).senders) == ["FCC"] else "prio")
        assert all(isinstance(f[k], t) for k, t in FRAME_KEYS.items())
        assert isinstance(f["wcrt_s"], float) and f["c_s"] <= f["wcrt_s"] <= f["period_s"]
        assert f["deadline_met"]
    assert doc["utilisation"] == pytest.approx(sum(f["c_s"] / f["period_s"] for f in doc["frames"]))


@pytest.mark.parametrize(("text", "bps"), [("125k", 125_000), ("250000", 250_000), ("1M", 1_000_000)])
def test_bit_rate_forms(capsys: pytest.CaptureFixture[str], text: str, bps: int) -> None:
    rc, doc, _ = as_json(capsys, "--bitrate", text)
    assert doc["bitrate"] == bps
    assert all(f["c_s"] == pytest.approx(135 / bps) for f in doc["frames"])  # 8-byte 11-bit frames


def test_a_slow_bus_fails_with_its_table_and_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    rc, doc, err = as_json(capsys, "--bitrate", "125k")
    assert rc == EXIT_FAILED
    assert doc["utilisation"] > 1
    unbounded = [f for f in doc["frames"] if f["wcrt_s"] is None]
    assert unbounded and not any(f["deadline_met"] for f in unbounded)
    missed = sum(not f["deadline_met"] for f in doc["frames"])
    assert f"{missed} of {len(doc['frames'])} frames miss their deadline" in one_line(err)
    rc, out, err = run(capsys, "--bitrate", "125k")
    assert rc == EXIT_FAILED and out.count("unbounded") == len(unbounded) and "MISSED" in out
    assert "bus utilisation" in out and one_line(err)


def test_the_table(capsys: pytest.CaptureFixture[str]) -> None:
    rc, out, err = run(capsys)
    assert (rc, err) == (0, "")
    lines = out.splitlines()
    assert "at 500000 bit/s (the DBC's Baudrate)" in lines[0]
    assert "FCC FIFO-queued" in lines[1]
    assert lines[2].split()[:4] == ["id", "name", "sender", "queue"]
    tick = next(ln for ln in lines if " SIM_TICK " in ln).split()
    assert tick[0] == "0x020" and tick[2] == "SIM" and tick[3] == "prio" and tick[4] == "20" and tick[-1] == "met"
    ack = next(ln for ln in lines if " FCC_ACK " in ln).split()
    assert ack[2:4] == ["FCC", "fifo"] and ack[-1] == "met"
    assert lines[-1].startswith("bus utilisation 0.") and lines[-1].endswith("(27 of the FIFO's 27)")


def test_fifo_option(capsys: pytest.CaptureFixture[str]) -> None:
    """--fifo: the rig's (fcc) by default; `none` all priority-queued; a node of the DBC; else exit 2."""
    def bounds(*argv: str) -> dict[str, tuple[str, float]]:
        rc, doc, _ = as_json(capsys, "--bitrate", "250k", *argv)
        assert rc == 0
        return {f["name"]: (f["queue"], f["wcrt_s"]) for f in doc["frames"]}
    rig, fcc, none = bounds(), bounds("--fifo", "FCC"), bounds("--fifo", "none")
    assert rig == fcc and rig["FCC_ACK"] == ("fifo", pytest.approx(37 * 540e-6))
    assert none["FCC_ACK"] == ("prio", pytest.approx(7 * 540e-6)) and all(q == "prio" for q, _ in none.values())
    gyro = bounds("--fifo", "MSL_GYRO")
    assert gyro["MSL_RATE_GYRO"][0] == "fifo" and gyro["FCC_ACK"][0] == "prio"
    rc, out, err = run(capsys, "--fifo", "nobody")
    assert (rc, out) == (EXIT_USAGE, "") and "--fifo nobody: not a sender" in one_line(err)


@pytest.mark.parametrize("text", ["2M", "fast", "0", "-500k", "k", "9999"])
def test_bad_bit_rate_is_one_line_and_exit_2(capsys: pytest.CaptureFixture[str], text: str) -> None:
    rc, out, err = run(capsys, f"--bitrate={text}")
    assert (rc, out) == (EXIT_USAGE, "")
    assert "--bitrate" in one_line(err)


def test_bad_jitter_and_dbc_are_exit_2(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    rc, _, err = run(capsys, "--jitter", "-0.001")
    assert rc == EXIT_USAGE and "--jitter" in one_line(err)
    bad = tmp_path / "bad.dbc"
    bad.write_text("garbage\n")
    rc, out, err = run(capsys, "--dbc", str(bad))
    assert (rc, out) == (EXIT_USAGE, "") and "not a DBC this rig reads" in one_line(err)


def test_jitter_lengthens_every_response(capsys: pytest.CaptureFixture[str]) -> None:
    _, plain, _ = as_json(capsys)
    _, jittered, _ = as_json(capsys, "--jitter", "0.001")
    for a, b in zip(plain["frames"], jittered["frames"]):
        assert b["wcrt_s"] >= a["wcrt_s"] + 0.001 - 1e-12


def test_a_dbc_without_baudrate_is_500k_and_says_so(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    text = dbc.load().path.read_text(encoding="utf-8")
    assert 'BA_ "Baudrate" 500000;' in text
    no_rate = tmp_path / "no_rate.dbc"
    no_rate.write_text(text.replace('BA_ "Baudrate" 500000;', "").replace(
        'BA_DEF_DEF_  "Baudrate" 500000;', 'BA_DEF_DEF_  "Baudrate" 250000;'), encoding="utf-8")
    rc, out, _ = run(capsys, "--dbc", str(no_rate))
    assert rc == 0 and "at 500000 bit/s (the DBC has no Baudrate: 500000)" in out.splitlines()[0]
    rate = tmp_path / "rate.dbc"
    rate.write_text(text.replace('BA_ "Baudrate" 500000;', 'BA_ "Baudrate" 1000000;'), encoding="utf-8")
    _, doc, _ = as_json(capsys, "--dbc", str(rate))
    assert doc["bitrate"] == 1_000_000


def test_a_scenario_sets_its_aircrafts_periods(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    scenario = tmp_path / "fast.toml"
    scenario.write_text('aircraft = "missile"\n[lqg]\nperiod = 0.01\n')
    rc, doc, _ = as_json(capsys, "--scenario", str(scenario))
    periods = {f["name"]: f["period_s"] for f in doc["frames"]}
    assert periods["MSL_RATE_GYRO"] == periods["MSL_ELEV_CMD"] == periods["SIM_TICK"] == 0.01
    assert periods["CDRW_AOA"] == 0.02 and periods["FCC_STATUS"] == 0.1
    _, plain, _ = as_json(capsys)
    assert doc["utilisation"] > plain["utilisation"]
    (tmp_path / "bad.toml").write_text('aircraft = "missile"\n[lqg]\nperiod = 9\n')
    rc, out, err = run(capsys, "--scenario", str(tmp_path / "bad.toml"))
    assert (rc, out) == (EXIT_USAGE, "") and "period" in one_line(err)


@pytest.mark.parametrize(("argv", "words"), [([], "required: COMMAND"), (["nope"], "invalid choice: 'nope'")])
def test_hil_bus_needs_a_command(capsys: pytest.CaptureFixture[str], argv: list[str], words: str) -> None:
    rc = main(["bus", *argv])
    out, err = capsys.readouterr()
    assert (rc, out) == (EXIT_USAGE, "") and words in one_line(err)


def test_a_cdrw_scenario_sets_its_frames_at_its_step(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    scenario = tmp_path / "cdrw.toml"
    scenario.write_text('aircraft = "cdrw"\n[plant]\ndt = 0.01\n')
    rc, doc, _ = as_json(capsys, "--scenario", str(scenario))
    periods = {f["name"]: f["period_s"] for f in doc["frames"]}
    assert periods["CDRW_AOA"] == periods["SID_KF_STATE"] == periods["FCC_ACK"] == 0.01
    assert periods["MSL_RATE_GYRO"] == 0.05 and periods["TSYNC_SYNC"] == 0.1
