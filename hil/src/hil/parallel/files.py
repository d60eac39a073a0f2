"""The files between the host side of a worker's rig (hil.parallel.guest) and the loop inside
it (hil.parallel.server), in a directory both see:

    DIR/ready        written once the loop runs
    DIR/req/N.pkl    a request: pickled (function, args); taken and removed by the loop
    DIR/res/N.pkl    its answer: pickled ("ok", value, seconds) or ("error", exception, seconds)
    DIR/lease        touched by the host while it wants the rig; the loop ends when it has not
                     changed for LEASE_S (the host process was killed) or when DIR/stop appears

Files are written under a temporary name and renamed, so a reader never sees half of one.
"""
from __future__ import annotations

import os
from pathlib import Path

LEASE_S = 20.0
POLL_S = 0.01


def write_atomic(path: Path, data: bytes) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)
