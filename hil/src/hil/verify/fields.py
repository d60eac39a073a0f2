"""The result fields an expectation may name: each documented, each read from what a flight
wrote (summary.json, run_info.json, cdrw.csv) or from the case's attacker.

A field belongs to a source: "cdrw" or "missile" (the case must fly that aircraft), "node"
(any flight: fcc's counters), "attack" (the case must have an attack).  A name that is not
here, or whose source the case does not have, is refused when the suite is loaded.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from hil.io.output import read_csv

NEVER = math.inf   # a step that never came (no fault, no flag): every "<=" on it fails


@dataclass(frozen=True)
class Field:
    name: str
    source: str
    doc: str
    read: Callable[[Mapping[str, Any]], float]


def _at(*path: str) -> Callable[[Mapping[str, Any]], float]:
    def read(run: Mapping[str, Any]) -> float:
        v: Any = run
        for p in path:
            v = v[int(p)] if isinstance(v, list) else v[p]
        return float(v)
    return read


FIELDS: dict[str, Field] = {}


def _add(name: str, source: str, doc: str, read: Callable[[Mapping[str, Any]], float]) -> None:
    FIELDS[name] = Field(name, source, doc, read)


# ---- fcc as a node on the bus (any flight) --------------------------------------------------
_add("overruns", "node", "steps fcc could not finish within the period", _at("summary", "firmware", "overruns"))
_add("heartbeats", "node", "authenticated FCC_STATUS heartbeats the rig received", _at("info", "heartbeats"))
_add("worst_step_us", "node", "fcc's longest step execution (us, its own clock)", _at("info", "worst_step_us"))
for _k in ("ok", "repeated", "ok_some_lost", "wrong_sequence", "error", "no_new_data"):
    _add(f"e2e.{_k}", "node", f"fcc's E2E verdicts {_k!r} on sensor frames", _at("summary", "firmware", "e2e", _k))
for _k in ("unknown_id", "wrong_dlc", "out_of_range", "tx_refused"):
    _add(f"rejected.{_k}", "node", f"frames fcc rejected: {_k}", _at("summary", "firmware", "rejected", _k))
for _k, _src in (("mac", "mac_failed"), ("freshness", "freshness_failed"), ("unpaired", "unpaired"),
                 ("mode", "mode_refused")):
    _add(f"refused.{_k}", "node", f"secured frames fcc refused ({_src})",
         _at("summary", "firmware", "security", "fcc", _src))
for _k, _src in (("mac", "mac_failed"), ("freshness", "freshness_failed"), ("unpaired", "unpaired")):
    _add(f"rig_refused.{_k}", "node", f"secured frames from fcc the rig refused ({_src})",
         _at("summary", "firmware", "security", "rig", _src))
_add("bus_trust.ok", "node", "1 if fcc's outputs were authentic (summary.json's bus_trust: nothing forged on its "
     "identifiers, no frame on them fcc did not send, the reference cross-check held where it applies); a case "
     "that names no bus_trust field must have it (hil.verify.runner)",
     lambda run: float((run["summary"].get("bus_trust") or {}).get("verdict") == "ok"))
_add("bus_trust.forged_frames", "node", "frames and authenticators forged on fcc's outputs the rig refused "
     "(bus_trust.forged: refused + conflicting copies)", lambda run: float(sum(
         sum(v.values()) for v in run["summary"]["bus_trust"]["forged"].values())))
_add("bus_trust.own_id", "node", "frames on fcc's own identifiers fcc counted (another node sent as fcc)",
     lambda run: float(run["summary"]["bus_trust"]["own_id"] or 0))
_add("bus.errors", "node", "CAN error frames fcc saw", _at("summary", "firmware", "bus", "bus_errors"))
_add("bus.rx_overflows", "node", "receive queue overflows in fcc", _at("summary", "firmware", "bus", "rx_overflows"))

# ---- the CDRW identification (seed 1) -------------------------------------------------------
_add("steps.cdrw", "cdrw", "CDRW steps fcc reported", _at("summary", "firmware", "steps", "cdrw"))
_add("cdrw.steps", "cdrw", "CDRW steps the simulator flew", _at("summary", "cdrw", "flight", "steps"))
for _k in ("missing_steps", "unanswered_steps", "degraded_steps"):
    _add(f"cdrw.{_k}", "cdrw", f"CDRW {_k.replace('_', ' ')}", _at("summary", "cdrw", "flight", _k))
for _f in ("azkf", "zkf", "kf"):
    for _s in ("alpha", "q"):
        _add(f"{_f}.{_s}.error_integral", "cdrw",
             f"{_f.upper()}: integral |y_faultfree - y_hat| dt of {_s} (Table 4, the rows fcc flew)",
             _at("summary", "cdrw", "table4", _f, _s))
        _add(f"{_f}.{_s}.error_integral_truth", "cdrw",
             f"{_f.upper()}: integral |x_true - x_hat| dt of {_s}", _at("summary", "cdrw", "table4_truth", _f, _s))
        _add(f"{_f}.{_s}.coverage", "cdrw", f"{_f.upper()}: share of steps with the true {_s} inside the bounds",
             _at("summary", "cdrw", "coverage", _f, _s))
_add("replay.max_difference", "cdrw", "largest difference between fcc's estimates and sid_replay's on the "
     "same readings", _at("summary", "cdrw", "replay_check", "max_abs_estimate_difference"))
_add("fault.start_step", "cdrw", "first step with the true fault active (inf: no fault)", _at("derived", "fault_start"))
_add("detector.first_flag_step", "cdrw", "first step fcc's AZKF flagged a fault (inf: never)",
     _at("derived", "first_flag"))
_add("detector.latency_steps", "cdrw", "steps from the fault's start to the first flag at or after it "
     "(inf: not flagged)", _at("derived", "latency"))
_add("detector.false_alarm_steps", "cdrw", "flagged steps more than 10 steps after any true-fault step "
     "and before the fault", _at("derived", "false_alarms"))
_add("detector.flagged_steps", "cdrw", "steps the AZKF flagged", _at("derived", "flagged"))

# ---- the missile autopilot (seed 2) ---------------------------------------------------------
_add("steps.missile", "missile", "missile steps fcc reported", _at("summary", "firmware", "steps", "missile"))
for _k in ("rms_q", "rms_alpha"):
    _add(f"missile.{_k}", "missile", f"closed loop through fcc: RMS of {_k[4:]}",
         _at("summary", "missile", "runs", "0", _k))
    _add(f"open_loop.{_k}", "missile", f"open loop, same gusts and noise: RMS of {_k[4:]}",
         _at("summary", "missile", "runs", "1", _k))
    _add(f"reference.{_k}", "missile", f"the scipy LQG reference on the same gusts: RMS of {_k[4:]}",
         _at("summary", "missile", "runs", "0", "reference", _k))
    _add(f"stationary.{_k}", "missile", f"covariance analysis, stationary RMS of {_k[4:]}",
         _at("summary", "missile", "runs", "0", "stationary", _k))
_add("dac_codes_equal_reference", "missile", "share of steps whose D/A code equals the reference design's",
     _at("summary", "missile", "runs", "0", "reference", "code_agreement"))
for _k in ("commands_missing", "commands_late", "commands_rejected", "unanswered_steps"):
    _add(_k if _k.startswith("commands") else f"missile.{_k}", "missile", f"missile {_k.replace('_', ' ')}",
         _at("summary", "missile", "runs", "0", _k))

# ---- a realtime flight's timing (mode = "realtime", the missile: hil.results.timing) -----------
def _rt(*path: str) -> Callable[[Mapping[str, Any]], float]:
    """A timing percentile; one with no sample (n = 0: null), or one the target does not report
    (a device whose log has no such summary line), is inf, which no bound holds."""
    read = _at("summary", "realtime", *path)

    def get(run: Mapping[str, Any]) -> float:
        try:
            return read(run)
        except (TypeError, KeyError):
            return NEVER
    return get


for _p in ("p50", "p99", "max"):
    _add(f"realtime.latency_{_p}_us", "realtime", f"sensor to command in fcc, its own clock ({_p}, us)",
         _rt("fcc", "latency_us missile", _p))
    _add(f"realtime.cmd_delay_{_p}_us", "realtime", f"sampling instant to the command on the bus, master "
         f"time ({_p}, us)", _rt("bus", "cmd_delay", _p))
    _add(f"realtime.data_age_{_p}_us", "realtime", f"age of the newest sensor frame when the command "
         f"went out, on the bus ({_p}, us)", _rt("bus", "data_age", _p))
    _add(f"realtime.sim_jitter_{_p}_us", "realtime", f"|sensor frame - its sampling instant| on the bus, "
         f"master time ({_p}, us)", _rt("bus", "sim_jitter", _p))
    _add(f"realtime.sync_offset_{_p}_us", "realtime",
         f"|fcc's sync residual| in its heartbeats while LOCKED ({_p}, us)", _rt("bus", "sync_offset", _p))
_add("realtime.period_us", "realtime", "the missile's step period (us): the deadline of a step",
     lambda run: 1e6 * float(run["summary"]["missile"]["runs"][0]["period"]))
_add("realtime.delay_us", "realtime", "the missile's actuation instant after its sampling instant (us): "
     "the delay fcc's LQG is designed for (the target's in realtime: hil.rig.flight.on_target)",
     lambda run: 1e6 * float(run["summary"]["realtime"]["delay_s"]))
_add("realtime.late_steps", "realtime", "steps the simulator sent after their instant",
     _at("summary", "realtime", "simulator", "late_steps"))
_add("realtime.late_frames", "realtime", "sensor frames the simulator's transmitter sent late",
     _at("summary", "realtime", "simulator", "transmitter", "late"))

# ---- a realtime flight's time synchronisation (hil.results.sync: `hil run` exits 7 unless ok) ----
for _k in ("mac_failed", "freshness_failed", "unauthenticated", "step_refused", "rate_refused"):
    _add(f"sync.refused.{_k}", "sync", f"fcc's FCC_SYNC_REFUSALS.{_k} at its last heartbeat",
         _at("summary", "sync", "refused", _k))
_add("sync.losses", "sync", "times fcc lost the sync (FCC_SYNC_STATUS.losses)", _at("summary", "sync", "losses"))
_add("sync.rejected", "sync", "sync pairs fcc rejected (FCC_SYNC_STATUS.rejected)", _at("summary", "sync", "rejected"))
_add("sync.master_unpaired_frames", "sync", "the rig's master's frames no TSYNC_AUTH covered (a SYNC whose "
     "echo never came)", _at("summary", "sync", "master_unpaired_frames"))
_add("sync.forged_frames", "sync", "SYNC/FOLLOW_UP frames fcc refused unauthenticated beyond the master's "
     "unpaired ones: forged", lambda run: float(max(0, run["summary"]["sync"]["refused"]["unauthenticated"]
                                                      - run["summary"]["sync"]["master_unpaired_frames"])))
_add("sync.locked", "sync", "1 if fcc was LOCKED at its last heartbeat", lambda run: float(
    run["summary"]["sync"]["state"] == "LOCKED"))
def _verdict(v: str) -> Callable[[Mapping[str, Any]], float]:
    return lambda run: float(run["summary"]["sync"]["verdict"] == v)


for _v in ("ok", "attacked", "refused", "lost"):
    _add(f"sync.verdict.{_v}", "sync", f"1 if the run's sync verdict is {_v!r} (`hil run` exits 7 unless ok)",
         _verdict(_v))

# ---- the case's attacker ----------------------------------------------------------------------
_add("attack.forged", "attack", "forged frames the attacker put on the bus", _at("attack", "forged"))


def _detector(csv_path: Path) -> dict[str, float]:
    """Fault truth and the AZKF's flags per step, from cdrw.csv."""
    cols = read_csv(csv_path)
    truth = [bool(v) for v in cols["fault"]]
    flags = [bool(v) for v in cols["azkf_fault"]]
    start = next((k for k, v in enumerate(truth) if v), None)
    first = next((k for k, v in enumerate(flags) if v), None)
    after = next((k for k, v in enumerate(flags) if v and start is not None and k >= start), None)
    last_truth = -10**9
    false_alarms = 0
    for k, (t, f) in enumerate(zip(truth, flags)):
        if t:
            last_truth = k
        elif f and k - last_truth > 10:
            false_alarms += 1
    return {"fault_start": NEVER if start is None else start,
            "first_flag": NEVER if first is None else first,
            "latency": NEVER if after is None or start is None else after - start,
            "false_alarms": false_alarms, "flagged": sum(flags)}


def read_run(run_dir: Path, summary: Mapping[str, Any], info: Mapping[str, Any],
             attack: Mapping[str, float] | None) -> dict[str, Any]:
    """Everything a field reads, for one flight."""
    csv_path = run_dir / "cdrw.csv"
    return {"summary": summary, "info": info, "attack": attack or {},
            "derived": _detector(csv_path) if csv_path.is_file() else {}}


def values(run: Mapping[str, Any], names: set[str] | frozenset[str]) -> dict[str, float]:
    return {n: FIELDS[n].read(run) for n in names}


def describe() -> str:
    """The field list `hil verify --fields` prints."""
    w = max(map(len, FIELDS))
    return "\n".join(f"{f.name:<{w}}  [{f.source}]  {f.doc}" for f in FIELDS.values())
