"""`hil rig up|status|down`: a warm rig (hil.parallel.keeper), for the commands flown on it
with --rig (hil.cli.onrig), the guest's boot and Python's imports paid once.

    hil rig up [--target host|qemu-m4f] [--idle-timeout S]   (returns once the rig is ready)
    hil rig status                                         (0 up, 1 down)
    hil rig down                                           (the guest stopped, nothing left)
"""
from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import time

from hil.cli.usage import EXIT_FAILED, PROG
from hil.parallel import forked
from hil.parallel.warm import STATE, State, client_attached, pid_alive, read_state, state_dir

#: the modules a rig's loop imports before its first command (what `hil run|verify|campaign`
#: import on their way: the commands then start with them loaded)
PRELOAD = ("hil.cli", "hil.cli.needs", "hil.cli.run", "hil.cli.campaign", "hil.cli.verify", "hil.runs.run",
           "hil.runs.campaign", "hil.runs.evaluate", "hil.runs.outcome", "hil.rig.session",
           "hil.rig.flight", "hil.rig.lockstep", "hil.rig.ack", "hil.rig.simtime", "hil.rig.tickplan",
           "hil.targets.host", "hil.sim.drivers", "hil.results.flight", "hil.results.report",
           "hil.results.rowtables", "hil.results.sidrows", "hil.results.sync", "hil.results.timing",
           "hil.bus.busload", "hil.bus.logio", "numpy", "numpy.random",
           "cryptography.hazmat.primitives.cmac", "cryptography.hazmat.primitives.ciphers.algorithms",
           "cryptography.hazmat.decrepit.ciphers.algorithms")
#: how long `hil rig down` waits for the keeper to stop the guest before killing both
DOWN_WAIT_S = 60.0
KEEPER_LOG = "keeper.log"


def run(args: argparse.Namespace) -> int:
    return {"up": up, "status": status, "down": down}[args.rig_command](args)


def up(args: argparse.Namespace) -> int:
    d = state_dir()
    state = read_state(d)
    if state is not None:
        print(f"rig already up: pid {state.pid}, target {state.target} ({d / STATE})")
        return 0
    with open(d / KEEPER_LOG, "wb") as log:
        keeper = subprocess.Popen([sys.executable, "-m", "hil.parallel.keeper", str(d), "--target", args.target,
                                   "--idle-timeout", str(args.idle_timeout), "--preload", ",".join(PRELOAD)],
                                  stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                  start_new_session=True)
    while (state := read_state(d)) is None or state.pid != keeper.pid:
        if keeper.poll() is not None:
            lines = (d / KEEPER_LOG).read_text(errors="replace").strip().splitlines()
            print(f"{PROG}: rig up: the rig did not start ({lines[-1] if lines else keeper.returncode}; "
                  f"{d / KEEPER_LOG})", file=sys.stderr)
            return EXIT_FAILED
        time.sleep(0.05)
    print(f"rig up: pid {state.pid}, target {state.target}, interface {state.iface}, idle timeout "
          f"{state.idle_timeout:g} s ({d / STATE})")
    return 0


def describe(state: State) -> list[str]:
    client = client_attached(state)
    return [f"rig: up, pid {state.pid}, target {state.target}, interface {state.iface}",
            f"uptime: {time.time() - state.started:.0f} s, commands run: {forked.runs(state.root)}, "
            f"idle timeout: {state.idle_timeout:g} s",
            f"client: {'none' if client is None else f'pid {client}'}"]


def status(args: argparse.Namespace) -> int:
    state = read_state(state_dir())
    if state is None:
        print("rig: down")
        return EXIT_FAILED
    print("\n".join(describe(state)))
    return 0


def down(args: argparse.Namespace) -> int:
    state = read_state(state_dir())
    if state is None:
        print("rig: down (none was up)")
        return 0
    os.kill(state.pid, signal.SIGTERM)
    deadline = time.monotonic() + DOWN_WAIT_S
    while pid_alive(state.pid):
        if time.monotonic() > deadline:     # a keeper that does not stop: killed, its guest stopped
            for pid, sig in ((state.pid, signal.SIGKILL), (state.guest, signal.SIGTERM)):
                try:
                    os.kill(pid, sig)      # (scripts/with-vcan stops its guest on SIGTERM)
                except ProcessLookupError:
                    pass
            print(f"{PROG}: rig down: the keeper did not stop within {DOWN_WAIT_S:g} s: killed", file=sys.stderr)
            return EXIT_FAILED
        time.sleep(0.05)
    print(f"rig: down (pid {state.pid} stopped)")
    return 0
