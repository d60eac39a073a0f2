"""One flight inside one rig -- a campaign's CDRW flight or a sweep's missile flight -- in a
session of its own (candump, fcc, the simulator's socket), so its result depends on nothing
but its inputs: not on which worker flies it, nor on the flights that worker flew before."""
from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path
from typing import Any

from ..faults import Scenario, with_fault_start
from ..rig.apps import CdrwDriver, MissileDriver
from ..rig.buslog import split_flights
from ..rig.report import firmware_summary
from ..rig.results import cdrw_record, cdrw_result, missile_result
from ..progress import bar as progress_bar
from ..rig.runs import CampaignFlight, RigConfig, _fly, _require_log, campaign_flight, fcc_args
from ..rig.session import RigError, RigSession


@dataclasses.dataclass
class FlightDone:
    """What a rig sends back for one flight."""

    flight: Any                  # CampaignFlight or MissileResult
    firmware: dict[str, Any]     # fcc's counters over this flight's session


def fly_campaign_flight(scenario: Scenario, index: int, fault_start: float, cfg: RigConfig,
                        keep: bool = False) -> FlightDone:
    """Flight `index` of a campaign, its faults moved to `fault_start`, in a fresh session in
    cfg.out_dir (removed afterwards unless `keep`; kept when the flight fails)."""
    out = Path(cfg.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with RigSession(out, fcc_args([scenario], cfg), iface=cfg.iface, fcc_binary=cfg.fcc_binary) as rig:
        d = CdrwDriver(with_fault_start(scenario, fault_start), rig.codec, cfg.mode == "realtime")
        with progress_bar(d.n_steps, False, "") as bar:
            _fly(rig, [d], cfg, bar)
        rec = cdrw_record(d)
        rig.shutdown()
    _require_log(rig)
    flights = split_flights(out / "bus.log")
    if len(flights) != 1:
        raise RigError(f"{out / 'bus.log'}: {len(flights)} flights recorded, expected 1")
    done = FlightDone(campaign_flight(index, fault_start, cdrw_result(rig.spec, rec, flights[0]),
                                      fcc_args([scenario], cfg)),
                      firmware_summary(rig.status, rig.security.counters()))
    if not keep:
        shutil.rmtree(out, ignore_errors=True)
    return done


def fly_sweep_point(scenario: Scenario, cfg: RigConfig) -> FlightDone:
    """One closed-loop missile flight of a sweep (the scenario carries its T and word length),
    fcc designing for it on the flight's SIM_CONTROL reset as in the sequential sweep."""
    out = Path(cfg.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    lqg = scenario.lqg
    assert lqg is not None
    with RigSession(out, fcc_args([scenario], cfg), iface=cfg.iface, fcc_binary=cfg.fcc_binary) as rig:
        d = MissileDriver(scenario, rig.codec, cfg.mode == "realtime")
        with progress_bar(0, False, "") as bar:
            _fly(rig, [d], cfg, bar, None, lqg.period, lqg.bits)
        rig.shutdown()
    done = FlightDone(missile_result(d, reference=cfg.mode == "lockstep"), firmware_summary(rig.status, rig.security.counters()))
    shutil.rmtree(out, ignore_errors=True)
    return done


def add_counters(a: dict[str, Any], b: dict[str, Any]) -> dict[str, Any]:
    """fcc's counters of two sessions added up (nested dicts of whole numbers)."""
    return {k: add_counters(v, b.get(k, {})) if isinstance(v, dict) else v + b.get(k, 0)
            for k, v in a.items()}


__all__ = ["CampaignFlight", "FlightDone", "add_counters", "fly_campaign_flight", "fly_sweep_point"]
