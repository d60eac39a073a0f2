"""`hil live --plot`: the chart page served on 127.0.0.1, loaded in headless Chromium (the
browser the verify report's test opens, with its flags), drew the points of the chosen
signals: of a recorded bus log and of a growing one (--follow: host), and of a run flying on
vcan0."""
from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from hil.bus import SIM_NODES, FrameCodec, load
from hil.bus.candump import LogFrame
from hil.bus.logio import write_candump
from hil.cli.usage import EXIT_USAGE
from hil.rig.liveplot import Chart
from hil.sim.frame_faults import KIND_CODES
from rig_helpers import cli

SPEC = load()


def _browser_dom(url: str) -> str:
    """The page's DOM after its script ran (3 s of the page's virtual time)."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    assert browser, "chromium is not installed (scripts/setup installs it)"
    p = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu", "--virtual-time-budget=3000",
                        "--dump-dom", url], check=True, capture_output=True, text=True, timeout=120)
    return p.stdout


def _points_drawn(dom: str) -> int:
    m = re.search(r'<canvas id="chart"[^>]*data-points="(\d+)"', dom)
    assert m, dom[:2000]
    return int(m.group(1))


def _serve(*args: str) -> tuple[subprocess.Popen, str]:
    """`hil live --plot ...` in its own process, and its URL (its first line: it serves)."""
    proc = subprocess.Popen([sys.executable, "-m", "hil.cli", "live", "--plot", "--port", "0", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    line = proc.stdout.readline()
    m = re.match(r"live chart: (http://127\.0\.0\.1:\d+/) ", line)
    assert m, (line, proc.stderr.read() if proc.poll() is not None and proc.stderr else "")
    return proc, m.group(1)


def _recorded(path: Path, n: int) -> Path:
    """A candump log of n missile steps at 10 Hz: the gyro and fcc's estimate, DBC-encoded (and,
    from 20 steps on, a stuck gyro's SIM_EVENT start at step 10 and end at step 20)."""
    sim, fcc = FrameCodec(SPEC, SIM_NODES), FrameCodec(SPEC, "FCC")
    frames = []
    for k in range(n):
        t = 1000.0 + 0.1 * k
        fid, data = sim.encode("MSL_RATE_GYRO", {"q_g": 0.01 * k, "step": k})
        frames.append(LogFrame(t, "vcan0", fid, data))
        fid, data = fcc.encode("MSL_STATE_EST", {"q_hat": 0.01 * k, "alpha_t_hat": 0.0, "w_g_hat": 0.0,
                                                 "step": k & 0xFF})
        frames.append(LogFrame(t + 0.004, "vcan0", fid, data))
        if k in (10, 20):   # a stuck gyro from step 10 to step 20, as the simulator says it
            fid, data = sim.encode("SIM_EVENT", {"active": int(k == 10), "oracle_fault": 0, "fault_id": 0,
                                                 "kind": KIND_CODES["stuck"], "target_id": 0x101, "step": k})
            frames.append(LogFrame(t - 0.001, "vcan0", fid, data))
    write_candump(path, frames)
    return path


def test_chart_of_a_recorded_log_in_headless_chromium(tmp_path):
    log = _recorded(tmp_path / "bus.log", 50)
    proc, url = _serve("--log", str(log), "--seconds", "300", "--signals", "q_g,MSL_STATE_EST.q_hat")
    try:
        data = json.loads(urllib.request.urlopen(url + "data?since=0", timeout=10).read())
        assert data["signals"] == ["MSL_RATE_GYRO.q_g", "MSL_STATE_EST.q_hat"] and data["seq"] == 102
        assert data["points"]["MSL_RATE_GYRO.q_g"][49] == [pytest.approx(4.9), pytest.approx(0.49, abs=1e-3)]
        assert data["faults"] == [[pytest.approx(0.999), pytest.approx(1.999), "stuck on 0x101"]]
        page = urllib.request.urlopen(url, timeout=10).read().decode()
        assert "<script" in page and "http" not in page.split("<script", 1)[1]   # nothing fetched elsewhere
        dom = _browser_dom(url)
        assert _points_drawn(dom) == 100 and re.search(r'<canvas id="chart"[^>]*data-faults="1"', dom)
        req = urllib.request.Request(url, headers={"Host": "rebound.example:80"})
        with pytest.raises(urllib.error.HTTPError) as e:
            urllib.request.urlopen(req, timeout=10)
        assert e.value.code == 403
    finally:
        proc.kill()
        proc.wait()


def test_signals_are_checked(tmp_path, capsys):
    rc, out, err = cli(capsys, "live", "--plot", "--signals", "MSL_RATE_GYRO.nope", "--log", str(tmp_path / "x.log"))
    assert rc == EXIT_USAGE and out == ""
    assert err.strip().splitlines() == ["hil: --signals: MSL_RATE_GYRO has no signal 'nope' (it has step, q_g)"]
    with pytest.raises(ValueError, match="name one as MESSAGE.step"):
        Chart(SPEC, ["step"])


def _points_reach(url: str, n: int) -> int:
    """The chart's point count once it has n (or what it has after 30 s)."""
    seen, deadline = 0, time.monotonic() + 30
    while seen < n and time.monotonic() < deadline:
        data = json.loads(urllib.request.urlopen(url + "data?since=0", timeout=10).read())
        seen = sum(len(pts) for pts in data["points"].values())
        time.sleep(0.05)
    return seen


def test_follow_charts_a_growing_log_as_it_grows(tmp_path):
    """--follow OUT: the recorder's log in the staging directory of the run flying into OUT,
    read as it grows (here written in two blocks, as a block-buffered recorder does)."""
    frames = _recorded(tmp_path / "all.log", 40).read_text().splitlines(keepends=True)
    live = tmp_path / ".run.partial-host-1-0123456789abcdef" / ".canrec-1" / "bus.log"
    live.parent.mkdir(parents=True)
    proc, url = _serve("--follow", str(tmp_path / "run"), "--seconds", "300", "--signals", "q_g")
    try:
        with open(live, "w") as fh:
            fh.write("".join(frames[:20]) + frames[20][:10])   # 10 steps and half a line
            fh.flush()
            assert _points_reach(url, 10) == 10
            fh.write(frames[20][10:] + "".join(frames[21:]))
            fh.flush()
            assert _points_reach(url, 40) == 40
        assert _points_drawn(_browser_dom(url)) == 40
    finally:
        proc.kill()
        proc.wait()


@pytest.mark.vcan
def test_chart_of_a_flying_run(tmp_path, capsys):
    # the guest's loopback is down (scripts/with-vcan brings up vcan0 only); the chart is
    # served on it
    if "UP" not in subprocess.run(["ip", "-br", "link", "show", "lo"], capture_output=True, text=True).stdout:
        subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
    proc, url = _serve("--iface", "vcan0", "--seconds", "300")
    try:
        # realtime, as the chart is meant for: a lockstep flight's bursts outran the viewer's
        # socket buffer (125 of its 200 points, measured); 7: a time-sync loss of the loaded guest
        rc, _, err = cli(capsys, "run", "missile", "--mode", "realtime", "--out", str(tmp_path / "run"),
                         "--quiet", "--no-plots")
        assert rc == 0 or (rc == 7 and "time sync lost" in err), err
        # the run is over: every frame of it was on the bus before its end; the chart has them
        # once `hil live` has read its socket's queue
        assert _points_reach(url, 200) == 200   # the 100 steps' gyro readings and estimates
        assert _points_drawn(_browser_dom(url)) > 0
    finally:
        proc.kill()
        proc.wait()
