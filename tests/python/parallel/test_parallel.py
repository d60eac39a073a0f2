"""Campaigns on several rigs at once (hil.parallel, Dask): from the host shell, each worker
its own UML guest (or vcanK) with its own fcc and recorder.

* 4 flights on 2 workers (2 sessions of 2) = the same on 1 worker (1 session of 4), byte for
  byte (summary.json, campaign.csv, faults.log, cdrw_run0.csv), and = the sequential campaign
  in one fcc (fcc's counters included);
* a worker killed in the middle of a flight: the flight is flown again elsewhere, same results,
  and run_info counts the retried flights and the lost worker;
* fcc or a worker's guest killed in the middle of a chunk (a test hook, at a given flight):
  the flights it finished are kept, only the one in the air is flown again, run_info says why
  (the process, its signal or status, its last lines) and which worker lost its rig;
* a flight that fails on its rig is retried once and then reported (exit 1, one line);
* a sweep's (T, N) points on 2 workers = the sequential sweep.

Bounded: each test boots at most two guests (about 3 s each) and flies a few 7 s flights.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from hil.cli import main

REPO = Path(__file__).resolve().parents[3]
RUNS, SEED = 4, 3
ARTEFACTS = ("summary.json", "campaign.csv", "faults.log", "cdrw_run0.csv")

UML = Path(os.environ.get("WITH_VCAN_UML_DIR") or REPO / ".uml")
needs_rig = pytest.mark.skipif(not (UML / "linux.uml").exists() and not Path("/sys/class/net/vcan0").exists(),
                                reason="needs User-Mode Linux (scripts/setup) or a kernel with vcan")


@pytest.fixture(scope="module", autouse=True)
def rig_dir(tmp_path_factory) -> Iterator[Path]:
    """Every rig of this module keeps its files (hil-rig-PID: requests, answers, the flights a
    failure leaves behind) under pytest's tmp dir, not in /tmp: $HIL_RIG_DIR, which
    hil.parallel.guest.rig_root reads and the Dask workers and guests inherit."""
    rigs = tmp_path_factory.mktemp("rigs")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("HIL_RIG_DIR", str(rigs))
        yield rigs


@pytest.fixture(scope="module", autouse=True)
def sessions_of_several_flights() -> Iterator[None]:
    """One rig session per worker (TASKS_PER_WORKER = 1): the module's 4-flight campaigns fly
    one session of 4 flights on 1 worker and two of 2 on 2 workers (fcc reset between them),
    so that the results are compared across chunkings too; the chunks are made by the
    coordinator, this process."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr("hil.parallel.runs.TASKS_PER_WORKER", 1)
        mp.setattr("hil.parallel.runs.LOCAL_TASKS_PER_RIG", 1)
        yield


def test_session_chunks_cover_the_campaign_in_order_and_balance():
    from hil.parallel import runs
    from hil.parallel.runs import SESSION_FLIGHTS_MAX, session_chunks
    for flights in (1, 2, 3, 4, 5, 12, 99, 100, 1000, 1001, 10_000):
        for workers in (1, 2, 3, 16, 32, 64):
            chunks = session_chunks(flights, workers)
            sizes = [len(c) for c in chunks]
            assert [i for c in chunks for i in c] == list(range(flights))
            assert max(sizes) <= SESSION_FLIGHTS_MAX and max(sizes) - min(sizes) <= 1
            want = max(runs.TASKS_PER_WORKER * workers, -(-flights // SESSION_FLIGHTS_MAX))
            assert len(chunks) == min(flights, want)
    assert [len(c) for c in session_chunks(4, 2)] == [2, 2]     # TASKS_PER_WORKER is 1 in this module
    with pytest.raises(ValueError):
        session_chunks(0, 2)


def test_chunks_by_default_keep_rigs_busy(monkeypatch):
    """The brief's case: 1000 flights on 16 machines of 2 rigs made 40 chunks (38 % of the rigs
    idle in the second round); now every rig flies 4 chunks of 7 or 8 flights."""
    from hil.parallel.runs import session_chunks
    monkeypatch.setattr("hil.parallel.runs.TASKS_PER_WORKER", 4)   # the default, not this module's
    chunks = session_chunks(1000, 32)
    assert len(chunks) == 128 and {len(c) for c in chunks} == {7, 8}
    assert len(session_chunks(1000, 2)) == 10                 # at most 100 flights a session
    assert len(session_chunks(3, 2)) == 3
    # this machine's rigs (--workers): 2 chunks a rig, one flying while the other is evaluated
    assert [len(c) for c in session_chunks(100, 2, 2)] == [25] * 4


def test_one_session_counters_do_not_depend_on_the_chunking():
    """fcc's counters of sessions of 1, 2 and 4 flights merge to the same figures, those of one
    session flying all 4 (the session's end counted once)."""
    from hil.parallel.flights import SESSION_END, add_counters, flights_counters, one_session_counters

    def session(k: int) -> dict:
        return add_counters({"e2e": {"ok": 1411 * k, "error": 0}, "steps": {"cdrw": 351 * k}}, SESSION_END)
    for parts in ([4], [2, 2], [1, 1, 1, 1], [1, 3]):
        assert one_session_counters([flights_counters(session(k)) for k in parts]) == session(4)
    assert flights_counters(session(1)) == {"e2e": {"ok": 1411, "error": 0}, "steps": {"cdrw": 351}}


def test_the_rest_of_a_failed_chunk_is_its_unfinished_flights():
    from hil.parallel.engine import Flight
    fl = Flight(3, print, ("scenario", [(i, 0.5 * i) for i in range(10, 15)]), count=5, first=10)
    rest = fl.rest(2)
    assert rest.args == ("scenario", [(12, 6.0), (13, 6.5), (14, 7.0)]) and rest.count == 3
    assert (rest.first, rest.part, rest.index) == (12, 1, 3)
    again = rest.rest(0)
    assert again.args == rest.args and again.count == 3 and again.part == 2


def test_a_failure_says_which_flights_and_why():
    from hil.parallel.engine import Flight, failure_record
    from hil.parallel.guest import RigDown
    fl = Flight(0, print, ("s", list(range(20, 30))), count=10, first=20)
    e = RigDown("the rig stopped during a flight (x)", {"signal": "SIGKILL", "last_lines": ["bye"]})
    f = failure_record(fl, e, "tcp://w:1", flown=4, kept=3)
    assert f["flights"] == [20, 29] and f["in_flight"] == 24 and f["reflown"] == 2   # flight 23 cut off too
    assert f["process"] == "rig" and f["signal"] == "SIGKILL" and f["last_lines"] == ["bye"]
    assert f["rig_lost"] is True and f["error"] == "the rig stopped during a flight (x)"
    done = failure_record(fl, ValueError("after the flights\nmore"), "tcp://w:1", flown=10, kept=0)
    assert done["in_flight"] is None and done["reflown"] == 10 and done["rig_lost"] is False
    assert done["error"] == "ValueError: after the flights" and done["process"] is None


def test_records_cut_off_where_the_rig_died_are_not_read(tmp_path):
    """records.pkl as a rig leaves it when it dies in the middle of a write: the records before
    are read, the cut one and those after are not; a record of another flight stops the read."""
    import pickle

    from hil.parallel.flights import RECORDS, _finished_records
    blobs = [pickle.dumps((i, {"flight": i, "data": list(range(1000))})) for i in (5, 6, 7)]
    (tmp_path / RECORDS).write_bytes(blobs[0] + blobs[1] + blobs[2][: len(blobs[2]) // 2])
    got = _finished_records(tmp_path, [(5, 0.5), (6, 0.6), (7, 0.7), (8, 0.8)])
    assert [(i, t, r["flight"]) for i, t, r in got] == [(5, 0.5, 5), (6, 0.6, 6)]
    assert _finished_records(tmp_path, [(6, 0.6)]) == []
    assert _finished_records(tmp_path / "none", [(5, 0.5)]) == []


def test_a_cut_off_log_keeps_the_flights_a_later_start_follows():
    from hil.parallel.flights import _whole_flights
    assert list(_whole_flights(iter("abc"), whole=True)) == ["a", "b", "c"]
    assert list(_whole_flights(iter("abc"), whole=False)) == ["a", "b"]
    assert list(_whole_flights(iter(""), whole=False)) == []


def test_last_lines_and_exit_cause(tmp_path):
    from hil.parallel.files import TAIL_BYTES, exit_cause, last_lines
    log = tmp_path / "fcc.log"
    log.write_text("x" * (3 * TAIL_BYTES) + "\n" + "".join(f"line {k}\n\n" for k in range(30)))
    assert last_lines(log) == [f"line {k}" for k in range(20, 30)]
    assert last_lines(log, 2) == ["line 28", "line 29"] and last_lines(tmp_path / "none") == []
    assert exit_cause(-9) == {"status": None, "signal": "SIGKILL"}
    assert exit_cause(137) == {"status": 137, "signal": None} and exit_cause(None)["status"] is None


def campaign(out: Path, *extra: str, runs: int = RUNS) -> tuple[int, str]:
    argv = ["campaign", "cdrw", "--runs", str(runs), "--seed", str(SEED), "--out", str(out),
            "--quiet", "--no-plots", *extra]
    return main(argv), ""


@pytest.fixture(scope="module")
def one_worker(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("w1")
    rc, _ = campaign(out, "--workers", "1")
    assert rc == 0
    return out


@needs_rig
def test_two_workers_equal_one_worker(one_worker, tmp_path, capsys):
    rc, _ = campaign(tmp_path, "--workers", "2")
    assert rc == 0, capsys.readouterr().err
    for name in ARTEFACTS:
        assert (tmp_path / name).read_bytes() == (one_worker / name).read_bytes(), name
    info = json.loads((tmp_path / "run_info.json").read_text())["parallel"]
    assert info["engine"] == "local rigs" and info["failed"] == 0
    # each chunk on the next idle rig (one booted faster may fly both)
    assert sum(info["flights_by_worker"].values()) == RUNS and set(info["flights_by_worker"]) <= {"rig-0", "rig-1"}
    assert info["tasks"] == 2 and info["flights_per_task"] == 2 and info["session_s_per_task"] > 0
    assert info["retried"] == 0 and info["workers_lost"] == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert [r["run"] for r in s["cdrw"]["runs"]] == list(range(RUNS)) and "failed_runs" not in s
    assert s["firmware"]["steps"]["cdrw"] == RUNS * 351


@needs_rig
def test_workers_equal_the_sequential_campaign(one_worker, tmp_path):
    """The sequential form inside one guest, one fcc reset between flights: the same Table 5,
    campaign.csv and faults, and fcc's counters (each session's end counted once)."""
    r = subprocess.run([str(REPO / "scripts" / "with-vcan"), sys.executable, "-m", "hil.cli", "campaign",
                        "cdrw", "--runs", str(RUNS), "--seed", str(SEED), "--out", str(tmp_path),
                        "--quiet", "--no-plots"], cwd=REPO, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    for name in ("campaign.csv", "faults.log", "cdrw_run0.csv"):
        assert (tmp_path / name).read_bytes() == (one_worker / name).read_bytes(), name
    seq = json.loads((tmp_path / "summary.json").read_text())
    par = json.loads((one_worker / "summary.json").read_text())
    assert seq == par


@needs_rig
def test_killed_worker_flight_flown_again(one_worker, tmp_path, monkeypatch):
    """A running cluster (the --scheduler path): one worker process is killed while its rig
    flies; Dask gives the flight to another worker and the results are unchanged."""
    from distributed import Client, LocalCluster

    rigs = tmp_path / "rigs"
    monkeypatch.setenv("HIL_RIG_DIR", str(rigs))   # the workers inherit it
    out = tmp_path / "out"
    killed: list[int] = []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                      memory_limit=0) as cluster, Client(cluster) as client:
        pids = set(client.run(os.getpid).values())

        def kill_first_flying() -> None:
            deadline = time.monotonic() + 300
            while time.monotonic() < deadline and not killed:
                for pid in pids:
                    if any((rigs / f"hil-rig-{pid}" / "flights").glob("task-*")):
                        os.kill(pid, signal.SIGKILL)
                        killed.append(pid)
                        return
                time.sleep(0.02)

        t = threading.Thread(target=kill_first_flying, daemon=True)
        t.start()
        rc, _ = campaign(out, "--scheduler", cluster.scheduler_address)
        t.join(5)
    assert killed, "no worker was seen flying"
    assert rc == 0
    for name in ARTEFACTS:
        assert (out / name).read_bytes() == (one_worker / name).read_bytes(), name
    info = json.loads((out / "run_info.json").read_text())["parallel"]
    # the killed worker's chunk (2 flights, TASKS_PER_WORKER = 1) was flown again by Dask
    assert info["retried"] == 2 and info["workers_lost"] == 1 and info["failed"] == 0


@needs_rig
def test_a_scheduler_whose_workers_boot_their_rigs_as_they_start(one_worker, tmp_path):
    """The --scheduler path as docs/campaigns.md starts its workers: two threads each, the rig
    booted by the preload as the worker starts (before any task); the same results as the
    local rigs'."""
    from distributed import Client, LocalCluster

    rigs = tmp_path / "rigs"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("HIL_RIG_DIR", str(rigs))   # the workers inherit it
        with LocalCluster(n_workers=1, threads_per_worker=2, processes=True, dashboard_address=":0",
                          memory_limit=0, preload=["hil.parallel.engine"]) as cluster, Client(cluster) as client:
            [pid] = client.run(os.getpid).values()
            deadline = time.monotonic() + 300
            while not (rigs / f"hil-rig-{pid}" / "boot1" / "ready").exists():   # no task yet
                assert time.monotonic() < deadline, "the preloaded worker booted no rig"
                time.sleep(0.05)
            rc, _ = campaign(tmp_path / "out", "--scheduler", cluster.scheduler_address)
    assert rc == 0
    for name in ARTEFACTS:
        assert (tmp_path / "out" / name).read_bytes() == (one_worker / name).read_bytes(), name
    info = json.loads((tmp_path / "out" / "run_info.json").read_text())["parallel"]
    assert info["engine"] == "dask.distributed" and info["retried"] == 0 and info["failed"] == 0


@needs_rig
def test_a_worker_that_dies_twice_loses_no_flight_silently(tmp_path, capsys):
    """A running cluster of one worker (the --scheduler path) whose worker process is killed
    whenever it flies: Dask gives the chunk to the worker restarted once, then gives up
    (allowed-failures = 1); the campaign says so in one line, exit 1 (hil.rig.errors.RigError:
    no flight gave a result), and writes no table."""
    import dask
    from distributed import Client, LocalCluster

    rigs = tmp_path / "rigs"
    out = tmp_path / "out"
    killed: list[int] = []

    def kill_every_flying_worker() -> None:
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline and len(killed) < 2:
            for d in rigs.glob("hil-rig-*/flights/task-*"):
                pid = int(d.parents[1].name.removeprefix("hil-rig-"))
                if pid not in killed:
                    os.kill(pid, signal.SIGKILL)
                    killed.append(pid)
            time.sleep(0.02)

    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("HIL_RIG_DIR", str(rigs))   # the workers inherit it
        with dask.config.set({"distributed.scheduler.allowed-failures": 1}), \
                LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0",
                             memory_limit=0) as cluster, Client(cluster):
            t = threading.Thread(target=kill_every_flying_worker, daemon=True)
            t.start()
            rc, _ = campaign(out, "--scheduler", cluster.scheduler_address, runs=2)
            t.join(5)
    err = capsys.readouterr().err.strip().splitlines()
    assert len(killed) == 2
    assert rc == 1 and len(err) == 1, err
    assert "all 2 flights failed twice" in err[0] and "its worker died twice" in err[0]
    assert not (out / "summary.json").exists()


def _servers_in(rigs: Path) -> list[int]:
    """The rig servers (hil.parallel.server) still running whose directory is under `rigs`."""
    pids = []
    for proc in Path("/proc").glob("[0-9]*"):
        try:
            cmd = (proc / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if b"hil.parallel.server" in cmd and any(str(rigs).encode() in c for c in cmd):
            pids.append(int(proc.name))
    return pids


@needs_rig
def test_an_interrupted_campaign_stops_its_rigs(tmp_path):
    """Ctrl-C (SIGINT) while two local rigs fly: one line, exit 130, and no rig left running
    (the rigs are killed, their tasks salvage nothing: nobody waits for them)."""
    rigs = tmp_path / "rigs"
    env = {**os.environ, "HIL_RIG_DIR": str(rigs)}
    proc = subprocess.Popen([sys.executable, "-m", "hil.cli", "campaign", "cdrw", "--runs", "40", "--seed",
                             str(SEED), "--workers", "2", "--no-plots", "--quiet", "--out", str(tmp_path / "out")],
                            cwd=REPO, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 300
    while not any(rigs.glob("hil-rig-*/flights/task-*")):   # a rig flies
        assert proc.poll() is None and time.monotonic() < deadline, "no rig flew"
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130 and err.strip().splitlines() == ["hil: interrupted"], err
    assert _servers_in(rigs) == []
    assert not (tmp_path / "out").exists()


def _campaign_with_rig_failure(out: Path, rig_dir: Path, what: str, monkeypatch) -> dict:
    """The module's 4-flight campaign on 1 worker (one chunk of 4) whose fcc or rig is killed
    before the last step of flight 1 (hil.parallel.flights.FAILURE_HOOK: deterministic, once);
    its run_info's `parallel`."""
    monkeypatch.setenv("HIL_TEST_RIG_FAILURE", f"{what} 1")   # the workers and guests inherit it
    for old in rig_dir.glob("hil-test-failure-*"):
        old.unlink()
    rc, _ = campaign(out, "--workers", "1")
    assert rc == 0
    assert (rig_dir / "hil-test-failure-1").exists()            # the hook did fire
    return json.loads((out / "run_info.json").read_text())["parallel"]


def _same_table_as_undisturbed(out: Path, one_worker: Path) -> None:
    """Table 5 and every per-flight file byte for byte as the undisturbed campaign; fcc's
    counters of flight 0 (flown by the session that failed) are lost, and said so."""
    for name in ("campaign.csv", "faults.log", "cdrw_run0.csv"):
        assert (out / name).read_bytes() == (one_worker / name).read_bytes(), name
    got, want = (json.loads((d / "summary.json").read_text()) for d in (out, one_worker))
    assert got["cdrw"] == want["cdrw"] and "failed_runs" not in got
    assert got["firmware_uncounted"] == [0] and "firmware_uncounted" not in want
    assert got["firmware"]["steps"]["cdrw"] == (RUNS - 1) * 351


@needs_rig
def test_killed_fcc_costs_one_flight_and_says_why(one_worker, tmp_path, rig_dir, monkeypatch):
    """fcc killed (SIGKILL) in flight 1 of the chunk 0..3: flight 0 is kept, flights 1..3 are
    flown by a new session: one flight flown again (was: the whole chunk)."""
    info = _campaign_with_rig_failure(tmp_path, rig_dir, "fcc", monkeypatch)
    assert info["retried"] == 1 and info["failed"] == 0
    assert sum(info["flights_by_worker"].values()) == RUNS
    [f] = info["failures"]
    assert f["flights"] == [0, 3] and f["in_flight"] == 1 and f["finished"] == 1 and f["kept"] == 1
    assert f["reflown"] == 1 and f["process"] == "fcc" and f["signal"] == "SIGKILL" and f["status"] is None
    assert f["error"].startswith("FccDied: ") and "SIGKILL" in f["error"]
    assert f["last_lines"] and any("fcc" in ln for ln in f["last_lines"])   # fcc.log's last words
    assert f["rig_lost"] is False and info["lost_workers"] == [] and info["workers_lost"] == 0
    _same_table_as_undisturbed(tmp_path, one_worker)


@needs_rig
def test_killed_guest_costs_one_flight_and_the_worker_is_named(one_worker, tmp_path, rig_dir, monkeypatch):
    """The rig itself killed in flight 1 (its server: the guest ends): flight 0 is read from the
    recorder's file the guest left, flights 1..3 flown by the rig booted again; the worker that
    lost its rig is in lost_workers (was: [], only workers that left Dask counted)."""
    info = _campaign_with_rig_failure(tmp_path, rig_dir, "rig", monkeypatch)
    assert info["retried"] == 1 and info["failed"] == 0, [{k: f[k] for k in ("error", "kept", "reflown")}
                                                          for f in info["failures"]]
    [f] = info["failures"]
    assert f["in_flight"] == 1 and f["kept"] == 1 and f["reflown"] == 1
    assert f["process"] == "rig" and f["rig_lost"] is True
    assert f["status"] is not None or f["signal"] is not None
    assert "the rig stopped during a flight" in f["error"]
    assert info["lost_workers"] == [f["worker"]] and info["workers_lost"] == 1
    _same_table_as_undisturbed(tmp_path, one_worker)


@needs_rig
def test_failing_flight_is_retried_then_reported(tmp_path, capsys, rig_dir):
    """fcc cannot start (its options pass `fcc --check-args`, but name an interface the worker has
    not): each flight is tried twice (on the one worker there is), then the campaign stops with
    one line and exit 1."""
    rc = main(["campaign", "cdrw", "--runs", "1", "--seed", "1", "--out", str(tmp_path), "--quiet",
               "--no-plots", "--workers", "1", "--fcc-args=--iface no-such0"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 1 and len(err) == 1
    assert "all 1 flights failed twice" in err[0] and "fcc" in err[0]
    assert "FccDied" in err[0] or "RigError" in err[0]
    # the failed flights' files stay for a look, in the module's rig dir (not in /tmp)
    assert any(rig_dir.glob("hil-rig-*/flights/task-*/fcc.log"))


@needs_rig
def test_sweep_on_workers_equals_the_sequential_sweep(tmp_path):
    """Two (T, N) points on 2 workers: every missile time series, faults.log, the RMS table
    and fcc's counters as the sequential sweep in one fcc."""
    argv = ["sweep", "missile", "--periods", "0.2,0.1", "--bits", "8", "--quiet", "--no-plots"]
    r = subprocess.run([str(REPO / "scripts" / "with-vcan"), sys.executable, "-m", "hil.cli", *argv,
                        "--out", str(tmp_path / "seq")], cwd=REPO, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert main([*argv, "--out", str(tmp_path / "par"), "--workers", "2"]) == 0
    seq_files = sorted(p.name for p in (tmp_path / "seq").iterdir() if p.suffix == ".csv")
    assert len(seq_files) == 8 and seq_files == sorted(p.name for p in (tmp_path / "par").glob("*.csv"))
    for name in [*seq_files, "faults.log"]:
        assert (tmp_path / "seq" / name).read_bytes() == (tmp_path / "par" / name).read_bytes(), name
    seq = json.loads((tmp_path / "seq" / "summary.json").read_text())
    par = json.loads((tmp_path / "par" / "summary.json").read_text())
    assert seq == par


@pytest.mark.parametrize("extra, words", [
    (["--workers", "0"], "--workers must be 1..64, got 0"),
    (["--workers", "2", "--mode", "realtime"], "lockstep flights only"),
    (["--workers", "2", "--target", "external"], "not --target/--interface"),
    (["--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "not allowed with argument"),
    (["--workers", "2", "--log-format", "blf"], "--log-format blf: --workers/--scheduler keep no bus log"),
    (["--scheduler", "tcp://127.0.0.1:1", "--log-format", "asc"], "--log-format asc: --workers"),
])
def test_bad_parallel_options_are_one_line(tmp_path, capsys, extra, words):
    rc = main(["campaign", "cdrw", "--runs", "2", "--out", str(tmp_path / "c"), "--quiet", *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and words in err[0]
    assert not (tmp_path / "c").exists()


def test_workers_inside_the_guest_say_so_at_once(tmp_path, capsys, monkeypatch):
    """Inside scripts/with-vcan's guest (which sets WITH_VCAN_UML) --workers cannot boot rigs:
    one line saying what to do, exit 2, before any cluster is started."""
    monkeypatch.setenv("WITH_VCAN_UML", "7.2.7 seccomp")
    rc = main(["campaign", "cdrw", "--runs", "2", "--out", str(tmp_path / "c"), "--quiet", "--workers", "2"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "without scripts/with-vcan" in err[0]
    assert not (tmp_path / "c").exists()


def test_the_bench_models_n_machines_from_the_real_chunking(monkeypatch):
    """scripts/bench parallel's model: greedy hand-out of the chunks, a + b x flights each."""
    from hil.bench.parallel import balance, makespan
    from hil.parallel.runs import session_chunks
    monkeypatch.setattr("hil.parallel.runs.TASKS_PER_WORKER", 4)
    assert makespan([3.0, 1.0, 1.0, 1.0], 2) == 3.0 and makespan([1.0] * 5, 2) == 3.0
    wall, excess = balance(10_000, 32, 0.5, 0.3, session_chunks(10_000, 32))
    assert excess < 0.20 and wall >= 10_000 * 0.3 / 32
    old = [range(i, min(i + 25, 1000)) for i in range(0, 1000, 25)]
    assert balance(1000, 32, 0.0, 0.3, old)[1] > 0.5                   # 40 chunks on 32 rigs
    assert balance(1000, 32, 0.0, 0.3, session_chunks(1000, 32))[1] < 0.1


def _worker_profiles() -> bool:
    import dask

    return bool(dask.config.get("distributed.worker.profile.enabled"))


def test_local_workers_do_not_sample_their_tasks_stacks():
    """A local cluster's workers run without Dask's statistical profiler (its samples, taken
    every 10 ms from the worker's event loop, are for a dashboard nobody watches here)."""
    from hil.parallel.engine import Cluster

    with Cluster(workers=1, rigs=False) as cluster:
        assert list(cluster.client.run(_worker_profiles).values()) == [False]
