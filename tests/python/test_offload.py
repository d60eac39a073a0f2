"""hil.offload: the host's half of a flight flown in the UML guest.

On the host: a real server process answers calls with the caller's environment and working
directory, raises the callee's exceptions in the caller, refuses what is not hil's, and stops
with its parent; a driver pickled for the guest flies the same frames without numpy.
In the guest (vcan): `hil run cdrw` gives the same results with and without the server.
"""
from __future__ import annotations

import os
import pickle
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from hil import offload
from hil.bus import FrameCodec, load
from hil.faults import ScenarioError, load_default_scenario
from hil.rig.apps import AppDriver
from hil.rig.flight import RigConfig, drivers_for_guest

from rig_helpers import cli

READY_TIMEOUT_S = 60.0


def _serve(d: Path, parent: int) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "hil.offload", "serve", str(d), "--parent", str(parent)])


@pytest.fixture
def server(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    d = tmp_path / "offload"
    d.mkdir()
    proc = _serve(d, os.getpid())
    deadline = time.monotonic() + READY_TIMEOUT_S
    while not (d / offload.READY).exists():
        assert proc.poll() is None, "the server exited before it was ready"
        assert time.monotonic() < deadline, "the server did not get ready"
        time.sleep(0.01)
    monkeypatch.setenv(offload.ENV, str(d))
    yield d
    proc.terminate()
    proc.wait(10)


def test_a_call_runs_with_the_callers_environment(server: Path, tmp_path: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    assert offload.server_dir() == server
    monkeypatch.setenv("FCC_HIL_DBC", str(tmp_path / "mine.dbc"))
    assert offload.call("hil.bus.dbc:default_path") == tmp_path / "mine.dbc"
    sc = offload.call("hil.faults:load_default_scenario", "cdrw")
    assert sc == load_default_scenario("cdrw")
    assert not [p for p in server.iterdir() if p.name != offload.READY], "requests or answers left behind"


def test_the_callees_exception_is_raised_in_the_caller(server: Path) -> None:
    with pytest.raises(ScenarioError, match="no default scenario for aircraft 'plane'"):
        offload.call("hil.faults:load_default_scenario", "plane")


def test_only_hil_functions_are_called(server: Path) -> None:
    with pytest.raises(offload.OffloadError, match="not a hil function"):
        offload.call("os:getcwd")


def test_what_a_call_keeps_is_taken_once(server: Path) -> None:
    cfg = RigConfig(out_dir=Path("unused"))
    key, drivers = offload.call("hil.rig.flight:drivers_for_guest", [load_default_scenario("cdrw")], cfg)
    assert drivers[0].samples == [] and drivers[0].sim is None   # the samples stayed there
    offload.call("hil.offload:take", key)
    with pytest.raises(KeyError):
        offload.call("hil.offload:take", key)


def test_no_server_of_another_hil(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / offload.READY).write_text("/elsewhere/hil\n")
    monkeypatch.setenv(offload.ENV, str(tmp_path))
    assert offload.server_dir() is None
    with pytest.raises(offload.OffloadError, match="no hil.offload server"):
        offload.call("hil.faults:load_default_scenario", "cdrw")


def test_a_server_that_stopped_beating_is_not_used(server: Path) -> None:
    os.utime(server / offload.READY, (time.time() - 2 * offload.STALE_S,) * 2)
    assert offload.server_dir() is None
    time.sleep(1.5 * offload.BEAT_S)                # it lives: its next beat says so
    assert offload.server_dir() == server


def test_the_server_stops_with_its_parent(tmp_path: Path) -> None:
    parent = subprocess.Popen(["sleep", "0.5"])
    proc = _serve(tmp_path, parent.pid)
    parent.wait()
    assert proc.wait(READY_TIMEOUT_S) == 0
    assert not (tmp_path / offload.READY).exists()


def _flown_frames(d: AppDriver, codec: FrameCodec) -> list[tuple[int, bytes]]:
    """Every frame the simulator sends in a lockstep flight of d (ticks included)."""
    out = []
    while not d.done:
        frames = list(d.frames_for_step()) + d.injector.infrastructure(d.t_next, "SIM_TICK",
                                                                       {"app": d.app, "step": d.k})
        out += [(f.frame_id, f.data) for f in frames]
        d.k += 1
    return out


def test_a_driver_pickled_for_the_guest_flies_the_same_frames(tmp_path: Path) -> None:
    sc = load_default_scenario("cdrw")
    cfg = RigConfig(out_dir=tmp_path)
    _, (here,) = drivers_for_guest([sc], cfg)
    _, (there,) = drivers_for_guest([sc], cfg)
    there = pickle.loads(pickle.dumps(there))
    codec = FrameCodec(load())
    there.attach(codec)
    assert _flown_frames(there, codec) == _flown_frames(here, here.codec)


def test_the_guests_half_imports_no_numpy(tmp_path: Path) -> None:
    """What the guest does for a lockstep CDRW flight: the CLI, the scenario, the bus side,
    the driver from the host and its frames -- with numpy unimportable."""
    sc = load_default_scenario("cdrw")
    _, drivers = drivers_for_guest([sc], RigConfig(out_dir=tmp_path))
    (tmp_path / "drivers.pkl").write_bytes(pickle.dumps(drivers))
    code = f"""
import pickle, sys
class NoNumpy:
    def find_spec(self, name, path=None, target=None):
        if name == "numpy" or name.startswith("numpy."):
            raise ImportError("numpy is not for the guest")
sys.meta_path.insert(0, NoNumpy())
import hil.cli, hil.rig.flight, hil.rig.lockstep, hil.rig.session
from hil.bus import FrameCodec, load
sc = hil.cli._scenario("cdrw", None, [], None)
(d,) = pickle.loads(open({str(tmp_path / "drivers.pkl")!r}, "rb").read())
d.attach(FrameCodec(load()))
n = 0
while not d.done:
    n += len(d.frames_for_step()) + len(d.injector.infrastructure(d.t_next, "SIM_TICK", {{"app": 0, "step": d.k}}))
    d.k += 1
assert "numpy" not in sys.modules
print(n)
"""
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert int(r.stdout) >= 4 * drivers[0].n_steps


@pytest.mark.vcan
def test_hil_run_gives_the_same_results_with_and_without_the_host(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    assert offload.server_dir() is not None, "scripts/with-vcan started no hil.offload server"
    rc, out_there, _ = cli(capsys, "run", "cdrw", "--quiet", "--no-plots", "--out", str(tmp_path / "there"))
    assert rc == 0
    monkeypatch.delenv(offload.ENV)
    rc, out_here, _ = cli(capsys, "run", "cdrw", "--quiet", "--no-plots", "--out", str(tmp_path / "here"))
    assert rc == 0
    for name in ("summary.json", "cdrw.csv", "faults.log"):
        assert (tmp_path / "there" / name).read_bytes() == (tmp_path / "here" / name).read_bytes(), name
    assert out_there.replace("there", "here") == out_here
