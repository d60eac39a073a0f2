"""The symmetric filter comparison of a CDRW flight (summary.json's cdrw.tables): Table 4 with every filter's prior and
with every filter's posterior (`--rows prior|posterior`), next to the rows fcc flew with.

fcc runs one row mode on the bus (`hil run --rows`, default "paper": KF after y_k,
ZKF/AZKF before y_k, the paper's printed equations).  The other modes come from the
firmware's own code offline: the flight's sensor readings, at the resolution fcc decodes
them from their frames, replayed through `sid_replay --all-rows` with the same
identification options.  The replay in fcc's own mode is compared with fcc's rows
(`replay_check`: largest difference of the estimates and of the bounds, each against its
frame's resolution, and the steps whose fault flag differs; a faithful replay stays within one
resolution step and agrees on every flag: hil.results.trust judges it).
"""
from __future__ import annotations

import re
import subprocess
import tempfile
from collections.abc import Mapping, Sequence
from functools import lru_cache
from typing import Any

import numpy as np

from hil.bus.dbc import BusSpec
from hil.io.paths import tool
from hil.results import metrics
from hil.results.sidrows import ESTIMATES, ROW_MODES, read_binary_rows
from hil.sim.drivers import FILTERS, SID_PREFIX, SIGNAL_FRAMES
from hil.sim.sid_csv import sid_csv
from hil.util.processes import ProcessError
from hil.util.rounding import round_half_away_many

#: the two symmetric modes every CDRW summary carries (cdrw.tables)
SYMMETRIC = ("prior", "posterior")


@lru_cache(maxsize=1)
def _sid_option_names() -> frozenset[str]:
    """The identification options sid_replay and fcc share (fcc_opt_sid), from the usage."""
    r = subprocess.run([str(tool("sid_replay")), "--help"], capture_output=True, text=True,
                       timeout=60)
    text = r.stdout.split("identification options", 1)[-1]
    return frozenset(re.findall(r"(--[a-z0-9][a-z0-9-]*)", text))


#: the options hil.rig.flight.fcc_args writes besides --rows: none is an identification option,
#: so a command line of these alone needs no look at sid_replay's usage (a process start)
RIG_OPTIONS = frozenset({"--mode", "--apps", "--lqg-period", "--lqg-bits", "--lqg-delay",
                         "--gyro-var", "--accel-var", "--rt-priority"})


def sid_options(fcc_args: Sequence[str]) -> tuple[str, list[str]]:
    """(the row mode, the identification options) of an fcc command line: what a replay
    needs to run the same filters.  An option's value is the next word unless it starts
    with "--" (the options of fcc_opt_sid are `--name value` or flags)."""
    given = {a.partition("=")[0] for a in fcc_args if a.startswith("--")}
    names = frozenset({"--rows"}) if given <= RIG_OPTIONS | {"--rows"} else _sid_option_names()
    rows, out = "paper", []
    i = 0
    while i < len(fcc_args):
        a = fcc_args[i]
        name, eq, val = a.partition("=")
        has_next = i + 1 < len(fcc_args) and not fcc_args[i + 1].startswith("--")
        if name in names:
            if eq:
                value: str | None = val
            else:
                value = fcc_args[i + 1] if has_next else None
                i += 1 if has_next else 0
            if name == "--rows":
                rows = value or rows
            else:
                out += [name] + ([value] if value is not None else [])
        i += 1
    if rows not in ROW_MODES:
        raise ValueError(f"rows must be one of {', '.join(ROW_MODES)}, not {rows!r}")
    return rows, out


def _received(spec: BusSpec, sig: str, values: np.ndarray) -> np.ndarray:
    """The readings as fcc decodes them (NaN and infinities as they are): what
    float(s.to_phys(s.to_raw(v))) gives value by value, a column at a time (the same float
    operations: hil.util.rounding.round_half_away_many, then raw / inv_scale; every reading's
    signal is a scaled one)."""
    frame, name = SIGNAL_FRAMES[sig]
    s = next(x for x in spec.by_name(frame).signals if x.name == name)
    with np.errstate(invalid="ignore"):   # (NaN and infinities: given back as they are below)
        raw = round_half_away_many(values * s.inv_scale) + 0.0   # (+ 0.0: a 0 is unsigned)
    return np.where(np.isfinite(values), raw / s.inv_scale, values)


class Replay:
    """`sid_replay --all-rows --estimates --binary` on the flight's readings as fcc received
    them (one process for the three modes: starting one costs ~0.1 s in the guest; only the
    ESTIMATES columns, as binary64: no number formatted or parsed), running while the caller
    does other work; result() waits for it: {row mode: {filter: ESTIMATES columns}}."""

    def __init__(self, spec: BusSpec, series: Mapping[str, np.ndarray],
                 sid_args: Sequence[str] = ()) -> None:
        csv = sid_csv(series["t"].tolist(), _received(spec, "alpha", series["alpha_meas"]).tolist(),
                      _received(spec, "q", series["q_meas"]).tolist(),
                      _received(spec, "de", series["de_meas"]).tolist(),
                      [int(f) for f in series["fault"]])
        # files, not pipes: the output (~0.3 MB) would fill a pipe and stop sid_replay until read
        self._input, self._output = tempfile.TemporaryFile(), tempfile.TemporaryFile()  # noqa: SIM115 - closed by close()
        self._input.write(csv.encode("ascii"))
        self._input.seek(0)
        self.spec = spec
        self._proc = subprocess.Popen([str(tool("sid_replay")), "--all-rows", "--estimates", "--binary",
                                       *sid_args],
                                      stdin=self._input, stdout=self._output, stderr=subprocess.PIPE)

    def result(self) -> dict[str, dict[str, dict[str, np.ndarray]]]:
        try:
            _, err = self._proc.communicate(timeout=120)
            self._output.seek(0)
            data = self._output.read()
        finally:
            self._input.close()
            self._output.close()
        if self._proc.returncode != 0:
            msg = (err.decode(errors="replace").strip().splitlines() or ["no message"])[0]
            raise ProcessError(f"sid_replay --all-rows: exit {self._proc.returncode}: {msg}")
        out: dict[str, dict[str, dict[str, np.ndarray]]] = {m: {} for m in ROW_MODES}
        for name, cols in read_binary_rows(data, all_rows=True).items():
            mode, _, filt = name.partition("/")
            out[mode][filt] = cols
        return out


def mode_tables(series: Mapping[str, np.ndarray], est: Mapping[str, Mapping[str, np.ndarray]],
                dt: float) -> dict[str, Any]:
    """Table 4 (vs the fault-free measurement and vs the truth) and the bounds coverage of
    one row mode; est[filter] has alpha_hat, q_hat, alpha_lo, alpha_hi, q_lo, q_hi."""
    y_ff = np.column_stack([series["alpha_ff"], series["q_ff"]])
    truth = np.column_stack([series["alpha_true"], series["q_true"]])
    xh = {f: np.column_stack([est[f]["alpha_hat"], est[f]["q_hat"]]) for f in FILTERS if f in est}
    table, _ = metrics.error_table(y_ff, xh, dt)
    table_truth, _ = metrics.error_table(truth, xh, dt)
    bounds = {f: (np.column_stack([est[f]["alpha_lo"], est[f]["q_lo"]]),
                  np.column_stack([est[f]["alpha_hi"], est[f]["q_hi"]])) for f in xh}
    return {"table4": table, "table4_truth": table_truth,
            "coverage": metrics.coverage_table(truth, bounds),
            "improvement_over_kf_pct": metrics.improvements(table),
            "improvement_over_kf_truth_pct": metrics.improvements(table_truth)}


def fcc_rows(series: Mapping[str, np.ndarray]) -> dict[str, dict[str, np.ndarray]]:
    """fcc's own rows of a flight (the run's series) in Replay.result()'s layout."""
    return {f: {c: np.asarray(series[f"{f}_{c}"]) for c in ESTIMATES} for f in FILTERS}


def symmetric_tables(series: Mapping[str, np.ndarray], dt: float, flown: str,
                     replay: Replay) -> tuple[dict[str, Any], dict[str, str | float]]:
    """({mode: mode_tables} for prior and posterior, replay_check), from the Replay of this
    flight (started by the caller, so that it runs while the caller works on).  The mode fcc
    flew (sid_options) is taken from fcc's rows; the others from the replay.  replay_check:
    the largest |replay - fcc| of the estimates in fcc's own mode (NaN rows left out).  When
    sid_replay refuses the flight (e.g. shorter than the MLS window) the tables are empty
    and replay_check says why ("not_computed")."""
    tables: dict[str, Any] = {}
    try:
        replays = replay.result()
    except RuntimeError as e:
        return {}, {"rows": flown, "not_computed": str(e)}
    for mode in SYMMETRIC:
        est = fcc_rows(series) if mode == flown else replays[mode]
        tables[mode] = mode_tables(series, est, dt)
    return tables, {"rows": flown, **cross_check(replay.spec, replays[flown], series)}


#: the replay_check's columns: the estimates, the bounds (each against its frame's signal)
CHECKED = {"estimate": ("STATE", ("alpha_hat", "q_hat")),
           "bound": ("BOUNDS", ("alpha_lo", "alpha_hi", "q_lo", "q_hi"))}


def cross_check(spec: BusSpec, replay: Mapping[str, Mapping[str, np.ndarray]],
                series: Mapping[str, np.ndarray]) -> dict[str, Any]:
    """fcc's rows (series) against sid_replay's in the same mode on the same readings: the
    largest |replay - fcc| of the estimates and of the bounds (the replay saturated to the
    frame's range as fcc's encoder does; steps without fcc's frame left out), the resolution of
    each (`resolution`), and the steps at which fcc's fault flag (every filter's row carries
    the AZKF detector's) differs from the replay's AZKF detector."""
    out: dict[str, Any] = {"resolution": {}}
    for kind, (part, cols) in CHECKED.items():
        worst = 0.0
        for f in FILTERS:
            msg = spec.by_name(f"{SID_PREFIX[f]}_{part}")
            for c in cols:
                sig = next(x for x in msg.signals if x.name == c)
                lo, hi = sig.raw_min / sig.inv_scale, sig.raw_max / sig.inv_scale
                ours = np.asarray(series[f"{f}_{c}"], float)
                theirs = np.clip(np.asarray(replay[f][c], float)[: len(ours)], lo, hi)
                d = np.abs(theirs - ours[: len(theirs)])
                if np.any(np.isfinite(d)):
                    worst = max(worst, float(np.nanmax(d)))
                out["resolution"][kind] = 1.0 / sig.inv_scale
        out[f"max_abs_{kind}_difference"] = worst
    detector = np.asarray(replay["azkf"]["fault"], float)
    mismatched = np.zeros(len(detector), bool)
    for f in FILTERS:
        flag = np.asarray(series[f"{f}_fault"], float)[: len(detector)]
        mismatched[: len(flag)] |= np.isfinite(flag) & (flag != detector[: len(flag)])
    out["fault_flag_mismatches"] = int(np.count_nonzero(mismatched))
    return out
