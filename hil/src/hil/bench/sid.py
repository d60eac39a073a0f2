"""Time one identification step of the numpy reference (scripts/bench.d/sid).

    python -m hil.bench.sid [STEPS]

Prints "SCENARIO US_PER_STEP" for the scenarios of sid_bench: the step is
MLS update + filter step on the synthetic flight, after the same warm-up
(normal flight; the 0.1 s spike window; a fault held by the oracle until the
generator matrix is at its largest, p = 1004).
"""
from __future__ import annotations

import argparse
import time
from collections.abc import Callable, Sequence

import numpy as np

from hil.reference.flight import synthetic_flight
from hil.reference.mls import Mls
from hil.reference.sid import SidConfig, SidLoop
from hil.reference.zkf import AzkfConfig, DetectorConfig

SCENARIOS = ("mls", "mls-kf", "mls-zkf", "mls-azkf", "mls-azkf-spike", "mls-azkf-worst")


def _flight(n: int, fault_time: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    f = synthetic_flight(duration=0.02 * (n - 1), fault_time=fault_time)
    return f.x, f.y, f.de, f.fault


def time_scenario(name: str, steps: int) -> float:
    """Microseconds per measured step."""
    warmup = 200 if name == "mls-azkf-spike" else 300
    steps = min(steps, 20) if name == "mls-azkf-spike" else steps
    n = warmup + steps + 1
    x, y, de, fault = _flight(n, 4.0 if name == "mls-azkf-spike" else 1e9)
    step: Callable[[int], object]  # what a step returns is not measured
    if name == "mls":
        mls = Mls()
        step = lambda k: mls.update(x[k - 1], de[k - 1], x[k])  # noqa: E731
    else:
        kind = name.split("-")[1]
        cfg = SidConfig()
        held = name == "mls-azkf-worst"
        if held:
            cfg.azkf = AzkfConfig(det=DetectorConfig(mode="oracle"))
        loop = SidLoop(kind, cfg)
        step = lambda k: loop.step(y[k], de[k], held or bool(fault[k]))  # noqa: E731
    for k in range(1, warmup + 1):
        step(k)
    t0 = time.perf_counter()
    for k in range(warmup + 1, n):
        step(k)
    return (time.perf_counter() - t0) / steps * 1e6


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m hil.bench.sid", description=__doc__.splitlines()[0])
    p.add_argument("steps", nargs="?", type=int, default=300, help="measured steps (default 300)")
    steps = p.parse_args(argv).steps
    for name in SCENARIOS:
        print(f"{name} {time_scenario(name, steps):.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
