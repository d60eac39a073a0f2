"""A task of the parallel engines (hil.parallel.engine: Dask, or this machine's own rigs driven
by threads of the command): what it is (Flight), what comes back (Done), what a run gives
(Results), and its flight on a rig (fly_task): the rig flies it, the worker evaluates it
(Flight.post) outside the rig, and a failed task gives back what it finished (its salvage)
with the failure's cause (failure_record).
"""
from __future__ import annotations

import dataclasses
import socket
import threading
import time
from collections.abc import Callable
from contextlib import AbstractContextManager
from dataclasses import dataclass, field
from typing import Any

from hil.parallel.guest import GuestRig, RigDown, RigFailed
from hil.rig.config import RigConfig


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


def fly_task(flight: Flight, cfg: RigConfig, flight_timeout: float,
             rig: Callable[[], AbstractContextManager[tuple[GuestRig, str]]],
             stopping: threading.Event | None = None) -> Done:
    """A flight, or a chunk of flights: flown in the rig that rig() gives with its worker's
    name (booted, and held while it flies; another task may be evaluated meanwhile), then
    evaluated here (post).  The times in Done are this task's own: neither the rig's boot
    nor another task's flight.  A task that fails once `stopping` is set (the command was
    interrupted) salvages nothing: nobody waits for it."""
    work_dir = None
    worker = "?"
    t0 = time.perf_counter()
    try:
        with rig() as (guest, worker):
            t0 = time.perf_counter()
            work_dir = guest.work_dir(f"task-{flight.index:06d}.{flight.part}")
            guest.flight_timeout = flight_timeout
            fcfg = dataclasses.replace(cfg, out_dir=work_dir, iface=guest.iface, progress=False, plots=False)
            value, rig_s = guest.call(flight.fn, *flight.args, fcfg)
            flown_s = time.perf_counter() - t0
        t0 = time.perf_counter() - flown_s
        if flight.post is not None:
            value = flight.post(value, *flight.post_args, cfg)
    except Exception as e:  # noqa: BLE001 - kept what it finished, with the cause, for the coordinator
        value, kept, flown = None, 0, 0
        if flight.salvage is not None and work_dir is not None and not (stopping and stopping.is_set()):
            try:
                saved = flight.salvage(work_dir, *flight.args, cfg)
                value, kept, flown = saved.value, saved.kept, saved.flown
            except Exception:  # noqa: BLE001 - nothing kept: the task's flights are flown again
                pass
        return Done(value, worker, 0.0, time.perf_counter() - t0, kept,
                    failure_record(flight, e, worker, flown, kept))
    return Done(value, worker, rig_s, time.perf_counter() - t0, flight.count)


__all__ = ["Done", "Flight", "Results", "failure_record", "fly_task"]
