"""Bounded reads of the files a user names (key file, scenario, summaries): never more than a
limit, so /dev/zero or a huge file is one clear line, not a hang or an exhausted memory."""
from __future__ import annotations

from pathlib import Path


class TooLarge(ValueError):
    """A file larger than its kind can be (one line for the user)."""


def read_bounded(path: str | Path, limit: int, what: str) -> bytes:
    """At most `limit` bytes of the file; TooLarge when it has more (OSError as open raises)."""
    with open(path, "rb") as fh:
        data = fh.read(limit + 1)
    if len(data) > limit:
        raise TooLarge(f"{path}: larger than a {what} can be ({limit} bytes at most)")
    return data
