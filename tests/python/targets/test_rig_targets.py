"""`hil ... --target host|qemu-m4f|external` and `--interface/--channel/--bitrate`.

Without a bus: the command-line checks, and the external target on python-can's virtual bus
(nothing answers: one line, exit 1, the rig's own recorder wrote bus.log).  On vcan0: the
default flight against a hand-started fcc (--target external) gives exactly the Table 4 of
--target host, and python-can's send/recv path with the link as recorder flies the same
flight as the raw-socket path with candump.
"""
from __future__ import annotations

import json
import struct
import subprocess
import time
from dataclasses import replace
from pathlib import Path

import pytest

from hil.bus.secoc import TEST_KEY_FILE
from hil.cli.parser import TARGET_CHOICES
from hil.scenario.file import load_default_scenario
from hil.rig.link import CanLink
from hil.targets.qemu_m4f import PilError, boot_options, boot_record
from hil.rig.config import RigConfig
from hil.rig.errors import RigError
from hil.rig.flight import fcc_args, on_target
from hil.scenario.plant_options import RT_ACTUATION_DELAY
from hil.targets.registry import TARGETS
from rig_helpers import CDRW_1S, cli, fly, scenario
from test_cli import one_line


def test_cli_offers_every_target():
    assert tuple(TARGETS) == TARGET_CHOICES


@pytest.mark.parametrize("argv, words", [
    (["--target", "board"], "invalid choice: 'board'"),
    (["--target", "external", "--fcc-args", "--apps cdrw"], "--fcc-args: the external target"),
    (["--target", "external", "--fcc", "/bin/sh"], "--fcc: the external target runs no firmware"),
    (["--fcc", "/no/such/fcc"], "--fcc /no/such/fcc: not an executable file"),
    (["--bitrate", "fast"], "--bitrate"),
    (["--bitrate", "5000000"], "--bitrate"),
    (["--target", "qemu-m4f", "--interface", "virtual"], "use --interface socketcan"),
])
def test_bad_target_options(capsys, tmp_path, argv, words):
    rc, _, err = cli(capsys, "run", "cdrw", *argv, "--out", str(tmp_path / "o"))
    assert rc == 2
    assert words in one_line(err)


def test_external_nothing_answers(capsys, tmp_path):
    """python-can's virtual bus, nobody on it: one line within about the timeout, exit 1; the
    link recorded what the rig sent (candump -L format, the end marker last)."""
    t0 = time.monotonic()
    rc, out, err = cli(capsys, "run", "cdrw", "--target", "external", "--interface", "virtual",
                       "--channel", f"nobody{time.monotonic_ns()}", "--timeout", "0.5",
                       "--quiet", "--no-plots", "--out", str(tmp_path / "o"))
    assert rc == 1 and out == ""
    line = one_line(err)
    assert line.startswith("hil: nothing answered on nobody") and "within 0.5 s" in line
    assert time.monotonic() - t0 < 5
    (kept,) = tmp_path.glob("o.failed-*")       # the failed run's directory
    log = (kept / "bus.log").read_text().splitlines()
    assert log and log[-1].endswith(" 7F0#FFFFFFFF00000000")
    assert "the rig started no firmware" in (kept / "fcc.log").read_text()


def test_boot_options_refuse_what_the_image_does_not_take():
    assert boot_options(["--mode", "lockstep", "--apps", "cdrw", "--mode", "realtime"]) == \
        {"--mode": "realtime", "--apps": "cdrw"}
    with pytest.raises(PilError, match="the M4F image takes no --window"):
        boot_options(["--window", "50"])
    with pytest.raises(PilError, match="--lqg-bits needs a value"):
        boot_options(["--lqg-bits"])


@pytest.mark.parametrize("mode", ["lockstep", "realtime"])
def test_boot_record_carries_the_rigs_lqg_delay(mode):
    """The image gets the delay the rig resolved for the run, as the host fcc does on its
    command line (lockstep 0, realtime the target's own: 15 ms), in bytes 44-51 of its record."""
    sc = load_default_scenario("missile")
    args = fcc_args([sc], RigConfig(Path("unused"), mode=mode, target="qemu-m4f"))
    delay = 0.015 if mode == "realtime" else 0.0
    assert args[args.index("--lqg-delay") + 1] == f"{delay:.6g}"
    rec = boot_record(args)
    assert rec.lqg_delay == delay and rec.mode == mode
    assert struct.unpack_from("<d", rec.encode(), 44)[0] == delay
    with pytest.raises(PilError, match="not auto"):
        boot_record(["--lqg-delay", "auto"])


# ---- on vcan0 -------------------------------------------------------------------------------
@pytest.mark.vcan
def test_external_hand_started_fcc_same_table4_as_host(capsys, tmp_path, bin_path):
    """The default lockstep flight against an fcc started by hand: the same Table 4 (exactly:
    the flight is deterministic) as the rig's own fcc; the device is left running."""
    rc, out_host, err = cli(capsys, "run", "cdrw", "--quiet", "--no-plots", "--out", str(tmp_path / "host"))
    assert rc == 0, err
    info = json.loads((tmp_path / "host" / "run_info.json").read_text())
    assert info["target"] == "host"
    fcc = subprocess.Popen([str(bin_path("fcc")), "--iface", "vcan0", "--mode", "lockstep",
                            "--apps", "cdrw", "--key-file", str(TEST_KEY_FILE)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        rc, out_ext, err = cli(capsys, "run", "cdrw", "--target", "external", "--quiet", "--no-plots",
                               "--key-file", str(TEST_KEY_FILE), "--out", str(tmp_path / "ext"))
        assert rc == 0, err
        assert fcc.poll() is None           # the rig did not stop a device it does not own
    finally:
        fcc.terminate()
        fcc.wait(10)
    host = json.loads((tmp_path / "host" / "summary.json").read_text())
    ext = json.loads((tmp_path / "ext" / "summary.json").read_text())
    assert ext["cdrw"]["table4"] == host["cdrw"]["table4"]
    assert ext["cdrw"]["table4_truth"] == host["cdrw"]["table4_truth"]
    assert ext["cdrw"]["flight"]["missing_steps"] == 0
    # the same tables; only the cross-check's bound is said not to apply: an external device's
    # arithmetic is not assumed to be sid_replay's (hil.results.trust)
    not_applied = " (not applied: target external: its arithmetic is not sid_replay's)"
    assert not_applied in out_ext
    assert out_ext.split("fcc counters")[0].replace(not_applied, "") == out_host.split("fcc counters")[0]
    info = json.loads((tmp_path / "ext" / "run_info.json").read_text())
    assert info["target"] == "external" and info["fcc_exit"] is None
    assert info["fcc_command"].startswith("fcc --iface vcan0 --mode lockstep --apps cdrw")


@pytest.mark.vcan
def test_external_wrong_mode_is_one_line(capsys, tmp_path, bin_path):
    fcc = subprocess.Popen([str(bin_path("fcc")), "--iface", "vcan0", "--mode", "realtime",
                            "--apps", "cdrw", "--key-file", str(TEST_KEY_FILE)],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        rc, _, err = cli(capsys, "run", "cdrw", "--target", "external", "--quiet", "--no-plots",
                         "--key-file", str(TEST_KEY_FILE), "--out", str(tmp_path / "o"))
    finally:
        fcc.terminate()
        fcc.wait(10)
    assert rc == 1
    assert one_line(err).startswith("hil: the device under test on vcan0 runs in realtime mode, "
                                    "the run is lockstep")


@pytest.mark.vcan
def test_python_can_path_flies_like_the_raw_socket(tmp_path, monkeypatch):
    """python-can's own send/recv with the link as the recorder (the path of a PCAN, Kvaser or
    SLCAN adapter), here on vcan0: the same results as the raw socket with candump."""
    sc = scenario(CDRW_1S)
    raw = fly(tmp_path / "raw", sc)
    monkeypatch.setattr(CanLink, "RAW_INTERFACES", frozenset())
    generic = fly(tmp_path / "generic", sc)
    assert generic.summary["cdrw"] == raw.summary["cdrw"]
    log = (tmp_path / "generic" / "bus.log").read_text().splitlines()
    assert sum(1 for ln in log if " 110#" in ln) == 51
    assert log[-1].endswith(" 7F0#FFFFFFFF00000000")


def test_a_realtime_run_acts_at_its_targets_actuation_instant():
    """"auto" is the target's own delay in realtime (the M4F image's serial line), a CAN node's
    5 ms on the host, 0 in lockstep; a delay the scenario gives is kept; a period the target's
    delay does not fit in is one RigError."""
    sc = load_default_scenario("missile")
    def delay(target: str, mode: str, scenario=sc) -> float:
        cfg = RigConfig(Path("unused"), mode=mode, target=target)
        return on_target(scenario, cfg).lqg.resolved_delay(mode == "realtime")
    assert delay("qemu-m4f", "realtime") == 0.015
    assert delay("host", "realtime") == RT_ACTUATION_DELAY
    assert delay("qemu-m4f", "lockstep") == 0.0
    given = replace(sc, lqg=replace(sc.lqg, delay=0.002))
    assert delay("qemu-m4f", "realtime", given) == 0.002
    fast = replace(sc, lqg=replace(sc.lqg, period=0.01))
    with pytest.raises(RigError, match="--target qemu-m4f acts 15 ms after its sampling instant"):
        delay("qemu-m4f", "realtime", fast)
