"""`--workers N` on this machine: N rigs driven by threads of the command itself, without Dask.

Each rig is a guest (or vcanK) of its own, as a Dask worker's is; the real work is there.
Dask's local cluster cost more than the work of a short campaign: a scheduler, and a nanny
and a worker process per rig, each importing Dask and hil (about 2 s of CPU to start and
stop them), their event loops beside the rigs, and each chunk's evaluation in a worker
process while its rig waited.  Here the rigs boot at once, all together, as the command
starts; a pool of 2 threads a rig (PIPELINE) flies the tasks: a task takes the next idle
rig, flies its chunk there, gives the rig back and evaluates its flights (Flight.post) while
the rig flies the next task.  The evaluations share this process (about 15 ms of Python and
numpy a flight, its sid_replay a process of its own).  A rig that dies is booted again by its
next task (GuestRig.call); the engine's retries are hil.parallel.engine's, as for Dask.
"""
from __future__ import annotations

import itertools
import queue
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ThreadPoolExecutor
from contextlib import contextmanager

from hil.parallel.guest import GuestRig, RigDown
from hil.parallel.tasks import Done, Flight, fly_task
from hil.rig.config import RigConfig

#: tasks under way per rig: one flying in it, one evaluated (its post) meanwhile
PIPELINE = 2
#: this process's engines so far: each one's rigs have directories of their own (a failed
#: task's directory is kept for a look, and the next engine's must not be it)
_engines = itertools.count()


class LocalRigs:
    """`n` rigs of this process, booting from the start; submit() flies a task on one."""

    def __init__(self, n: int) -> None:
        if n < 1:
            raise ValueError(f"LocalRigs: n must be >= 1, got {n}")
        engine = next(_engines)
        self.rigs = [GuestRig(name=f"-{engine}.{k}") for k in range(n)]
        self.names = {id(r): f"rig-{k}" for k, r in enumerate(self.rigs)}
        self._idle: queue.Queue[GuestRig] = queue.Queue()
        self._pool = ThreadPoolExecutor(PIPELINE * n, thread_name_prefix="hil-rig-task")
        self._futures: list[Future[Done]] = []
        self._closing = threading.Event()
        self._boots = [threading.Thread(target=self._boot, args=(r,), name="hil-rig-boot", daemon=True)
                       for r in self.rigs]
        for t in self._boots:
            t.start()

    def _boot(self, rig: GuestRig) -> None:
        """Boot a rig and make it idle; a failed boot is its first task's to report (the
        task boots it again, GuestRig.call, and fails with the cause)."""
        try:
            rig.start()
        except Exception:  # noqa: BLE001 - reported by the task that boots it again
            pass
        self._idle.put(rig)

    def workers(self) -> list[str]:
        return sorted(self.names.values())

    @contextmanager
    def _take(self) -> Iterator[tuple[GuestRig, str]]:
        """The next idle rig and its name, held until given back."""
        rig = self._idle.get()
        if self._closing.is_set():
            self._idle.put(rig)
            raise RigDown("the rigs are stopping (the command was interrupted)")
        try:
            yield rig, self.names[id(rig)]
        finally:
            self._idle.put(rig)

    def submit(self, flight: Flight, cfg: RigConfig, flight_timeout: float) -> Future[Done]:
        fut = self._pool.submit(fly_task, flight, cfg, flight_timeout, self._take, self._closing)
        self._futures.append(fut)
        return fut

    def close(self) -> None:
        """Every rig stopped, all at once: each guest powers off; when tasks are still under
        way (the command was interrupted), the rigs are killed first, so that their tasks end
        at once (and take no rig again), then the pool's threads end."""
        self._closing.set()
        for t in self._boots:
            t.join()
        if not all(f.done() for f in self._futures):
            self._each_rig(GuestRig.kill)
        self._pool.shutdown(wait=True, cancel_futures=True)
        self._each_rig(GuestRig.stop)

    def _each_rig(self, what: Callable[[GuestRig], None]) -> None:
        threads = [threading.Thread(target=what, args=(r,), name="hil-rig-stop") for r in self.rigs]
        for t in threads:
            t.start()
        for t in threads:
            t.join()

    def __repr__(self) -> str:
        return f"LocalRigs({len(self.rigs)})"
