"""Hand-written or a well-kept library? hil's own code beside the library that could replace it,
each pair checked for the same answers first and then timed side by side in one run (timeit,
best of REPEAT): docs/decisions.md keeps the numbers and what was decided.

    .venv/bin/python scripts/lib/library_choices.py [--quick]

1. scenario validation: hil.scenario (tomllib + hil.scenario.schema) against msgspec and
   pydantic models of the same file (a subset: the top level and its three fault kinds, each
   with its bounds; the real schema has 18 kinds, plant and sensor tables);
2. frame packing: hil.bus.dbc (MessageSpec.encode_raw/decode_raw) against cantools'
   Message.encode/decode (scaling off), one CDRW_AOA frame;
3. candump -L parsing: hil.bus.candump.read_log against python-can's CanutilsLogReader;
4. CRC-8 SAE J1850: hil.bus.e2e against crccheck's Crc8SaeJ1850, on 8-byte frames;
5. the 95 % percentile bootstrap of Table 5's improvement over the KF:
   hil.reference.cdrw_controls.bootstrap against scipy.stats.bootstrap (paired, percentile).

Also what each library would add to a command before it does anything: its import time in a
fresh interpreter that has imported hil.cli (the median of IMPORT_RUNS).  A library missing from
the environment is skipped and said so (pydantic and msgspec are no dependency of hil).
"""

import importlib.util
import statistics
import subprocess
import sys
import tempfile
import timeit
from collections.abc import Callable
from pathlib import Path

import numpy as np

from hil.bus import dbc
from hil.bus.candump import format_line, read_log
from hil.bus.e2e import crc8_j1850
from hil.io import paths
from hil.reference.cdrw_controls import bootstrap
from hil.scenario.file import load_scenario

REPEAT = 5
IMPORT_RUNS = 7
SCENARIO = paths.SCENARIOS / "cdrw_multi_fault.toml"


def best_us(fn: Callable[[], object], number: int) -> float:
    """The best of REPEAT timings of `number` calls, per call, in microseconds."""
    return min(timeit.repeat(fn, number=number, repeat=REPEAT)) / number * 1e6


def have(module: str) -> bool:
    return importlib.util.find_spec(module) is not None


def import_ms(module: str) -> float:
    """What importing module adds to a `hil` command: a fresh interpreter that has imported
    hil.cli (and with it typing, dataclasses, tomllib ...) times the import (median)."""
    def run() -> float:
        out = subprocess.run([sys.executable, "-c", "import hil.cli, time; t = time.perf_counter(); "
                              f"import {module}; print(time.perf_counter() - t)"],
                             capture_output=True, text=True, check=True)
        return float(out.stdout)
    return statistics.median(run() for _ in range(IMPORT_RUNS)) * 1e3


# ---- 1. scenario validation ------------------------------------------------------------------
def validators() -> dict[str, Callable[[], object]]:
    import tomllib
    text = SCENARIO.read_text(encoding="utf-8")
    frames = {m.name for m in dbc.load().messages}
    out: dict[str, Callable[[], object]] = {"hil.scenario": lambda: load_scenario(SCENARIO, frames)}
    if have("msgspec"):
        import msgspec
        from typing import Annotated, Literal

        Pos = Annotated[float, msgspec.Meta(gt=0)]
        NonNeg = Annotated[float, msgspec.Meta(ge=0)]
        Prob = Annotated[float, msgspec.Meta(gt=0, le=1)]

        class MSpike(msgspec.Struct, tag_field="kind", tag="spike", forbid_unknown_fields=True):
            signal: Literal["alpha", "q", "de"]
            start: NonNeg
            duration: Pos
            magnitude: float

        class MLoss(msgspec.Struct, tag_field="kind", tag="loss", forbid_unknown_fields=True):
            frame: str
            start: NonNeg
            duration: Pos
            probability: Prob = 1.0

        class MBadCrc(msgspec.Struct, tag_field="kind", tag="bad_crc", forbid_unknown_fields=True):
            frame: str
            start: NonNeg
            duration: Pos
            probability: Prob = 1.0

        class MScenario(msgspec.Struct, forbid_unknown_fields=True):
            aircraft: Literal["cdrw", "missile"]
            name: str = ""
            description: str = ""
            duration: Pos = 7.0
            seed: Annotated[int, msgspec.Meta(ge=0)] = 1
            faults: list[MSpike | MLoss | MBadCrc] = []

        out["msgspec"] = lambda: msgspec.toml.decode(SCENARIO.read_bytes(), type=MScenario) \
            if hasattr(msgspec, "toml") else msgspec.convert(tomllib.loads(text), MScenario)
    if have("pydantic"):
        from typing import Annotated, Literal

        import pydantic

        strict = pydantic.ConfigDict(extra="forbid", frozen=True)

        class PSpike(pydantic.BaseModel):
            model_config = strict
            kind: Literal["spike"]
            signal: Literal["alpha", "q", "de"]
            start: Annotated[float, pydantic.Field(ge=0)]
            duration: Annotated[float, pydantic.Field(gt=0)]
            magnitude: float

        class PFrame(pydantic.BaseModel):
            model_config = strict
            kind: Literal["loss", "bad_crc"]
            frame: str
            start: Annotated[float, pydantic.Field(ge=0)]
            duration: Annotated[float, pydantic.Field(gt=0)]
            probability: Annotated[float, pydantic.Field(gt=0, le=1)] = 1.0

        class PScenario(pydantic.BaseModel):
            model_config = strict
            aircraft: Literal["cdrw", "missile"]
            name: str = ""
            description: str = ""
            duration: Annotated[float, pydantic.Field(gt=0)] = 7.0
            seed: Annotated[int, pydantic.Field(ge=0)] = 1
            faults: list[Annotated[PSpike | PFrame, pydantic.Field(discriminator="kind")]] = []

        out["pydantic"] = lambda: PScenario.model_validate(tomllib.loads(text))
    return out


# ---- 2. frame packing -------------------------------------------------------------------------
def packers() -> tuple[dict[str, Callable[[], object]], bool]:
    import cantools
    spec = dbc.load().by_name("CDRW_AOA")
    raw = {s.name: 1 for s in spec.signals}
    frame = spec.encode_raw(raw)
    msg = cantools.database.load_file(str(dbc.default_path())).get_message_by_name("CDRW_AOA")
    same = (msg.encode(raw, scaling=False, strict=False) == frame
            and msg.decode(frame, scaling=False) == spec.decode_raw(frame))
    return {"hil.bus.dbc": lambda: spec.decode_raw(spec.encode_raw(raw)),
            "cantools": lambda: msg.decode(msg.encode(raw, scaling=False, strict=False), scaling=False)}, same


# ---- 3. candump -L parsing --------------------------------------------------------------------
def candump_log(directory: Path, lines: int) -> Path:
    rng = np.random.default_rng(1)
    log = directory / "bus.log"
    log.write_text("".join(format_line(1e-3 * k, "vcan0", int(rng.integers(0, 0x7FF)),
                                       rng.integers(0, 256, 8, dtype=np.uint8).tobytes()) + "\n"
                           for k in range(lines)))
    return log


def readers(log: Path) -> tuple[dict[str, Callable[[], object]], bool]:
    import can
    ours = [(f.timestamp, f.frame_id, f.data) for f in read_log(log)]
    theirs = [(m.timestamp, m.arbitration_id, bytes(m.data)) for m in can.CanutilsLogReader(str(log))]
    return {"hil.bus.candump": lambda: sum(1 for _ in read_log(log)),
            "python-can": lambda: sum(1 for _ in can.CanutilsLogReader(str(log)))}, ours == theirs


# ---- 4. CRC-8 -------------------------------------------------------------------------------
def crcs(frames: list[bytes]) -> tuple[dict[str, Callable[[], object]], bool]:
    from crccheck.crc import Crc8SaeJ1850
    same = all(crc8_j1850(f) == Crc8SaeJ1850.calc(f) for f in frames)
    return {"hil.bus.e2e": lambda: [crc8_j1850(f) for f in frames],
            "crccheck": lambda: [Crc8SaeJ1850.calc(f) for f in frames]}, same


# ---- 5. bootstrap -----------------------------------------------------------------------------
def bootstraps(n_boot: int) -> tuple[dict[str, Callable[[], object]], tuple[np.ndarray, np.ndarray]]:
    from scipy import stats
    rng = np.random.default_rng(3)
    kf = rng.uniform(0.1, 0.2, (12, 2))          # 12 flights' error integrals (alpha, q)
    azkf = kf * rng.uniform(0.3, 0.9, (12, 2))

    def theirs() -> tuple[np.ndarray, np.ndarray]:
        r = stats.bootstrap((azkf, kf), lambda e, b, axis: 100.0 * (1.0 - e.mean(axis) / b.mean(axis)),
                            paired=True, vectorized=True, method="percentile", n_resamples=n_boot,
                            axis=0, random_state=np.random.default_rng(0))
        return r.confidence_interval.low, r.confidence_interval.high
    ours = bootstrap(azkf, kf, n_boot=n_boot)
    lo, hi = theirs()
    return {"hil.reference": lambda: bootstrap(azkf, kf, n_boot=n_boot), "scipy.stats": theirs}, \
        (np.max(np.abs(np.concatenate([ours[0] - lo, ours[1] - hi]))), np.asarray(hi - lo))


def table(title: str, timings: dict[str, float], unit: str, note: str = "") -> None:
    base = next(iter(timings.values()))
    print(f"{title}{f'  ({note})' if note else ''}")
    for name, t in timings.items():
        print(f"  {name:<18} {t:10.2f} {unit}  x{t / base:5.2f}")


def main(quick: bool = False) -> None:
    k = 10 if quick else 1
    v = validators()
    table("1. scenario validation, cdrw_multi_fault.toml, per load", {n: best_us(f, 400 // k) for n, f in v.items()},
          "us", "msgspec, pydantic: a subset of the schema" +
          "".join(f"; {m} not installed" for m in ("msgspec", "pydantic") if not have(m)))
    p, same = packers()
    table("2. frame packing, CDRW_AOA encode + decode, per frame", {n: best_us(f, 20000 // k) for n, f in p.items()},
          "us", f"same bytes and raw values: {same}")
    with tempfile.TemporaryDirectory() as d:
        log = candump_log(Path(d), 20000 // k)
        r, same = readers(log)
        table(f"3. candump -L parsing, {20000 // k} lines, per line",
              {n: best_us(f, 1) / (20000 // k) for n, f in r.items()}, "us", f"same frames: {same}")
    frames = [np.random.default_rng(i).integers(0, 256, 8, dtype=np.uint8).tobytes() for i in range(1000)]
    c, same = crcs(frames)
    table("4. CRC-8 SAE J1850, 8-byte frames, per frame",
          {n: best_us(f, 20 // k or 1) / len(frames) for n, f in c.items()}, "us", f"same CRCs: {same}")
    b, (diff, width) = bootstraps(2000)
    table("5. bootstrap, 12 flights x 2 states, 2000 resamples, per interval",
          {n: best_us(f, 20 // k or 1) for n, f in b.items()}, "us",
          f"largest bound difference {diff:.2f} points in intervals {width.min():.1f}-{width.max():.1f} wide")
    print(f"import time added to `hil` (after hil.cli), median of {IMPORT_RUNS}")
    for module in ("hil.scenario.file", "msgspec", "pydantic", "cantools", "can", "crccheck.crc", "scipy.stats"):
        if have(module.split(".")[0]):
            print(f"  {module:<18} {import_ms(module):8.1f} ms")


if __name__ == "__main__":
    main("--quick" in sys.argv[1:])
