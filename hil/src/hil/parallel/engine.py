"""Flights on a Dask cluster: a local one of N worker processes (one rig each), or a running
cluster's scheduler (``--scheduler tcp://HOST:8786``) whose workers are machines with the
project built.

Each task is one flight or a chunk of consecutive flights: the worker's rig
(hil.parallel.guest, booted on the worker's first flight and kept) flies it and the value
comes back to this process.  One progress bar counts flights.  A task whose rig failed (fcc
died or hung, the guest died or did not answer) gives back what it finished (its salvage:
the flights whose results are whole) with the failure's cause, and the rest of its flights
are submitted again, to another worker when there is one: a failure costs the flight that
was in the air, not the chunk.  A task that fails twice without finishing a flight is
reported (its flights), and the others are kept.  A task whose worker process was killed is
flown again whole by Dask itself (``distributed.scheduler.allowed-failures`` = 1 here).
"""
from __future__ import annotations

import dataclasses
import logging
import os
import socket
import threading
import time
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from hil.parallel.guest import GuestRig, RigDown, RigFailed
from hil.rig.config import RigConfig
from hil.util.progress import bar as progress_bar

FLIGHT_TIMEOUT_S = 120.0
#: Dask's rescheduling after a worker died: once (the flight is then reported)
ALLOWED_FAILURES = 1
#: failures in a row that finish no flight before a task's flights are reported
TRIES = 2
#: a local worker's statistical profiler samples the task's stack every 10 ms from the
#: worker's event loop (for the dashboard, which nobody looks at here): CPU on the cores
#: the rigs and the evaluations need
QUIET_WORKERS = {"distributed.worker.profile.enabled": False}


@dataclass
class Flight:
    """One task: fn(*args, cfg) in a rig, cfg.out_dir and cfg.iface being the rig's own;
    then, when given, post(value, *post_args, cfg) on the worker, outside the rig.  `count`:
    how many flights the task flies (one rig session may fly several: a campaign chunk),
    numbered first.. in the run; a task of several flights has them as its last argument (a
    list), so that the rest of a failed task is a task too (rest).  `salvage(work_dir,
    *args, cfg)`, when given: what a failed task finished (Salvaged-like: value, kept,
    flown), on the worker.  `part`: 0 for the task as made, k for its k-th rest or retry."""

    index: int
    fn: Callable[..., Any]
    args: tuple[Any, ...]
    count: int = 1
    post: Callable[..., Any] | None = None
    post_args: tuple[Any, ...] = ()
    first: int = 0
    salvage: Callable[..., Any] | None = None
    part: int = 0

    def rest(self, finished: int) -> Flight:
        """The task less its first `finished` flights (all of it when none)."""
        if finished == 0:
            return dataclasses.replace(self, part=self.part + 1)
        *head, flights = self.args
        return dataclasses.replace(self, args=(*head, flights[finished:]), count=self.count - finished,
                                   first=self.first + finished, part=self.part + 1)


@dataclass
class Done:
    """A task's value and where and how long it flew (a worker's answer); after a failure,
    `failure` (its cause, hil.parallel.engine.failure_record) and the value of the `kept`
    flights it finished (None when none)."""

    value: Any
    worker: str
    rig_s: float       # inside the rig (session, flight, results)
    task_s: float      # on the worker, the rig's hand-over included (its boot not)
    kept: int = 0
    failure: dict[str, Any] | None = None


@dataclass
class Results:
    """values: each task's values by task index (a task that failed part-way has several,
    its parts' in flight order); failed: the error of each flight that was never flown,
    by flight number; failures: every rig failure on the way (failure_record)."""

    values: dict[int, list[Any]] = field(default_factory=dict)
    failed: dict[int, str] = field(default_factory=dict)
    failures: list[dict[str, Any]] = field(default_factory=list)
    info: dict[str, Any] = field(default_factory=dict)


# ---- on a worker ------------------------------------------------------------------------------
_rig: GuestRig | None = None
_rig_lock = threading.Lock()


def _worker_rig(flight_timeout: float) -> GuestRig:
    global _rig  # noqa: PLW0603 - one rig per worker process, made on its first task
    with _rig_lock:
        if _rig is None:
            _rig = GuestRig(flight_timeout=flight_timeout)
        return _rig


def failure_record(flight: Flight, e: Exception, worker: str, flown: int, kept: int) -> dict[str, Any]:
    """A failed task as run_info lists it: the worker, the task's flights (first, last), the
    one in the air when it failed (None: it failed before or after its flights), how many
    it had finished and how many of those are kept, re-flown (the flights flown again
    because of it: the one in the air and any finished one not kept), the error's one
    line and its cause (hil.parallel.guest.RigFailed: process, status, signal, last_lines),
    and whether the worker lost its rig (the guest died)."""
    msg = str(e).splitlines()[0] if str(e) else type(e).__name__
    in_air = flight.first + flown if flown < flight.count else None
    return {"worker": worker, "host": socket.gethostname(),
            "flights": [flight.first, flight.first + flight.count - 1], "in_flight": in_air,
            "finished": flown, "kept": kept, "reflown": flown - kept + (in_air is not None),
            "error": msg if isinstance(e, RigFailed) else f"{type(e).__name__}: {msg}",
            "process": None, "status": None, "signal": None, "last_lines": [],
            **getattr(e, "cause", {}), "rig_lost": isinstance(e, RigDown)}


def fly_on_rig(flight: Flight, cfg: RigConfig, flight_timeout: float) -> Done:
    """The Dask task: a flight, or a chunk of flights, in this worker process's rig."""
    from distributed import get_worker  # Dask: slow to import, for --workers/--scheduler only
    worker = get_worker().address
    rig = _worker_rig(flight_timeout)
    work_dir = rig.work_dir(f"task-{flight.index:06d}.{flight.part}")
    t0 = time.perf_counter()
    try:
        with _rig_lock:
            if not rig.alive():
                rig.start()
                t0 = time.perf_counter()   # the boot is not the flight's
        fcfg = dataclasses.replace(cfg, out_dir=work_dir, iface=rig.iface, progress=False, plots=False)
        value, rig_s = rig.call(flight.fn, *flight.args, fcfg)
        if flight.post is not None:
            value = flight.post(value, *flight.post_args, cfg)
    except Exception as e:  # noqa: BLE001 - kept what it finished, with the cause, for the coordinator
        value, kept, flown = None, 0, 0
        if flight.salvage is not None:
            try:
                saved = flight.salvage(work_dir, *flight.args, cfg)
                value, kept, flown = saved.value, saved.kept, saved.flown
            except Exception:  # noqa: BLE001 - nothing kept: the task's flights are flown again
                pass
        return Done(value, worker, 0.0, time.perf_counter() - t0, kept,
                    failure_record(flight, e, worker, flown, kept))
    return Done(value, worker, rig_s, time.perf_counter() - t0, flight.count)


def stop_rig() -> int:
    """client.run: stop this worker's rig (its guest powers off)."""
    global _rig  # noqa: PLW0603 - one rig per worker process, made on its first task
    with _rig_lock:
        if _rig is not None:
            _rig.stop()
            _rig = None
    return os.getpid()


def suspicious_keys(keys: Sequence[str], dask_scheduler: Any = None) -> list[str]:
    """client.run_on_scheduler: those of `keys` that were on a worker when it died (Dask gave
    them to another worker: TaskState.suspicious)."""
    tasks = dask_scheduler.tasks
    return [k for k in keys if k in tasks and tasks[k].suspicious > 0]


def noop(x: int) -> int:
    """The engine's own cost per task (scripts/bench)."""
    return x


# ---- the coordinator --------------------------------------------------------------------------
class Cluster:
    """A Dask client on a local cluster of `workers` processes, or on `scheduler`."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None) -> None:
        import dask  # Dask: slow to import, for --workers/--scheduler only
        from distributed import Client, LocalCluster

        if (workers is None) == (scheduler is None):
            raise ValueError("give either a number of workers or a scheduler address")
        t0 = time.perf_counter()
        self.cluster = None
        with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES, **QUIET_WORKERS}):
            if scheduler is None:
                assert workers is not None
                self.cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                            dashboard_address=":0", memory_limit=0,
                                            silence_logs=logging.CRITICAL)
                self.client = Client(self.cluster)
            else:
                self.client = Client(scheduler, timeout=30)
                self.client.wait_for_workers(1, timeout=120)
        self.address = self.client.scheduler.address
        self.start_s = time.perf_counter() - t0

    def workers(self) -> list[str]:
        return sorted(self.client.scheduler_info()["workers"])

    def close(self) -> None:
        try:
            self.client.run(stop_rig)
        except Exception:  # noqa: BLE001 - a worker already gone: its rig stops on its lease
            pass
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()

    def __enter__(self) -> Cluster:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def run(self, flights: Sequence[Flight], cfg: RigConfig, *, progress: bool = True,
            desc: str = "flights", flight_timeout: float = FLIGHT_TIMEOUT_S) -> Results:
        """Every flight once (the rest of a failed task again; a task that fails TRIES times
        without finishing a flight is reported); values by task index."""
        from distributed import as_completed  # Dask: slow to import (as above)
        from distributed.scheduler import KilledWorker

        t0 = time.perf_counter()
        res = Results()
        meta: dict[Any, tuple[Flight, int]] = {}

        def submit(fl: Flight, tries: int, avoid: str | None = None) -> Any:
            kw: dict[str, Any] = {}
            others = [w for w in self.workers() if w != avoid]
            if avoid is not None and others:
                kw = {"workers": others, "allow_other_workers": False}
            fut = self.client.submit(fly_on_rig, fl, cfg, flight_timeout * fl.count, pure=False,
                                     key=f"hil-flight-{fl.index}-{fl.part}-{os.urandom(4).hex()}", **kw)
            meta[fut] = (fl, tries)
            return fut

        per_worker: Counter[str] = Counter()
        rig_s = task_s = 0.0
        finished_at: list[tuple[float, int]] = []   # (seconds, flights done by then)
        retried = 0                                  # flights flown again after a rig failure
        seen = set(self.workers())                   # to count the workers lost on the way
        rigs_lost: set[str] = set()                  # workers whose rig (guest) died
        ac = as_completed([submit(fl, 0) for fl in flights])
        n = 0
        with progress_bar(sum(fl.count for fl in flights), progress, desc, unit="flight") as bar:
            for fut in ac:
                fl, tries = meta[fut]                # kept (and the scheduler's task state)
                seen.update(self.workers())
                if fut.status != "finished":         # Dask's own failure: e.g. its worker died twice
                    exc = fut.exception()
                    what = "its worker died twice" if isinstance(exc, KilledWorker) else f"{type(exc).__name__}: {exc}"
                    for k in range(fl.first, fl.first + fl.count):
                        res.failed[k] = what
                    bar.update(fl.count)
                    continue
                done: Done = fut.result()
                if done.kept:
                    res.values.setdefault(fl.index, []).append(done.value)
                    per_worker[done.worker] += done.kept
                    rig_s += done.rig_s
                    task_s += done.task_s
                    n += done.kept
                    finished_at.append((time.perf_counter() - t0, n))
                    bar.update(done.kept)
                if done.failure is None:
                    continue
                res.failures.append(done.failure)
                if done.failure["rig_lost"]:
                    rigs_lost.add(done.worker)
                rest, tries = fl.rest(done.kept), (0 if done.kept else tries + 1)
                if tries < TRIES:
                    retried += done.failure["reflown"]
                    bar.set_postfix(retried=retried)
                    ac.add(submit(rest, tries, done.worker))
                    continue
                done.failure["reflown"] = 0          # given up: its flights are reported
                for k in range(rest.first, rest.first + rest.count):
                    res.failed[k] = done.failure["error"] + f" (worker {done.worker}, host {done.failure['host']})"
                bar.update(rest.count)
        wall = time.perf_counter() - t0
        # the flights Dask gave to another worker after theirs died (the coordinator never
        # sees those attempts), and the workers that left during the run or lost their rig
        moved = set(self.client.run_on_scheduler(suspicious_keys, [f.key for f in meta]))
        retried += sum(fl.count for f, (fl, _) in meta.items() if f.key in moved)
        lost = sorted((seen - set(self.workers())) | rigs_lost)
        # steady state: after as many tasks as workers (every rig has booted by then)
        k = len(per_worker)
        steady = None
        if k >= 1 and len(finished_at) > k and finished_at[-1][0] > finished_at[k - 1][0]:
            steady = (n - finished_at[k - 1][1]) / (finished_at[-1][0] - finished_at[k - 1][0])
        res.info = {"engine": "dask.distributed", "scheduler": self.address,
                    "workers": len(per_worker), "flights_by_worker": dict(sorted(per_worker.items())),
                    "tasks": len(flights), "flights_per_task": max((fl.count for fl in flights), default=0),
                    "cluster_start_s": self.start_s, "flights_wall_s": wall,
                    "flights_per_s": n / wall if wall > 0 else None,
                    "steady_flights_per_s": steady,
                    "rig_s_per_flight": rig_s / n if n else None,
                    "task_s_per_flight": task_s / n if n else None,
                    "retried": retried, "workers_lost": len(lost), "lost_workers": lost,
                    "failures": res.failures, "failed": len(res.failed)}
        return res
