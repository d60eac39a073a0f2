"""Flights on a Dask cluster: a local one of N worker processes (one rig each), or a running
cluster's scheduler (``--scheduler tcp://HOST:8786``) whose workers are machines with the
project built.

Each task is one flight: the worker's rig (hil.parallel.guest, booted on the worker's first
flight and kept) flies it and the value comes back to this process.  One progress bar counts
flights.  A flight whose rig failed (fcc died or hung, the guest died or did not answer) is
submitted once more, to another worker when there is one; a flight whose worker process was
killed is rescheduled by Dask itself (``distributed.scheduler.allowed-failures`` = 1 here).
A flight that fails twice is reported, and the others are kept.
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

from hil.parallel.guest import GuestRig
from hil.rig.config import RigConfig
from hil.util.progress import bar as progress_bar

FLIGHT_TIMEOUT_S = 120.0
#: Dask's rescheduling after a worker died: once (the flight is then reported)
ALLOWED_FAILURES = 1
#: a local worker's statistical profiler samples the task's stack every 10 ms from the
#: worker's event loop (for the dashboard, which nobody looks at here): CPU on the cores
#: the rigs and the evaluations need
QUIET_WORKERS = {"distributed.worker.profile.enabled": False}


@dataclass
class Flight:
    """One task: fn(*args, cfg) in a rig, cfg.out_dir and cfg.iface being the rig's own;
    then, when given, post(value, *post_args, cfg) on the worker, outside the rig.  `count`:
    how many flights the task flies (one rig session may fly several: a campaign chunk)."""

    index: int
    fn: Callable[..., Any]
    args: tuple[Any, ...]
    count: int = 1
    post: Callable[..., Any] | None = None
    post_args: tuple[Any, ...] = ()


@dataclass
class Done:
    """A flight's value and where and how long it flew (a worker's answer)."""

    value: Any
    worker: str
    rig_s: float       # inside the rig (session, flight, results)
    task_s: float      # on the worker, the rig's hand-over included (its boot not)


class FlightFailed(RuntimeError):
    """A flight failed on a worker: (one line, that worker's address)."""

    def __init__(self, message: str, worker: str) -> None:
        super().__init__(message, worker)

    def __str__(self) -> str:
        return str(self.args[0])


@dataclass
class Results:
    values: dict[int, Any] = field(default_factory=dict)
    failed: dict[int, str] = field(default_factory=dict)
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


def fly_on_rig(flight: Flight, cfg: RigConfig, flight_timeout: float) -> Done:
    """The Dask task: one flight in this worker process's rig."""
    from distributed import get_worker  # Dask: slow to import, for --workers/--scheduler only
    worker = get_worker().address
    rig = _worker_rig(flight_timeout)
    t0 = time.perf_counter()
    try:
        with _rig_lock:
            if not rig.alive():
                rig.start()
                t0 = time.perf_counter()   # the boot is not the flight's
        fcfg = dataclasses.replace(cfg, out_dir=rig.work_dir(f"task-{flight.index:06d}"),
                                   iface=rig.iface, progress=False, plots=False)
        value, rig_s = rig.call(flight.fn, *flight.args, fcfg)
        if flight.post is not None:
            value = flight.post(value, *flight.post_args, cfg)
    except Exception as e:  # noqa: BLE001 - one line, with the worker, for the coordinator
        msg = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise FlightFailed(f"{type(e).__name__}: {msg} (worker {worker}, host {socket.gethostname()})",
                           worker) from None
    return Done(value, worker, rig_s, time.perf_counter() - t0)


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
        """Every flight once (a failed one twice); values by flight index."""
        from distributed import as_completed  # Dask: slow to import (as above)
        from distributed.scheduler import KilledWorker

        t0 = time.perf_counter()
        res = Results()
        meta: dict[Any, tuple[Flight, int]] = {}

        def submit(fl: Flight, attempt: int, avoid: str | None = None) -> Any:
            kw: dict[str, Any] = {}
            others = [w for w in self.workers() if w != avoid]
            if avoid is not None and others:
                kw = {"workers": others, "allow_other_workers": False}
            fut = self.client.submit(fly_on_rig, fl, cfg, flight_timeout * fl.count, pure=False,
                                     key=f"hil-flight-{fl.index}-{attempt}-{os.urandom(4).hex()}", **kw)
            meta[fut] = (fl, attempt)
            return fut

        per_worker: Counter[str] = Counter()
        rig_s = task_s = 0.0
        finished_at: list[tuple[float, int]] = []   # (seconds, flights done by then)
        retried = 0                                  # flights flown again after a rig failure
        seen = set(self.workers())                   # to count the workers lost on the way
        ac = as_completed([submit(fl, 0) for fl in flights])
        n = 0
        with progress_bar(sum(fl.count for fl in flights), progress, desc, unit="flight") as bar:
            for fut in ac:
                fl, attempt = meta[fut]              # kept (and the scheduler's task state)
                seen.update(self.workers())
                if fut.status == "finished":
                    done: Done = fut.result()
                    res.values[fl.index] = done.value
                    per_worker[done.worker] += fl.count
                    rig_s += done.rig_s
                    task_s += done.task_s
                    n += fl.count
                    finished_at.append((time.perf_counter() - t0, n))
                    bar.update(fl.count)
                    continue
                exc = fut.exception()
                if attempt == 0 and not isinstance(exc, KilledWorker):
                    retried += fl.count
                    bar.set_postfix(retried=retried)
                    avoid = exc.args[1] if isinstance(exc, FlightFailed) else None
                    ac.add(submit(fl, 1, avoid))
                    continue
                what = "its worker died twice" if isinstance(exc, KilledWorker) else str(exc)
                res.failed[fl.index] = what
                bar.update(fl.count)
        wall = time.perf_counter() - t0
        # the flights Dask gave to another worker after theirs died (the coordinator never
        # sees those attempts), and the workers that left during the run
        moved = set(self.client.run_on_scheduler(suspicious_keys, [f.key for f in meta]))
        retried += sum(fl.count for f, (fl, _) in meta.items() if f.key in moved)
        lost = sorted(seen - set(self.workers()))
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
                    "failed": len(res.failed)}
        return res
