"""What a run directory's summary says, as text: the papers' tables and fcc's counters.

Used at the end of every command and by `hil report DIR` (which reads summary.json back).
"""
from __future__ import annotations

from typing import Any

from hil.results import metrics
from hil.results.busstats_table import format_bus, format_wire_faults
from hil.results.figures import format_dead_zone, format_fig3
from hil.rig.status import StatusCounters


def firmware_summary(status: StatusCounters, rig_security: dict[str, int] | None = None) -> dict[str, Any]:
    """fcc's heartbeat counters at exit (only what the inputs decide; gauges in run_info), from
    authenticated heartbeats only; `security` adds what the rig's own verification counted."""
    g = status.get
    return {
        "security": {"fcc": {"mac_failed": g("FCC_SEC_COUNTS.mac_failed"),
                             "freshness_failed": g("FCC_SEC_COUNTS.freshness_failed"),
                             "unpaired": g("FCC_SEC_COUNTS.unpaired"),
                             "mode_refused": g("FCC_SEC_COUNTS.mode_refused")},
                     # refusals only: the count verified grows with the heartbeats (wall clock)
                     "rig": {k: v for k, v in (rig_security or {}).items() if k != "verified"}},
        "steps": {"cdrw": g("FCC_STATUS.cdrw_steps"), "missile": g("FCC_STATUS.msl_steps")},
        "overruns": g("FCC_STATUS.overruns"),
        "e2e": {"ok": g("FCC_E2E_COUNTS.ok"), "repeated": g("FCC_E2E_COUNTS.repeated"),
                "ok_some_lost": g("FCC_E2E_COUNTS.ok_some_lost"),
                "wrong_sequence": g("FCC_E2E_COUNTS.wrong_sequence"),
                "error": g("FCC_E2E_FAULTS.error"), "no_new_data": g("FCC_E2E_FAULTS.no_new_data")},
        "rejected": {"unknown_id": g("FCC_REJECT_COUNTS.unknown_id"),
                     "wrong_dlc": g("FCC_REJECT_COUNTS.wrong_dlc"),
                     "out_of_range": g("FCC_REJECT_COUNTS.out_of_range"),
                     "tx_refused": g("FCC_REJECT_COUNTS.tx_refused"),
                     # frames on fcc's own identifiers: another node sent as fcc
                     "own_id": g("FCC_E2E_FAULTS.own_id")},
        "bus": {"bus_errors": g("FCC_BUS_COUNTS.bus_errors"),
                "rx_overflows": g("FCC_BUS_COUNTS.rx_overflows"),
                "tx_dropped": g("FCC_BUS_COUNTS.tx_dropped"),
                "tx_retries": g("FCC_BUS_COUNTS.tx_retries")},
    }


def _cdrw_tables(res_table: metrics.Table, truth: metrics.Table, which: str,
                 show_paper: bool = True, rows: str = "") -> list[str]:
    paper = (metrics.PAPER_TABLE4 if which == "table4" else metrics.PAPER_TABLE5) if show_paper else None
    label = "Table 4 (one fault)" if which == "table4" else "Table 5 (mean over the campaign)"
    label += f", {rows} rows" if rows else ""
    return [metrics.format_error_table(res_table, f"CDRW {label}: integral |y_faultfree - y_hat| dt",
                                       paper),
            metrics.format_error_table(truth, f"CDRW {label}: integral |x_true - x_hat| dt")]


def summary_tables(summary: dict[str, Any]) -> list[str]:
    """The text tables of a summary.json (what each command prints at the end)."""
    tables: list[str] = []
    cd = summary.get("cdrw")
    if cd:
        # the paper's numbers only beside the paper's default scenario (old summaries: shown)
        paper = bool(cd.get("paper_scenario", True))
        rows = cd.get("rows", "")
        if "table5_ci" in cd:
            tables += [metrics.format_table5(cd, paper=metrics.PAPER_TABLE5 if paper else None,
                                             rows=rows),
                       metrics.format_table5(cd, truth=True, rows=rows)]
        for which in ("table4", "table5"):
            if which in cd and not (which == "table5" and "table5_ci" in cd):
                tables += _cdrw_tables(cd[which], cd[f"{which}_truth"], which, paper, rows)
        if "azkf_better_than_kf_runs" in cd and "table5_ci" not in cd:
            b = cd["azkf_better_than_kf_runs"]
            tables.append(f"AZKF better than KF in {b['alpha']} of {summary.get('runs_count')} "
                          f"flights for alpha, {b['q']} for q")
        if "coverage" in cd:
            tables.append(metrics.format_coverage(
                cd["coverage"], f"Bounds coverage ({rows or 'fcc'} rows): steps with the true state "
                "inside the bounds (zonotope hull; KF +-3 sigma)"))
        for mode, t in (cd.get("tables") or {}).items():
            if mode == rows:
                continue
            if "table5_ci" in t:
                tables += [metrics.format_table5(t, rows=mode), metrics.format_table5(t, truth=True, rows=mode)]
            else:
                tables += _cdrw_tables(t["table4"], t["table4_truth"], "table4", False, mode)
            if "coverage" in t:
                tables.append(metrics.format_coverage(t["coverage"], f"Bounds coverage ({mode} rows)"))
        if cd.get("replay_check", {}).get("not_computed"):
            tables.append(f"prior/posterior tables not computed: {cd['replay_check']['not_computed']}")
        elif cd.get("replay_check"):
            rc = cd["replay_check"]
            line = (f"sid_replay --rows {rc['rows']} on the readings fcc received vs fcc's own "
                    f"rows: largest estimate difference {rc['max_abs_estimate_difference']:.2e}")
            if "max_abs_bound_difference" in rc:   # (summaries before 2026-12-02: estimates only)
                line += (f", bound difference {rc['max_abs_bound_difference']:.2e}, fault flags "
                         f"differing at {rc['fault_flag_mismatches']} steps")
            applied = (summary.get("bus_trust") or {}).get("cross_check", "")
            if applied.startswith("not applied"):   # the replay is not fcc's input: say so
                line += f" ({applied})"
            tables.append(line)
    trust = summary.get("bus_trust")
    if isinstance(trust, dict) and trust.get("verdict", "ok") != "ok":
        tables.append(str(trust.get("message")))
    if summary.get("responses", {}).get("dead_zone"):
        tables.append(format_dead_zone(summary["responses"]["dead_zone"]))
    if summary.get("fig3"):
        tables.append(format_fig3(summary["fig3"]))
    ms = summary.get("missile")
    if ms and ms.get("runs"):
        tables.append("Missile, paper 2 (LQG) Fig. 3: RMS over the run\n"
                      + metrics.format_missile_table(ms["runs"]))
    if isinstance(summary.get("bus"), dict) and summary["bus"].get("frames") is not None:
        tables.append(format_bus(summary["bus"]))
    if "firmware" in summary:
        tables.append(format_firmware(summary["firmware"]))
    wire = format_wire_faults(summary.get("bus") or {})
    if wire:
        tables.append(wire)
    sync = summary.get("sync")
    if isinstance(sync, dict) and isinstance(sync.get("refused"), dict):
        r = sync["refused"]
        tables.append(f"time sync: fcc {sync.get('state')}, {sync.get('losses')} losses; refused "
                      f"unauthenticated {r.get('unauthenticated')} mac {r.get('mac_failed')} "
                      f"freshness {r.get('freshness_failed')} step {r.get('step_refused')} rate "
                      f"{r.get('rate_refused')}: {sync.get('message') or 'ok'}")
    return tables


def format_firmware(fw: dict[str, Any]) -> str:
    e, r, b = fw["e2e"], fw["rejected"], fw["bus"]
    return ("fcc counters: steps cdrw {0} missile {1}, overruns {2}\n"
            "  E2E ok {3} repeated {4} ok_some_lost {5} wrong_sequence {6} error {7} no_new_data {8}\n"
            "  rejected unknown_id {9} wrong_dlc {10} out_of_range {11}; bus errors {12} "
            "rx overflows {13}").format(
        fw["steps"]["cdrw"], fw["steps"]["missile"], fw["overruns"], e["ok"], e["repeated"],
        e["ok_some_lost"], e["wrong_sequence"], e["error"], e["no_new_data"], r["unknown_id"],
        r["wrong_dlc"], r["out_of_range"], b["bus_errors"], b["rx_overflows"]) + _format_security(fw)


def _format_security(fw: dict[str, Any]) -> str:
    sec = fw.get("security")
    if not isinstance(sec, dict) or not isinstance(sec.get("fcc"), dict):
        return ""
    f, r = sec["fcc"], sec.get("rig") or {}
    # (what the rig verified grows with the heartbeats, a wall-clock count: run_info.json has it)
    return ("\n  authentication: fcc refused mac {0} freshness {1} unpaired {2}, mode refusals {3}; "
            "rig refused mac {4} freshness {5}").format(
        f.get("mac_failed"), f.get("freshness_failed"), f.get("unpaired"), f.get("mode_refused"),
        r.get("mac_failed"), r.get("freshness_failed"))
