"""The host does the UML guest's maths: the bus side of a flight stays in the guest, the numpy
side (the flight's samples before it, the results after it) runs on the host.

Why: inside scripts/with-vcan's User-Mode Linux guest a system call costs ~22 us and importing
numpy ~0.6 s (0.12 s on the host), so a lockstep `hil run cdrw` spent most of its start-up on
importing and computing, not on the bus.  The host has a CPU of its own beside the guest's.

    scripts/with-vcan (host)      python -m hil.offload serve DIR, started before the guest
                                  boots: it imports the maths while the guest boots, writes
                                  DIR/ready, and answers calls until with-vcan stops it
    hil in the guest              offload.call("hil.rig.runs:evaluate_flight", ...) when
                                  $HIL_OFFLOAD_DIR names a ready server of the same hil

A call is two pickles in DIR (the guest's root file system is the host's): the request
req-PID-N.pkl (function, arguments, the caller's environment and working directory, so the
call runs as if in the caller) and the answer resp-PID-N.pkl (the value, or the exception,
raised again in the caller).  A round trip costs ~2 ms.  The server runs one call at a time;
what a call keeps for a later one of the same flight (offload.keep/take) lives in its memory.
The directory is with-vcan's own (mode 700), so only its guest writes requests there.
"""
from __future__ import annotations

import argparse
import importlib
import itertools
import os
import pickle
import sys
import threading
import time
from pathlib import Path
from typing import Any

ENV = "HIL_OFFLOAD_DIR"
READY = "ready"
#: how long a caller waits for an answer (a long flight's evaluation; the server beats meanwhile)
CALL_TIMEOUT_S = 900.0
#: the caller's polling interval, and the server's for HOT_S after a call (a flight's evaluation
#: follows its drivers within seconds); idle, the server looks every IDLE_POLL_S (polling at
#: 1 ms cost it 7 % of a CPU)
POLL_S = 0.001
HOT_S = 5.0
IDLE_POLL_S = 0.02
#: the server touches DIR/ready this often; older than STALE_S, it is taken for dead
BEAT_S = 1.0
STALE_S = 10.0
#: what the server imports before it says ready (the maths of a CDRW flight and its results)
PRELOAD = ("hil.rig.runs", "hil.rig.results", "hil.rig.rowtables", "hil.plants.cdrw_flight",
           "hil.rig.simtime")


class OffloadError(RuntimeError):
    """The host's server is gone or did not answer (one line)."""


def _package_dir() -> str:
    return str(Path(__file__).resolve().parent)


def server_dir() -> Path | None:
    """The directory of a live, ready server running this same hil (None: do the work here)."""
    d = os.environ.get(ENV)
    if not d:
        return None
    try:
        ready = (Path(d) / READY).read_text(encoding="utf-8").strip()
    except OSError:
        return None
    return Path(d) if ready == _package_dir() and _alive(Path(d)) else None


def _alive(d: Path) -> bool:
    """The server has said it lives within STALE_S (the guest cannot see host processes)."""
    try:
        return time.time() - (d / READY).stat().st_mtime < STALE_S
    except OSError:
        return False


_calls = itertools.count()


class Pending:
    """A call on its way: the host works while the caller goes on; result() waits for it."""

    def __init__(self, d: Path, func: str, args: tuple[Any, ...]) -> None:
        self.dir, self.func = d, func
        name = f"{os.getpid()}-{next(_calls)}.pkl"
        tmp = d / f".req-{name}"
        tmp.write_bytes(pickle.dumps((func, args, dict(os.environ), os.getcwd()),
                                     protocol=pickle.HIGHEST_PROTOCOL))
        tmp.rename(d / f"req-{name}")
        self.answer = d / f"resp-{name}"

    def result(self) -> Any:
        """The function's value, or its exception raised here."""
        deadline = time.monotonic() + CALL_TIMEOUT_S
        while True:
            try:
                data = self.answer.read_bytes()
                break
            except FileNotFoundError:
                if time.monotonic() > deadline or not _alive(self.dir):
                    raise OffloadError(f"hil.offload: the host's server did not answer "
                                       f"{self.func}") from None
                time.sleep(POLL_S)
        self.answer.unlink()
        ok, value = pickle.loads(data)
        if not ok:
            raise value
        return value


def submit(func: str, *args: Any) -> Pending:
    """Start func ("module:name") with args on the host's server."""
    d = server_dir()
    if d is None:
        raise OffloadError(f"no hil.offload server ready in ${ENV}")
    return Pending(d, func, args)


def call(func: str, *args: Any) -> Any:
    """func ("module:name") called with args by the host's server: its value."""
    return submit(func, *args).result()


# ---- what a call keeps for a later call (the host's half of a flight) -------------------------
_kept: dict[int, Any] = {}
_keys = itertools.count(1)


def keep(obj: Any) -> int:
    """Hold obj in this process until take(key)."""
    key = next(_keys)
    _kept[key] = obj
    return key


def take(key: int) -> Any:
    return _kept.pop(key)


# ---- the server --------------------------------------------------------------------------------
def _run(func: str, args: tuple[Any, ...], env: dict[str, str], cwd: str) -> tuple[bool, Any]:
    module, _, name = func.partition(":")
    if not module.startswith("hil."):
        return False, OffloadError(f"hil.offload: {func} is not a hil function")
    saved_env, saved_cwd = dict(os.environ), os.getcwd()
    os.environ.clear()
    os.environ.update(env)
    try:
        os.chdir(cwd)
        return True, getattr(importlib.import_module(module), name)(*args)
    except Exception as e:  # noqa: BLE001 - the caller raises it again
        return False, e
    finally:
        os.chdir(saved_cwd)
        os.environ.clear()
        os.environ.update(saved_env)


def _answer(d: Path, req: Path) -> None:
    func, args, env, cwd = pickle.loads(req.read_bytes())
    req.unlink()
    result = _run(func, args, env, cwd)
    try:
        data = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception as e:  # noqa: BLE001 - an unpicklable value or exception: say what it was
        data = pickle.dumps((False, OffloadError(f"hil.offload: {func}: {type(e).__name__}: {e}")))
    name = req.name[len("req-"):]
    tmp = d / f".resp-{name}"
    tmp.write_bytes(data)
    tmp.rename(d / f"resp-{name}")


def _beat(ready: Path, stop: threading.Event) -> None:
    """Touch the ready file while the server lives, also during a long call."""
    while not stop.wait(BEAT_S):
        try:
            os.utime(ready)
        except OSError:
            return


def serve(d: Path, parent: int) -> None:
    """Answer calls in d until the parent (with-vcan) is gone or d is removed."""
    for m in PRELOAD:
        importlib.import_module(m)
    ready = d / READY
    ready.write_text(_package_dir() + "\n", encoding="utf-8")
    stop = threading.Event()
    threading.Thread(target=_beat, args=(ready, stop), daemon=True).start()
    last_call = -HOT_S
    try:
        while d.is_dir():
            reqs = sorted(p for p in d.iterdir() if p.name.startswith("req-"))
            for req in reqs:
                _answer(d, req)
                last_call = time.monotonic()
            if not reqs:
                try:
                    os.kill(parent, 0)
                except ProcessLookupError:
                    break
                time.sleep(POLL_S if time.monotonic() - last_call < HOT_S else IDLE_POLL_S)
    finally:
        stop.set()
        ready.unlink(missing_ok=True)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.offload",
                                description="answer the hil calls of a UML guest (scripts/with-vcan)")
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("serve", help="serve calls in DIR until PID exits")
    s.add_argument("dir", type=Path)
    s.add_argument("--parent", type=int, required=True, help="stop when this process has exited")
    args = p.parse_args(argv)
    if not args.dir.is_dir():
        print(f"hil.offload: {args.dir}: not a directory", file=sys.stderr)
        return 2
    serve(args.dir, args.parent)
    return 0


if __name__ == "__main__":  # through the package, so that what crosses pickles as hil.offload's
    from hil.offload import main as _main
    sys.exit(_main())
