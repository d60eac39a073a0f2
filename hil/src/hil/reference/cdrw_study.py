"""The identification firmware on the simulated CDRW flight: Tables 4-5, detector, rho(A).

    python -m hil.reference.cdrw_study [--tool build/bin/sid_replay] [--runs 100]
        [--seeds 20] [--ratio-seeds 50] [-- extra sid_replay options]

Flies the CDRW plant offline (hil.sim.cdrw_flight, the default scenario: 0.1 s spike on
alpha and q at 4 s), replays the readings through the *firmware* (sid_replay, the C
modules of firmware/sid) for the `order` and `skip` fault policies, and prints:

* Table 4: the default flight, error integral sum |y - x_hat| dt per state against the
  fault-free measurement and against the true state, improvement over the KF;
* the detector on that flight: when the fault is flagged, latency, clearing delay;
* false alarms on `--seeds` fault-free flights (noise seeds 1..N);
* the fault-free innovation ratio max_i |y_i - x_i| / (hull(P)_i + hull(F)_i) of the
  AZKF with the detector off, over `--ratio-seeds` seeds: the smallest margin that raises
  no false alarm on each (valid because without any alarm the loop is the same);
* Table 5: the mean over `--runs` fault start times drawn as `hil campaign` draws them,
  with the detector's statistics (detected at the first faulty sample, clearing delay,
  flags outside the fault);
* rho(A_k) tracking: mean |rho_hat - rho_true| (and |A21| error) of each closed loop, and
  of the MLS alone (--mls-only) on the true states and on the measurements, with and
  without the optional intercept.

Everything is measured, nothing is assumed; the numbers go into firmware/sid/README.md.
"""
from __future__ import annotations

import argparse
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hil.reference.metrics import error_table
from hil.results.sidrows import read_rows
from hil.scenario.campaign import campaign_fault_times
from hil.scenario.file import load_default_scenario, with_fault_start
from hil.sim.cdrw_flight import CdrwFlight, simulate_cdrw
from hil.sim.sid_csv import sid_csv

DT = 0.02
FILTERS = ("kf", "zkf", "azkf")
#: paper, seed 1 Table 4 (real CDRW flight, vs the fault-free measurement)
PAPER_TABLE4 = {"kf": (0.1956, 0.3045), "zkf": (0.1089, 0.2731), "azkf": (0.1073, 0.2554)}
PAPER_TABLE5 = {"kf": (0.1686, 0.1700), "zkf": (0.0966, 0.0976), "azkf": (0.0895, 0.0903)}
#: hull of the default measurement generators F = 0.02 I (SPEC section 2)
F_HULL = np.array([0.02, 0.02])

Rows = dict[str, dict[str, np.ndarray]]


def simulate(seed: int = 1, fault_start: float | None = 4.0) -> CdrwFlight:
    """The default CDRW scenario with another noise seed; fault_start None: no fault."""
    sc = load_default_scenario("cdrw").replace(seed=seed)
    sc = sc.replace(faults=()) if fault_start is None else with_fault_start(sc, fault_start)
    return simulate_cdrw(sc)


def campaign_times(runs: int, seed: int = 1) -> np.ndarray:
    """Fault start times as `hil campaign` draws them (hil.scenario.campaign)."""
    return campaign_fault_times(load_default_scenario("cdrw"), runs, seed)


def flight_csv(f: CdrwFlight, faulty: bool = True, states: bool = False) -> str:
    """sid_replay input: the readings (with or without the fault), or the true states."""
    if states:
        a, q = f.alpha_true, f.q_true
    elif faulty:
        a, q = f.alpha_meas, f.q_meas
    else:
        a, q = f.alpha_meas_faultfree, f.q_meas_faultfree
    de = f.de if faulty else f.de_faultfree
    flag = f.fault_flag if faulty else np.zeros(len(f.t), dtype=int)
    return sid_csv(f.t.tolist(), a.tolist(), q.tolist(), de.tolist(), flag.tolist())  # the same text


def run_tool(tool: Path, csv_text: str, args: Sequence[str] = ()) -> Rows:
    res = subprocess.run([str(tool), *args], input=csv_text, capture_output=True, text=True,
                         timeout=120)
    if res.returncode != 0:
        raise RuntimeError(f"sid_replay {' '.join(args)}: {res.stderr.strip()}")
    return read_rows(res.stdout)


def errors(f: CdrwFlight, est: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(vs fault-free measurement, vs truth): sum |target - x_hat| dt for (alpha, q)."""
    t = error_table(np.column_stack([f.alpha_meas_faultfree, f.q_meas_faultfree]),
                    np.column_stack([f.alpha_true, f.q_true]), {"f": est})["f"]
    return t["meas"], t["truth"]


def intervals(flag: np.ndarray) -> list[tuple[int, int]]:
    """[(first, last)] step indices of each run of True."""
    out, k, n = [], 0, len(flag)
    while k < n:
        if flag[k]:
            j = k
            while j < n and flag[j]:
                j += 1
            out.append((k, j - 1))
            k = j
        else:
            k += 1
    return out


@dataclass
class Detection:
    latency: int | None   # steps from the first faulty sample to the flag (None: missed)
    clear_delay: int | None  # steps after the last faulty sample until the flag is down
    other_flags: int      # flagged steps that belong to no fault episode


def detection(f: CdrwFlight, flag: np.ndarray) -> Detection:
    """The AZKF's flag against the injected fault (the fault_flag column)."""
    faulty = np.flatnonzero(f.fault_flag)
    if len(faulty) == 0:
        return Detection(None, None, int(np.count_nonzero(flag)))
    k0, k1 = int(faulty[0]), int(faulty[-1])
    first = next((k for k in range(k0, k1 + 1) if flag[k]), None)
    j = k1 + 1
    while j < len(flag) and flag[j]:
        j += 1
    episode = np.zeros(len(flag), dtype=bool)
    if first is not None:
        episode[first:j] = True
    return Detection(None if first is None else first - k0, j - (k1 + 1) if first is not None else None,
                     int(np.count_nonzero(flag & ~episode)))


def innovation_ratio(f: CdrwFlight, est: dict[str, np.ndarray], faulty: bool = False) -> np.ndarray:
    """Per step max_i |y_i - x_i| / (hull(P)_i + hull(F)_i) of a ZKF/AZKF row set."""
    y = (np.column_stack([f.alpha_meas, f.q_meas]) if faulty
         else np.column_stack([f.alpha_meas_faultfree, f.q_meas_faultfree]))
    xh = np.column_stack([est["alpha_hat"], est["q_hat"]])
    hull = np.column_stack([est["alpha_hi"] - est["alpha_lo"], est["q_hi"] - est["q_lo"]]) / 2
    return np.max(np.abs(y - xh) / (hull + F_HULL), axis=1)


def rho_tracking(f: CdrwFlight, est: dict[str, np.ndarray], skip: int = 20) -> tuple[float, float]:
    """(mean |rho_hat - rho_true|, mean |A21_hat - A21_true|) after the first `skip` steps."""
    s = slice(skip, None)
    return (float(np.mean(np.abs(est["rho"][s] - f.rho_true[s]))),
            float(np.mean(np.abs(est["a21"][s] - f.A_true[s, 1, 0]))))


# ---- printing --------------------------------------------------------------------------
def _pct(v: float, base: float) -> str:
    return f"{100.0 * (1.0 - v / base):+.0f}%"


def print_table(title: str, tab: dict[str, tuple[np.ndarray, np.ndarray]],
                paper: dict[str, tuple[float, float]] | None = None) -> None:
    print(title)
    print(f"  {'filter':6} {'alpha meas':>18} {'q meas':>18} {'alpha truth':>18} {'q truth':>18}"
          + ("   paper alpha / q" if paper else ""))
    for name in FILTERS:
        if name not in tab:
            continue
        meas, truth = tab[name]
        cells = []
        for v, base in ((meas[0], tab["kf"][0][0]), (meas[1], tab["kf"][0][1]),
                        (truth[0], tab["kf"][1][0]), (truth[1], tab["kf"][1][1])):
            cells.append(f"{v:.4f}" + ("" if name == "kf" else f" ({_pct(v, base)})"))
        extra = f"   {paper[name][0]:.4f} / {paper[name][1]:.4f}" if paper else ""
        print(f"  {name.upper():6} " + " ".join(f"{c:>18}" for c in cells) + extra)


# ---- the study --------------------------------------------------------------------------
def study_policy(tool: Path, policy: str, extra: Sequence[str], runs: int, seeds: int) -> None:
    args = ["--fault-policy", policy, *extra]
    print(f"\n=== fault policy {policy} (sid_replay {' '.join(args)}) ===")
    f = simulate()
    rows = run_tool(tool, flight_csv(f), args)
    print_table("Table 4, default flight (fault at 4.00 s, 0.1 s):",
                {n: errors(f, rows[n]) for n in FILTERS}, PAPER_TABLE4)
    flag = rows["azkf"]["fault"].astype(bool)
    d = detection(f, flag)
    iv = [(round(a * DT, 2), round(b * DT, 2)) for a, b in intervals(flag)]
    print(f"  AZKF fault flag: {iv}; latency {d.latency} steps, cleared {d.clear_delay} steps "
          f"after the fault, {d.other_flags} other flagged steps")

    alarms = []
    for s in range(1, seeds + 1):
        g = simulate(s, None)
        az = run_tool(tool, flight_csv(g), ["--filter", "azkf", *args])["azkf"]
        spans = intervals(az["fault"].astype(bool))
        if spans:
            alarms.append((s, [(round(a * DT, 2), round(b * DT, 2)) for a, b in spans]))
    print(f"  false alarms on {seeds} fault-free flights (seeds 1..{seeds}): "
          f"{len(alarms)} {alarms[:5] if alarms else ''}")

    times = campaign_times(runs)
    tabs: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {n: [] for n in FILTERS}
    lat, clr, other, missed = [], [], 0, 0
    for tf in times:
        g = simulate(1, float(tf))
        r = run_tool(tool, flight_csv(g), args)
        for n in FILTERS:
            tabs[n].append(errors(g, r[n]))
        d = detection(g, r["azkf"]["fault"].astype(bool))
        if d.latency is None or d.clear_delay is None:  # both None together: missed
            missed += 1
        else:
            lat.append(d.latency)
            clr.append(d.clear_delay)
        other += d.other_flags > 0
    mean = {n: (np.mean([t[0] for t in tabs[n]], axis=0), np.mean([t[1] for t in tabs[n]], axis=0))
            for n in FILTERS}
    print_table(f"Table 5-like, mean over {runs} fault start times (paper 1, campaign draw):",
                mean, PAPER_TABLE5)
    lat_a, clr_a = np.asarray(lat), np.asarray(clr)
    print(f"  AZKF detector: missed {missed}/{runs}; flagged at the first faulty sample "
          f"{int(np.sum(lat_a == 0))}/{runs}; cleared after the fault: median "
          f"{np.median(clr_a) if len(clr_a) else float('nan'):.0f} steps, max "
          f"{clr_a.max() if len(clr_a) else -1}, <= 3 steps in {int(np.sum(clr_a <= 3))}/{runs}; "
          f"runs with flags outside the fault: {other}")
    slow = sorted({round(float(t), 2) for t, c in zip(times, clr) if c > 3})
    if slow:
        print(f"  faults cleared late start at {slow} s")


def study_common(tool: Path, extra: Sequence[str], ratio_seeds: int) -> None:
    print("\n=== fault-free innovation ratio of the AZKF (detector off), "
          f"{ratio_seeds} seeds ===")
    worst = []
    for s in range(1, ratio_seeds + 1):
        g = simulate(s, None)
        r = run_tool(tool, flight_csv(g), ["--filter", "azkf", "--detector", "off", *extra])
        ratio = innovation_ratio(g, r["azkf"])
        k = int(np.argmax(ratio))
        worst.append((float(ratio[k]), round(k * DT, 2), s))
    worst.sort(reverse=True)
    q = np.percentile([w[0] for w in worst], [50, 90, 100])
    print(f"  max ratio per flight: median {q[0]:.2f}, 90% {q[1]:.2f}, max {q[2]:.2f}; worst "
          f"(ratio, t, seed): {[(round(w[0], 2), w[1], w[2]) for w in worst[:3]]}")
    times = campaign_times(40)
    spikes = []
    for tf in times:
        g = simulate(1, float(tf))
        r = run_tool(tool, flight_csv(g), ["--filter", "azkf", "--detector", "off", *extra])
        k0 = int(np.flatnonzero(g.fault_flag)[0])
        spikes.append(float(innovation_ratio(g, r["azkf"], faulty=True)[k0]))
    print(f"  the spike's ratio at its first sample over 40 fault times: min {min(spikes):.2f}, "
          f"median {np.median(spikes):.2f}")

    print("\n=== rho(A_k) tracking, default flight (mean over steps 20..350) ===")
    f = simulate()
    print(f"  true rho(A): {f.rho_true.min():.3f} .. {f.rho_true.max():.3f}; "
          f"A21 {f.A_true[:, 1, 0].min():.3f} .. {f.A_true[:, 1, 0].max():.3f}")
    for label, icpt in (("paper (no intercept)", []), ("with --mls-intercept", ["--mls-intercept"])):
        rows = run_tool(tool, flight_csv(f), [*icpt, *extra])
        cells = ", ".join(f"{n.upper()} {rho_tracking(f, rows[n])[0]:.4f} "
                          f"(A21 {rho_tracking(f, rows[n])[1]:.3f})" for n in FILTERS)
        print(f"  closed loops, {label}: |rho err| {cells}")
        for src, kw in (("true states", {"states": True}), ("measurements", {"faulty": False})):
            mls = run_tool(tool, flight_csv(f, **kw), ["--mls-only", *icpt, *extra])["mls"]
            rho_e, a21_e = rho_tracking(f, mls)
            print(f"    MLS alone on the {src:12}: |rho err| {rho_e:.4f}, |A21 err| {a21_e:.3f}, "
                  f"rho at 1 s {mls['rho'][50]:.3f} (true {f.rho_true[50]:.3f}), at 4.5 s "
                  f"{mls['rho'][225]:.3f} (true {f.rho_true[225]:.3f})")


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m hil.reference.cdrw_study",
                                 description=__doc__.split("\n\n")[0])
    ap.add_argument("--tool", type=Path, default=Path("build/bin/sid_replay"))
    ap.add_argument("--runs", type=int, default=100, help="fault times for Table 5 (100)")
    ap.add_argument("--seeds", type=int, default=20, help="fault-free flights (20)")
    ap.add_argument("--ratio-seeds", type=int, default=50, help="seeds for the ratio (50)")
    ap.add_argument("--policy", choices=("order", "skip", "both"), default="both")
    ap.add_argument("extra", nargs="*", help="more sid_replay options (after --)")
    a = ap.parse_args(argv)
    if not a.tool.exists():
        print(f"cdrw_study: {a.tool} not found (build sid_replay, or pass --tool)", file=sys.stderr)
        return 1
    for pol in (("order", "skip") if a.policy == "both" else (a.policy,)):
        study_policy(a.tool, pol, a.extra, a.runs, a.seeds)
    study_common(a.tool, a.extra, a.ratio_seeds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
