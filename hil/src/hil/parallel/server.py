"""The loop inside a worker's rig: ``python -m hil.parallel.server DIR``.

Runs where the rig's CAN interface is (a UML guest started by scripts/with-vcan, or the host
with its own vcanK).  DIR is shared with the host side (hil.parallel.guest): its files are hil.parallel.files'.
The flights' modules (hil.parallel.flights) are imported with this one, before DIR/ready is
written: at the rig's boot, not at its first flight's time.  A request is run only under the
rig's token (DIR/token); a warm rig's commands (hil.parallel.forked) come through here too.
"""
from __future__ import annotations

import hmac
import os
import pickle
import sys
import time
import traceback
from pathlib import Path
from typing import Any

import hil.parallel.flights  # noqa: F401 - the requests' functions, loaded before "ready"
from hil.parallel import forked
from hil.parallel.files import LEASE_S, POLL_S, write_atomic


class Unauthentic(PermissionError):
    """A request without the rig's token (never unpickled)."""


def read_request(path: Path, token: str) -> tuple[Any, tuple[Any, ...]]:
    """(fn, args) of a request written under `token` (hil.parallel.files.write_request);
    Unauthentic, unread, otherwise."""
    line, _, body = path.read_bytes().partition(b"\n")
    if not hmac.compare_digest(line, token.encode()):
        raise Unauthentic(f"{path.name}: a request without the rig's token: refused")
    fn, args = pickle.loads(body)
    return fn, args


def _answer(req: Path, res_dir: Path, token: str) -> None:
    t0 = time.perf_counter()
    try:
        try:
            fn, args = read_request(req, token)
        finally:
            req.unlink()
        out: tuple[Any, ...] = ("ok", fn(*args), 0.0)
    except Exception as e:  # noqa: BLE001 - every failure goes back to the host
        try:
            pickle.dumps(e)
            err: BaseException = e
        except Exception:  # noqa: BLE001 - an exception that does not pickle: its text
            err = RuntimeError(f"{type(e).__name__}: {e}")
        print(traceback.format_exc(), file=sys.stderr, flush=True)
        out = ("error", err, 0.0)
        req.unlink(missing_ok=True)
    out = (out[0], out[1], time.perf_counter() - t0)
    write_atomic(res_dir / req.name, pickle.dumps(out, protocol=pickle.HIGHEST_PROTOCOL))


def serve(root: Path, lease_s: float = LEASE_S) -> int:
    req_dir, res_dir = root / "req", root / "res"
    lease = root / "lease"
    token = (root / "token").read_text().strip()
    write_atomic(root / "ready", f"{os.getpid()}\n".encode())
    last_lease, seen_at = None, time.monotonic()
    while not (root / "stop").exists():
        try:
            stamp = lease.stat().st_mtime_ns
        except OSError:
            return 0                                 # the host removed the rig directory
        if stamp != last_lease:
            last_lease, seen_at = stamp, time.monotonic()
        elif time.monotonic() - seen_at > lease_s:
            print(f"hil.parallel.server: lease not renewed for {lease_s:g} s, stopping",
                  file=sys.stderr, flush=True)
            return 0
        reqs = sorted(p for p in req_dir.glob("*.pkl"))
        if not reqs:
            time.sleep(POLL_S)
            continue
        for req in reqs:
            _answer(req, res_dir, token)
            forked.after_answer()
    return 0


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print("usage: python -m hil.parallel.server DIR", file=sys.stderr)
        return 2
    return serve(Path(args[0]))


if __name__ == "__main__":
    sys.exit(main())
