"""A warm rig's keeper: ``python -m hil.parallel.keeper STATE_DIR --target T --idle-timeout S
[--preload MOD,...]``, started by `hil rig up` in a session of its own.

It boots the rig as a campaign's worker does (hil.parallel.guest: a UML guest, or a vcanK of
its own, with the flight loop of hil.parallel.server), has the loop import the commands'
modules and a CDRW flight's samples (hil.parallel.warmup), writes the state file (hil.parallel.warm) and then
watches: a command whose client died is cancelled (the rig stays usable); the rig stops
after S seconds without a command, on SIGTERM, SIGINT or SIGHUP (`hil rig down`), or when its
guest died -- removing the state file and the guest with everything in it.  Killed
outright (SIGKILL), it leaves the guest to end by itself when its lease runs out
(hil.parallel.files.LEASE_S).
"""
from __future__ import annotations

import argparse
import os
import signal
import sys
import time
from pathlib import Path

from hil.parallel import forked
from hil.parallel.guest import GuestRig
from hil.parallel.warm import STATE, State, pid_alive
from hil.parallel.warmup import warm_up

WATCH_S = 0.2


class Stopped(Exception):
    """A signal asked the keeper to stop."""


def _stop(signum: int, _frame: object) -> None:
    raise Stopped(signal.Signals(signum).name)


def watch(rig: GuestRig, idle_timeout: float) -> str:
    """Until the rig should stop: why it stops."""
    assert rig.dir is not None
    root, last, cancelled = rig.dir, time.monotonic(), None
    while rig.alive():
        now = forked.running(root)
        if now is not None:
            last = time.monotonic()
            pid, name = now
            if name != cancelled and not pid_alive(pid):
                forked.cancel(root, name)
                cancelled = name
                print(f"client {pid} died: its command {name} cancelled", flush=True)
        elif any((root / "req").iterdir()):
            last = time.monotonic()
        elif time.monotonic() - last > idle_timeout:
            return f"idle for {idle_timeout:g} s"
        time.sleep(WATCH_S)
    return "its guest stopped"


def keep(state_dir: Path, target: str, idle_timeout: float, modules: list[str]) -> int:
    state = state_dir / STATE
    rig = GuestRig(root=state_dir)
    for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
        signal.signal(sig, _stop)
    try:
        rig.start()
        assert rig.dir is not None and rig.proc is not None
        rig.call(warm_up, modules, rig.iface)
        State(os.getpid(), str(rig.dir), rig.token, target, rig.iface, time.time(), idle_timeout,
              rig.proc.pid).write(state)
        print(f"rig up: {rig.dir}", flush=True)
        why = watch(rig, idle_timeout)
    except Stopped as e:
        why = f"stopped by {e}"
    except Exception as e:  # noqa: BLE001 - the keeper's log says why, `hil rig up` prints it
        why = f"failed: {type(e).__name__}: {e}"
    finally:
        for sig in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
            signal.signal(sig, signal.SIG_IGN)   # the guest is stopped whatever comes now
        state.unlink(missing_ok=True)
        rig.stop()
    print(f"rig down: {why}", flush=True)
    return 1 if why.startswith("failed") or why == "its guest stopped" else 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.parallel.keeper")
    p.add_argument("state_dir", type=Path)
    p.add_argument("--target", default="host")
    p.add_argument("--idle-timeout", type=float, default=1800.0)
    p.add_argument("--preload", default="")
    a = p.parse_args(sys.argv[1:] if argv is None else argv)
    return keep(a.state_dir, a.target, a.idle_timeout, [m for m in a.preload.split(",") if m])


if __name__ == "__main__":
    sys.exit(main())
