"""`hil inject FAULT`: a fault into a realtime flight while it flies (hil.rig.inject).

One line on stdout when the rig applied it (the aircraft, the fault as applied, its step and
time); one line on stderr and exit 9 (EXIT_REFUSED) when refused, 2 for a fault the flight
cannot take, 1 when the rig did not answer in time.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from hil.bus.secoc import KeyFileError, read_key_file
from hil.cli.usage import EXIT_REFUSED, PROG
from hil.rig import inject
from hil.rig.session import KEPT_KEY
from hil.util.errors import HilError

#: how often the answer is looked for (s)
POLL_S = 0.02


def _channel(out: Path | None) -> Path:
    """The one live run's channel: in --out's staging directory, or the only one under out/."""
    found = inject.live_channels(out) if out is not None else sorted(
        p.parent for p in Path("out").glob(f".*.partial-*/{inject.CHANNEL}/{inject.STATE}"))
    where = f"--out {out}" if out is not None else "out/ (give the run's --out)"
    if not found:
        raise inject.InjectRefused(f"no run flies into {where}: start one with "
                                   f"`hil run missile --mode realtime`")
    if len(found) > 1:
        raise inject.InjectRefused(f"{len(found)} runs fly into {where}: give the run's --out")
    return found[0]


def _key(channel: Path, key_file: Path | None) -> bytes:
    path = key_file if key_file is not None else channel.parent / KEPT_KEY
    try:
        return read_key_file(path)
    except KeyFileError as e:
        hint = "" if key_file is not None else " (a run with --key-file: give the same --key-file)"
        raise inject.InjectRefused(f"no key for the run: {e}{hint}") from None


def _answer(channel: Path, rid: str, timeout: float) -> dict[str, object]:
    ack = channel / f"ack-{rid}.json"
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            doc = json.loads(ack.read_text(encoding="utf-8"))
        except FileNotFoundError:
            if not channel.is_dir():
                raise inject.InjectRefused("the run ended before the rig took the request") from None
            time.sleep(POLL_S)
            continue
        ack.unlink(missing_ok=True)
        return doc if isinstance(doc, dict) else {}
    (channel / f"req-{rid}.json").unlink(missing_ok=True)
    raise HilError(f"the rig did not answer within {timeout:g} s (is the run still flying?)")


def run(args: argparse.Namespace) -> int:
    try:
        channel = _channel(args.out)
        state = inject.read_state(channel)
        if state.get("mode") != "realtime":
            raise inject.InjectRefused(f"the run flies {state.get('mode')}: faults are injected "
                                       f"into realtime runs only (--mode realtime)")
        if not state.get("flying"):
            raise inject.InjectRefused("the run has not begun its flight yet: try again")
        text = inject.with_start(args.fault)
        inject.check_fault(text, state)   # ScenarioError: exit 2, as --fault's
        rid = inject.send(channel, text, _key(channel, args.key_file))
        doc = _answer(channel, rid, args.timeout)
        if not doc.get("ok"):
            raise inject.InjectRefused(f"the rig refused it: {doc.get('line')}")
    except inject.InjectRefused as e:
        print(f"{PROG} inject: {e}", file=sys.stderr)
        return EXIT_REFUSED
    print(f"injected: {doc.get('line')}")
    return 0
