"""summary.json's `bus` section of a `--bus wire` run: canbus's statistics (firmware/tools/canbus)
per frame name, each cyclic frame's worst-case response time (hil.bus.wcrt, Davis et al. 2007,
at the run's bit rate and the scenario's periods), and the run's check, measured ≤ bound.

The response times are the model's (canbus: queued at the sender's controller → the model's
end of frame), not when canbus's process delivered the frame: in the UML guest that delivery
is late by up to tens of milliseconds on a loaded host (`delivery_error`, reported apart), which
is the platform, not the bus.  Every cyclic frame is judged: the simulator's and the background
nodes' by Davis et al. 2007 (priority-ordered mailboxes), fcc's, which wait in one FIFO (a
SocketCAN node: hil.rig.wirebus.NODES), by hil.bus.wcrt's FIFO derivation; a FIFO frame above
its bound fails the run like any other.

The bound assumes each frame is queued on its period's grid, late by at most its queuing jitter
J.  `wcrt_s` is the issue's bound, J = 0.  The realtime simulator queues its frames late when the
host does not run it on time (its transmitter's send lateness: 0.1-2.4 s at most on a host at
load 10, measured; several instances of a frame then go out at once), which the J = 0 bound
does not cover: a frame above it but within `wcrt_jitter_s`, the bound with J = that run's
largest send lateness for every frame (as `hil bus wcrt --jitter`), is said so and does not
fail the run; above that too, it does.  fcc's own release jitter is not measured per frame:
fcc answers the simulator's frames, so its frames take the same J (their loose bound is the
whole analysis's, fcc's FIFO bounding the frames below its own).

With wire faults (hil.rig.wirefaults: error frames, a babbling node, a forced bus-off) the
analysis, which knows neither errors nor frames outside the DBC, bounds nothing: a frame above
its bound is said so (`above, with bus faults`) and does not fail the run.  The section's
`nodes` are each node's fault confinement as canbus modelled it: TEC and REC maxima, errors,
error frames written to it, error-passive and bus-off episodes, each bus-off's recovery time.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from hil.bus.dbc import BusSpec
from hil.bus.wcrt import (Frame, analyse, application_periods, cyclic_frames, frame_time, seconds, utilisation,
                          with_jitter, with_periods)
from hil.rig.wirebus import FIFO_SENDERS
from hil.scenario.file import Scenario
from hil.scenario.plant_options import CdrwPlantOptions

#: a frame's verdict: within its bound / above it (fails the run) / the analysis has no bound
#: (utilisation of the frames it waits for ≥ 1) / not cyclic /
#: above it while canbus fell behind the bus (`late_queued` > 0: a frame it read after an
#: arbitration it should have joined keeps its queue time, so its response time counts canbus's
#: own lateness; fails the run too, as not the model's)
WITHIN, ABOVE, UNBOUNDED, EVENT = "within", "above", "unbounded", "not cyclic"
LATE = "above, canbus late"
#: above the J = 0 bound, within the bound with the measured release jitter (does not fail)
JITTER = "within, with the release jitter"
#: above the bound on a bus with wire faults (error frames, a babbler: not in the analysis)
FAULTED = "above, with bus faults"
#: a node's fault confinement in canbus's statistics, as the section keeps it
_CONFINEMENT = ("sent", "tec_max", "rec_max", "tx_errors", "rx_errors", "error_frames", "error_passive",
                "bus_off", "bus_off_dropped", "recovery_s")
_PERCENTILES = ("p50_s", "p99_s", "max_s")


def step_period(sc: Scenario) -> float:
    """The period the scenario's aircraft steps at: the missile's [lqg] period, the CDRW's dt."""
    if sc.lqg is not None:
        return sc.lqg.period
    assert isinstance(sc.plant, CdrwPlantOptions)
    return sc.plant.dt


def flight_frames(spec: BusSpec, scenarios: Sequence[Scenario]) -> list[Frame]:
    """The DBC's cyclic frames at the flight's periods (a frame two aircraft share, the
    lockstep ones, at the shorter)."""
    frames = cyclic_frames(spec)
    periods: dict[str, Fraction] = {}
    for sc in scenarios:
        for name, p in application_periods(frames, sc.aircraft, seconds(step_period(sc))).items():
            periods[name] = min(p, periods.get(name, p))
    return with_periods(frames, periods)


def jitter_bound(frames: Sequence[Frame], frame_id: int, bitrate: int, jitter_s: float,
                 fifo: Sequence[str] = ()) -> Fraction | None:
    """One frame's bound with every frame's queuing jitter = jitter_s.  A priority-queued frame
    with no FIFO frame above it is analysed on what its bound depends on only -- the frames
    above it, it, and the longest below (the blocking) -- since with seconds of jitter the
    whole DBC's analysis takes minutes near U = 1 (measured: 17 s at 125 kbit/s with J = 0.5
    s); a FIFO's frame, or one below a FIFO frame, on them all."""
    m = next(f for f in frames if f.frame_id == frame_id)
    hp = [f for f in frames if f.priority < m.priority]
    lp = [f for f in frames if f.priority > m.priority]
    if any(f.sender in fifo for f in [*hp, m]):
        sub = list(frames)
    else:
        sub = [*hp, m, *([max(lp, key=lambda f: frame_time(f, bitrate))] if lp else [])]
    return next(r.wcrt_s for r in analyse(with_jitter(sub, seconds(jitter_s)), bitrate, fifo)
                if r.frame.frame_id == frame_id)


def load_frames(stats: Mapping[str, Any]) -> list[Frame]:
    """The background nodes' streams of a run on the wire-time bus ("load_streams" of canbus's
    statistics line, realtime --load or the lockstep model's, hil.rig.simbus), as the analysis
    takes them: 8-byte frames, deadline = period.  One identifier of two nodes (never at the
    same time: hil.rig.simbus.check_bus_load) at the shorter period."""
    periods: dict[int, Fraction] = {}
    for s in stats.get("load_streams", ()):
        p = Fraction(s["period_ns"], 10**9)
        periods[s["id"]] = min(p, periods.get(s["id"], p))
    return [Frame(i, f"LOAD_{i:03X}", "LOAD", p, p) for i, p in sorted(periods.items())]


def _queue(spec: BusSpec, frame_id: int, fifo_senders: Sequence[str]) -> str:
    m = spec.by_id(frame_id)
    return "fifo" if m is not None and any(s in fifo_senders for s in m.senders) else "prio"


def bus_section(stats: Mapping[str, Any], spec: BusSpec, scenarios: Sequence[Scenario],
                jitter_s: float = 0.0, fifo_senders: Sequence[str] = FIFO_SENDERS) -> dict[str, Any]:
    """The section: bit rate, model, utilisation of the cyclic frames at the flight's
    periods, canbus's delivery error and losses, and per frame name its response times, bound,
    sender's queue and verdict."""
    bitrate = int(stats["bitrate"])
    nodes = confinement(stats)
    faulted = stats.get("error_frames", 0) > 0 or any(n.startswith("babble") for n in nodes)
    frames = flight_frames(spec, scenarios) + load_frames(stats)
    d = stats["delivery_error"]
    simulated = {k: stats[k] for k in ("time_base", "load_dropped") if k in stats}
    return {"bitrate": bitrate, "model": "wire", **simulated,
            "utilisation": round(float(utilisation(frames, bitrate)), 5), "jitter_s": jitter_s,
            "frames_on_bus": stats["frames"], "lost": stats["lost"], "late_queued": stats["late_queued"],
            "load": stats["load"], "canbus_cpu_s": stats["cpu_s"], "canbus_wall_s": stats["wall_s"],
            "delivery_error": {k: d[k] for k in _PERCENTILES},
            "error_frames": stats.get("error_frames", 0), "nodes": nodes,
            "frames": judged_frames(stats["ids"], spec, frames, bitrate, jitter_s, fifo_senders,
                                    stats["late_queued"], faulted)}


def judged_frames(ids: Mapping[str, Mapping[str, Any]], spec: BusSpec, frames: Sequence[Frame],
                  bitrate: int, jitter_s: float, fifo_senders: Sequence[str],
                  late_queued: int = 0, faulted: bool = False) -> dict[str, Any]:
    """Per frame name (canbus's key "0x040" where the DBC has none): its measured response
    times (`ids`, canbus's shape: n, p50_s, p99_s, max_s), its bound at the bit rate, its
    sender's queue and its verdict (a frame above its bound on a bus with wire faults:
    FAULTED, which the analysis does not bound)."""
    bounds = {r.frame.frame_id: r.wcrt_s for r in analyse(frames, bitrate, fifo_senders)}
    out: dict[str, Any] = {}
    for key, got in ids.items():
        fid = int(key, 16)
        m = spec.by_id(fid)
        queue = _queue(spec, fid, fifo_senders)
        bound = bounds.get(fid)
        loose = None
        if bound is not None and Fraction(got["max_s"]) > bound and jitter_s > 0:
            loose = jitter_bound(frames, fid, bitrate, jitter_s, fifo_senders)
        entry = {"id": fid, "n": got["n"], **{k: got[k] for k in _PERCENTILES},
                 "wcrt_s": None if bound is None else float(bound),
                 "wcrt_jitter_s": None if loose is None else float(loose), "queue": queue}
        if fid not in bounds:
            entry["verdict"] = EVENT
        elif bound is None:
            entry["verdict"] = UNBOUNDED
        else:
            entry["verdict"] = _judge(Fraction(got["max_s"]), bound, loose, late_queued)
            entry["verdict"] = FAULTED if faulted and entry["verdict"] != WITHIN else entry["verdict"]
        out[m.name if m is not None else key] = entry
    return out


def confinement(stats: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """Each node's fault confinement (canbus's statistics; {} from a canbus without faults),
    by the rig's name of the node (sim, recorder, fcc, babble0...)."""
    return {n.get("node", n["iface"]): {k: n[k] for k in _CONFINEMENT}
            for n in stats.get("nodes", []) if all(k in n for k in _CONFINEMENT)}


def _judge(measured: Fraction, bound: Fraction, loose: Fraction | None, late_queued: int) -> str:
    if measured <= bound:
        return WITHIN
    if loose is not None and measured <= loose:
        return JITTER
    return LATE if late_queued else ABOVE


def bus_failure(section: Mapping[str, Any]) -> str:
    """Why the run fails on its bus ('' when it does not): a judged frame's measured response
    time above its bound (the model or the analysis is wrong), or frames canbus lost."""
    above = [(name, f) for name, f in section["frames"].items() if f["verdict"] == ABOVE]
    if above:
        name, f = above[0]
        return (f"{name}'s response time above its bound: {f['max_s'] * 1e3:.3f} ms > "
                f"{f['wcrt_s'] * 1e3:.3f} ms at {section['bitrate']} bit/s"
                + (f" ({len(above)} frames above their bound)" if len(above) > 1 else ""))
    late = [name for name, f in section["frames"].items() if f["verdict"] == LATE]
    if late:
        return (f"{late[0]}'s response time above its bound while canbus fell behind the bus "
                f"({section['late_queued']} frames read after an arbitration they should have "
                f"joined: the response times count its lateness, not the model's)")
    if section.get("lost"):
        return f"the wire-time bus (canbus) lost {section['lost']} frame(s)"
    return ""
