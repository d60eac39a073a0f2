"""Deterministic random edits of suite files, for the tests that hil verify's loader never
raises anything but a one-line SuiteError (tests/python/verify)."""
from __future__ import annotations

import random
from collections.abc import Sequence
from pathlib import Path

from hil.verify import suite


def edit_and_load(texts: Sequence[str], tokens: Sequence[str], seed: int, path: Path,
                  edits: int = 300) -> dict[str, int]:
    """Each of `edits` copies of a text, with 1-3 tokens put in at random places, loaded from
    path: {"loaded": n, "refused": n}; any refusal must be one line naming the file."""
    rng = random.Random(seed)
    outcomes = {"loaded": 0, "refused": 0}
    for _ in range(edits):
        text = rng.choice(list(texts))
        for _ in range(rng.randrange(1, 4)):
            k = rng.randrange(len(text))
            text = text[:k] + rng.choice(list(tokens)) + text[k + rng.randrange(0, 4):]
        path.write_text(text)
        try:
            suite.load(path)
            outcomes["loaded"] += 1
        except suite.SuiteError as e:
            assert "\n" not in str(e) and str(e).startswith(str(path)), str(e)
            outcomes["refused"] += 1
    return outcomes
