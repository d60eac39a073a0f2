"""Flights on many rigs: this machine's own (``--workers N``: hil.parallel.local, N rigs driven
by threads of the command), or a running Dask cluster's (``--scheduler tcp://HOST:8786``)
whose workers are machines with the project built.

Each task is one flight or a chunk of consecutive flights: the worker's rig
(hil.parallel.guest, booted on the worker's first flight and kept) flies it and the value
comes back to this process.  One progress bar counts flights.  A task whose rig failed (fcc
died or hung, the guest died or did not answer) gives back what it finished (its salvage:
the flights whose results are whole) with the failure's cause, and the rest of its flights
are submitted again, to another worker when there is one: a failure costs the flight that
was in the air, not the chunk.  A task that fails twice without finishing a flight is
reported (its flights), and the others are kept.  A task whose worker process was killed is
flown again whole by Dask itself (``distributed.scheduler.allowed-failures`` = 1 here).
A Dask worker started with ``--preload hil.parallel.engine`` boots its rig as it starts
(dask_setup), not on its first task; with ``--nthreads 2`` one task flies while the other's
flights are evaluated (the rig flies one at a time).
"""
from __future__ import annotations

import logging
import os
import queue
import threading
import time
from collections import Counter
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

from hil.parallel.guest import GuestRig
from hil.parallel.local import LocalRigs
from hil.parallel.tasks import Done, Flight, Results, failure_record, fly_task
from hil.rig.config import RigConfig
from hil.util.progress import bar as progress_bar

FLIGHT_TIMEOUT_S = 120.0
#: Dask's rescheduling after a worker died: once (the flight is then reported)
ALLOWED_FAILURES = 1
#: failures in a row that finish no flight before a task's flights are reported
TRIES = 2
#: a local Dask worker's statistical profiler samples the task's stack every 10 ms from the
#: worker's event loop (for the dashboard, which nobody looks at here): CPU on the cores
#: the rigs and the evaluations need
QUIET_WORKERS = {"distributed.worker.profile.enabled": False}


# ---- on a worker ------------------------------------------------------------------------------
_rig: GuestRig | None = None
_rig_lock = threading.Lock()     # the rig's making and booting
_flying = threading.Lock()       # the rig flies one task at a time (another's post meanwhile)


def _worker_rig() -> GuestRig:
    global _rig  # noqa: PLW0603 - one rig per worker process, made on its first task
    with _rig_lock:
        if _rig is None:
            _rig = GuestRig()
        return _rig


def _boot_rig() -> None:
    """This worker's rig booted; a failed boot is the first task's to report (it boots
    again, GuestRig.call, and fails with the cause)."""
    rig = _worker_rig()
    with _rig_lock:
        if not rig.alive():
            try:
                rig.start()
            except Exception:  # noqa: BLE001 - reported by the first task
                pass


def dask_setup(worker: Any) -> None:
    """Dask's preload hook (``dask worker --preload hil.parallel.engine``): the worker's rig
    boots while the worker starts."""
    threading.Thread(target=_boot_rig, name="hil-rig-boot", daemon=True).start()


@contextmanager
def _this_workers_rig(worker: str) -> Iterator[tuple[GuestRig, str]]:
    """This worker process's rig, booted (a boot under way finished), held while it flies."""
    with _flying:
        rig = _worker_rig()
        with _rig_lock:
            if not rig.alive():
                rig.start()
        yield rig, worker


def fly_on_rig(flight: Flight, cfg: RigConfig, flight_timeout: float) -> Done:
    """The Dask task: a flight, or a chunk of flights, in this worker process's rig."""
    from distributed import get_worker  # Dask: slow to import, for --scheduler only
    worker = get_worker().address
    return fly_task(flight, cfg, flight_timeout, lambda: _this_workers_rig(worker))


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


def _dask(workers: int | None, scheduler: str | None) -> tuple[Any, Any]:
    """(a local Dask cluster of `workers` processes, or None), and a client on it or on `scheduler`."""
    import dask  # Dask: slow to import, for --scheduler only
    from distributed import Client, LocalCluster

    with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES, **QUIET_WORKERS}):
        if scheduler is None:
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", memory_limit=0, silence_logs=logging.CRITICAL)
            return cluster, Client(cluster)
        client = Client(scheduler, timeout=30)
        client.wait_for_workers(1, timeout=120)
        return None, client


#: how long the coordinator waits for a task at a time: a signal (Ctrl-C) is handled by then
#: (the kernel may deliver it to any thread; the main thread sees it only when its wait ends)
WAKE_S = 0.2


def _next(finished: queue.Queue[Any]) -> Any:
    """The next finished task, waiting WAKE_S at a time (an interrupt raises between waits)."""
    while True:
        try:
            return finished.get(timeout=WAKE_S)
        except queue.Empty:
            continue


# ---- the coordinator --------------------------------------------------------------------------
class Cluster:
    """`workers` rigs of this machine (hil.parallel.local; with rigs=False, for tasks without
    rigs: a local Dask cluster of `workers` processes), or a Dask client on `scheduler`."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None, *, rigs: bool = True) -> None:
        if (workers is None) == (scheduler is None):
            raise ValueError("give either a number of workers or a scheduler address")
        t0 = time.perf_counter()
        self.cluster: Any = None
        self.local: LocalRigs | None = None
        self._closing: threading.Thread | None = None
        self.client: Any = None
        if workers is not None and rigs:
            self.local = LocalRigs(workers)
            self.address = "local"
        else:
            self.cluster, self.client = _dask(workers, scheduler)
            self.address = self.client.scheduler.address
        self.start_s = time.perf_counter() - t0

    def workers(self) -> list[str]:
        if self.local is not None:
            return self.local.workers()
        return sorted(self.client.scheduler_info()["workers"])

    def close_soon(self) -> None:
        """This machine's rigs start stopping now (their guests power off while the caller
        writes the results); close() waits for them.  (A Dask cluster closes in close().)"""
        if self.local is not None and self._closing is None:
            self._closing = threading.Thread(target=self.local.close, name="hil-rigs-stop")
            self._closing.start()

    def close(self) -> None:
        if self.local is not None:
            if self._closing is None:
                self.local.close()
            else:
                self._closing.join()
            return
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

    def _submit(self, fl: Flight, cfg: RigConfig, flight_timeout: float, avoid: str | None) -> Any:
        """The task submitted, to another worker than `avoid` when there is one (Dask; this
        machine's rigs take the next idle rig: a failed one boots again)."""
        if self.local is not None:
            return self.local.submit(fl, cfg, flight_timeout)
        kw: dict[str, Any] = {}
        others = [w for w in self.workers() if w != avoid]
        if avoid is not None and others:
            kw = {"workers": others, "allow_other_workers": False}
        return self.client.submit(fly_on_rig, fl, cfg, flight_timeout, pure=False,
                                  key=f"hil-flight-{fl.index}-{fl.part}-{os.urandom(4).hex()}", **kw)

    def _moved(self, futures: Sequence[Any]) -> set[str]:
        """The keys of the tasks Dask gave to another worker after theirs died."""
        if self.local is not None:
            return set()
        return set(self.client.run_on_scheduler(suspicious_keys, [f.key for f in futures]))

    def run(self, flights: Sequence[Flight], cfg: RigConfig, *, progress: bool = True,
            desc: str = "flights", flight_timeout: float = FLIGHT_TIMEOUT_S) -> Results:
        """Every flight once (the rest of a failed task again; a task that fails TRIES times
        without finishing a flight is reported); values by task index."""
        t0 = time.perf_counter()
        res = Results()
        meta: dict[Any, tuple[Flight, int]] = {}
        finished: queue.Queue[Any] = queue.Queue()

        def submit(fl: Flight, tries: int, avoid: str | None = None) -> None:
            fut = self._submit(fl, cfg, flight_timeout * fl.count, avoid)
            meta[fut] = (fl, tries)
            fut.add_done_callback(finished.put)

        per_worker: Counter[str] = Counter()
        rig_s = task_s = 0.0
        finished_at: list[tuple[float, int]] = []   # (seconds, flights done by then)
        retried = 0                                  # flights flown again after a rig failure
        seen = set(self.workers())                   # to count the workers lost on the way
        rigs_lost: set[str] = set()                  # workers whose rig (guest) died
        for fl in flights:
            submit(fl, 0)
        n = 0
        pending = len(flights)
        with progress_bar(sum(fl.count for fl in flights), progress, desc, unit="flight") as bar:
            while pending:
                fut = _next(finished)
                pending -= 1
                fl, tries = meta[fut]                # kept (and the scheduler's task state)
                seen.update(self.workers())
                exc = fut.exception()
                if exc is not None:                  # the engine's own failure: e.g. a Dask worker died twice
                    what = ("its worker died twice" if type(exc).__name__ == "KilledWorker"
                            else f"{type(exc).__name__}: {exc}")
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
                    submit(rest, tries, done.worker)
                    pending += 1
                    continue
                done.failure["reflown"] = 0          # given up: its flights are reported
                for k in range(rest.first, rest.first + rest.count):
                    res.failed[k] = done.failure["error"] + f" (worker {done.worker}, host {done.failure['host']})"
                bar.update(rest.count)
        wall = time.perf_counter() - t0
        # the flights Dask gave to another worker after theirs died (the coordinator never
        # sees those attempts), and the workers that left during the run or lost their rig
        moved = self._moved(list(meta))
        retried += sum(fl.count for f, (fl, _) in meta.items() if getattr(f, "key", None) in moved)
        lost = sorted((seen - set(self.workers())) | rigs_lost)
        # steady state: after as many tasks as workers (every rig has booted by then)
        k = len(per_worker)
        steady = None
        if k >= 1 and len(finished_at) > k and finished_at[-1][0] > finished_at[k - 1][0]:
            steady = (n - finished_at[k - 1][1]) / (finished_at[-1][0] - finished_at[k - 1][0])
        res.info = {"engine": "local rigs" if self.local is not None else "dask.distributed",
                    "scheduler": self.address,
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


__all__ = ["Cluster", "Done", "Flight", "Results", "dask_setup", "failure_record", "fly_on_rig", "noop", "stop_rig"]
