"""`hil study cdrw`: seed 1's Table 5 comparison with its controls (offline, no bus).

Every case flies the default CDRW scenario (hil.sim.cdrw_flight) and replays the readings
through the firmware's filters (sid_replay).  The number reported is the paper's Table 5
figure of merit, the improvement over the KF, 100 (1 - e_filter / e_kf), of the mean error
integral sum |y_faultfree - x_hat| dt over a set of flights:

* over `runs` fault start times (noise seed 1, drawn as `hil campaign` draws them), or
* for each noise seed 1..`noise_seeds`, the same fault times (case noise_seeds: the mean of
  the per-seed Table 5 improvements with a Student-t interval, and their range),

with a 95 % percentile-bootstrap interval over those flights (the ratio of means is
resampled).  The controls: no fault; the plant's true local model (A_k, B_k, c_k of the
simulator) in place of the MLS model (the Python reference loop, hil.reference.sid, whose
rows equal sid_replay's); detector oracle / off; row conventions prior / posterior; the
ZKF's order; the KF's process-noise generator E; and the two CDRW derivatives the paper
does not publish that move the result (C_m_alpha, the pull-up's size).
"""
from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from hil.reference.cdrw_study import errors, flight_csv, run_tool
from hil.reference.model import Model
from hil.reference.sid import SidLoop
from hil.scenario.campaign import campaign_fault_times
from hil.scenario.file import Scenario, load_default_scenario, with_fault_start
from hil.scenario.plant_options import CdrwPlantOptions
from hil.sim.cdrw_flight import CdrwFlight, simulate_cdrw

#: paper, seed 1 Table 5 (alpha, q) error integrals
PAPER_TABLE5 = {"kf": (0.1686, 0.1700), "zkf": (0.0966, 0.0976), "azkf": (0.0895, 0.0903)}
#: paper, seed 1 Table 4
PAPER_TABLE4 = {"kf": (0.1956, 0.3045), "zkf": (0.1089, 0.2731), "azkf": (0.1073, 0.2554)}


@dataclasses.dataclass(frozen=True)
class Case:
    name: str
    what: str
    args: tuple[str, ...] = ()          # sid_replay options for every filter
    kf_args: tuple[str, ...] = ()       # extra options for the KF only (its own pass)
    fault: bool = True
    true_model: bool = False
    cm_alpha: float | None = None
    pull_deg: float | None = None
    over: str = "times"                 # "times" | "seeds" | "one"


def cases() -> list[Case]:
    return [
        Case("paper", "default: paper rows, zonotope detector, ZKF order 1000, E = 0.004"),
        Case("no_fault", "no sensor fault at all (noise seed 1)", fault=False, over="one"),
        Case("true_model", "the plant's true local model A_k, B_k, c_k instead of the MLS",
             true_model=True),
        Case("detector_oracle", "detector = the simulator's fault flag", ("--detector", "oracle")),
        Case("detector_off", "detector off", ("--detector", "off")),
        Case("rows_prior", "rows: every filter before y_k", ("--rows", "prior")),
        Case("rows_posterior", "rows: every filter after y_k", ("--rows", "posterior")),
        Case("zkf_order_2", "ZKF order 2", ("--zkf-order", "2")),
        Case("zkf_order_4", "ZKF order 4", ("--zkf-order", "4")),
        Case("kf_e_0.001", "KF with E = 0.001 (ZKF, AZKF keep 0.004)", kf_args=("--e", "0.001")),
        Case("noise_seeds", "Table 5 per noise seed 1..N (the same fault times): mean of the "
             "seeds, t interval, per-seed range", over="seeds"),
        Case("cma_-0.12", "C_m_alpha = -0.12 /rad (project: -0.25)", cm_alpha=-0.12),
        Case("cma_-0.5", "C_m_alpha = -0.5 /rad", cm_alpha=-0.5),
        Case("pull_8", "pull-up 8 deg (project: 5.5)", pull_deg=8.0),
        Case("pull_2.75", "pull-up 2.75 deg", pull_deg=2.75),
    ]


def scenario(case: Case, seed: int = 1) -> Scenario:
    sc = load_default_scenario("cdrw").replace(seed=seed)
    plant = sc.plant
    if not isinstance(plant, CdrwPlantOptions):
        raise TypeError(f"the default cdrw scenario has a {type(plant).__name__}")
    if case.cm_alpha is not None:
        plant = dataclasses.replace(plant, params=dataclasses.replace(plant.params,
                                                                      C_ma=case.cm_alpha))
    if case.pull_deg is not None:
        plant = dataclasses.replace(plant, maneuver=dataclasses.replace(plant.maneuver,
                                                                        pull_deg=case.pull_deg))
    sc = sc.replace(plant=plant)
    return sc if case.fault else sc.replace(faults=())


def flights(case: Case, runs: int, noise_seeds: int) -> list[CdrwFlight]:
    if case.over == "one":
        return [simulate_cdrw(scenario(case))]
    if case.over == "seeds":  # seed after seed, the same fault times in each
        times = campaign_fault_times(scenario(case), runs, 1)
        return [simulate_cdrw(with_fault_start(scenario(case, s), float(t)))
                for s in range(1, noise_seeds + 1) for t in times]
    sc = scenario(case)
    return [simulate_cdrw(with_fault_start(sc, float(t)))
            for t in campaign_fault_times(sc, runs, 1)]


class _TrueModelLoop(SidLoop):
    """The reference loop with the simulator's local model of each step, MLS off."""

    def __init__(self, kind: str, f: CdrwFlight) -> None:
        super().__init__(kind)
        self.cfg.mls_enabled = False
        self.f, self.k = f, 0

    def _model(self) -> Model:
        k = min(self.k, len(self.f.t) - 1)
        return Model(self.f.A_true[k].copy(), self.f.B_true[k].copy(), self.f.c_true[k].copy())

    def step(self, y: np.ndarray, de: float, oracle: bool = False, valid: bool = True) -> dict:
        row = super().step(y, de, oracle, valid)
        self.k += 1
        return row


def true_model_errors(f: CdrwFlight, filters: Sequence[str] = ("kf", "azkf")) -> dict:
    y = np.column_stack([f.alpha_meas, f.q_meas])
    out = {}
    for kind in filters:
        loop = _TrueModelLoop(kind, f)
        rows = [loop.step(y[k], float(f.de[k]), bool(f.fault_flag[k])) for k in range(len(f.t))]
        est = {key: np.array([r[key] for r in rows]) for key in ("alpha_hat", "q_hat")}
        out[kind] = errors(f, est)[0]
    return out


def case_errors(tool: Path, case: Case, f: CdrwFlight) -> dict[str, np.ndarray]:
    """{filter: (e_alpha, e_q)} against the fault-free measurement."""
    if case.true_model:
        return true_model_errors(f)
    rows = run_tool(tool, flight_csv(f), case.args)
    out = {n: errors(f, rows[n])[0] for n in ("kf", "zkf", "azkf")}
    if case.kf_args:
        kf = run_tool(tool, flight_csv(f), (*case.args, "--filter", "kf", *case.kf_args))["kf"]
        out["kf"] = errors(f, kf)[0]
    return out


#: Student t 97.5 % quantiles by degrees of freedom (beyond: 1.96)
_T975 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306,
         9: 2.262, 10: 2.228, 11: 2.201, 12: 2.179, 14: 2.145, 19: 2.093, 29: 2.045}


def improvement(e: np.ndarray, base: np.ndarray) -> np.ndarray:
    return 100.0 * (1.0 - e.mean(axis=0) / base.mean(axis=0))


def bootstrap(e: np.ndarray, base: np.ndarray, n_boot: int = 2000,
              rng: np.random.Generator | None = None) -> tuple[np.ndarray, np.ndarray]:
    """95 % percentile interval of improvement() over the flights (paired resampling)."""
    n = len(e)
    if n < 2:
        v = improvement(e, base)
        return v, v
    rng = rng or np.random.default_rng(0)
    idx = rng.integers(0, n, size=(n_boot, n))
    vals = 100.0 * (1.0 - e[idx].mean(axis=1) / base[idx].mean(axis=1))
    return np.percentile(vals, 2.5, axis=0), np.percentile(vals, 97.5, axis=0)


def run_case(tool: Path, case: Case, runs: int, noise_seeds: int) -> dict:
    per = [case_errors(tool, case, f) for f in flights(case, runs, noise_seeds)]
    filters = [n for n in ("kf", "zkf", "azkf") if n in per[0]]
    e = {n: np.array([p[n] for p in per]) for n in filters}
    res: dict = {"what": case.what, "over": case.over, "n": len(per),
                 "error_mean": {n: e[n].mean(axis=0).tolist() for n in filters}}
    for n in filters:
        if n == "kf":
            continue
        lo, hi = bootstrap(e[n], e["kf"])
        res[f"{n}_vs_kf"] = {"alpha": float(improvement(e[n], e["kf"])[0]),
                             "q": float(improvement(e[n], e["kf"])[1]),
                             "alpha_ci": [float(lo[0]), float(hi[0])],
                             "q_ci": [float(lo[1]), float(hi[1])]}
        if case.over == "times":
            per_flight = 100.0 * (1.0 - e[n] / e["kf"])
            res[f"{n}_vs_kf"]["per_flight_range"] = {
                "alpha": [float(per_flight[:, 0].min()), float(per_flight[:, 0].max())],
                "q": [float(per_flight[:, 1].min()), float(per_flight[:, 1].max())]}
        if case.over == "seeds":  # Table 5 per noise seed: its spread and the mean's interval
            k = len(per) // noise_seeds
            per_seed = np.array([improvement(e[n][i * k:(i + 1) * k], e["kf"][i * k:(i + 1) * k])
                                 for i in range(noise_seeds)])
            m = per_seed.mean(axis=0)
            half = _T975.get(noise_seeds - 1, 1.96) * per_seed.std(axis=0, ddof=1) / np.sqrt(noise_seeds)
            res[f"{n}_vs_kf"].update(
                alpha=float(m[0]), q=float(m[1]),
                alpha_ci=[float(m[0] - half[0]), float(m[0] + half[0])],
                q_ci=[float(m[1] - half[1]), float(m[1] + half[1])],
                per_seed={"alpha": per_seed[:, 0].tolist(), "q": per_seed[:, 1].tolist()},
                per_seed_range={"alpha": [float(per_seed[:, 0].min()), float(per_seed[:, 0].max())],
                                "q": [float(per_seed[:, 1].min()), float(per_seed[:, 1].max())]})
    return res


def paper_table5() -> dict:
    """The paper's own Table 5 and Table 4: alpha/q ratio per filter, improvements."""
    out = {}
    for name, tab in (("table4", PAPER_TABLE4), ("table5", PAPER_TABLE5)):
        out[name] = {n: {"alpha_over_q": tab[n][0] / tab[n][1]} for n in tab}
        for n in ("zkf", "azkf"):
            out[name][n].update(alpha=100 * (1 - tab[n][0] / tab["kf"][0]),
                                q=100 * (1 - tab[n][1] / tab["kf"][1]))
    return out


def _first(t: np.ndarray, cond: np.ndarray) -> float | None:
    k = np.flatnonzero(cond)
    return float(t[k[0]]) if len(k) else None


def fig7_timing(tool: Path, level: float = 0.97, stall_deg: float = 15.0) -> dict:
    """Fig. 7 on the default flight: when each loop's MLS rho(A_k), the true rho and alpha
    first pass `level` / `stall_deg`, and the MLS's a21 against the true one before the pull."""
    f = simulate_cdrw(load_default_scenario("cdrw"))
    rows = run_tool(tool, flight_csv(f))
    pre = (f.t > 0.5) & (f.t < 2.0)
    out: dict = {"level": level, "alpha_passes_deg": stall_deg,
                 "alpha_time": _first(f.t, np.degrees(f.alpha_true) >= stall_deg),
                 "rho_true_time": _first(f.t, f.rho_true >= level),
                 "rho_true_max": float(np.max(f.rho_true)),
                 "a21_true_before_pull": float(np.mean(f.A_true[pre, 1, 0]))}
    for n in ("kf", "zkf", "azkf"):
        out[n] = {"rho_time": _first(f.t, rows[n]["rho"] >= level),
                  "a21_before_pull": float(np.mean(rows[n]["a21"][pre]))}
    return out


def cdrw_study(tool: Path, runs: int = 12, noise_seeds: int = 10,
               only: Sequence[str] | None = None,
               progress: Callable[[str], None] | None = None) -> dict:
    out: dict = {"runs": runs, "noise_seeds": noise_seeds, "paper": paper_table5(),
                 "fig7": fig7_timing(tool), "cases": {}}
    for case in cases():
        if only and case.name not in only:
            continue
        if progress:
            progress(case.name)
        out["cases"][case.name] = run_case(tool, case, runs, noise_seeds)
    return out


def _fmt(d: dict | None, key: str) -> str:
    if not d:
        return f"{'':>22}"
    lo, hi = d[f"{key}_ci"]
    return f"{d[key]:+6.1f} [{lo:+6.1f},{hi:+6.1f}]"


def format_cdrw_study(s: dict) -> str:
    lines = [f"paper 1 (MLS-AZKF), Table 5 comparison with controls: improvement over the KF, % "
             f"(mean over {s['runs']} fault times or {s['noise_seeds']} noise seeds; "
             "95 % bootstrap interval)",
             f"  {'case':18} {'n':>3}  {'AZKF alpha':>22} {'AZKF q':>22}  {'ZKF alpha':>22} "
             f"{'ZKF q':>22}"]
    for name, c in s["cases"].items():
        a, z = c.get("azkf_vs_kf"), c.get("zkf_vs_kf")
        lines.append(f"  {name:18} {c['n']:>3}  {_fmt(a, 'alpha')} {_fmt(a, 'q')}  "
                     f"{_fmt(z, 'alpha')} {_fmt(z, 'q')}")
    ns = s["cases"].get("noise_seeds", {}).get("azkf_vs_kf", {}).get("per_seed_range")
    if ns:
        lines.append(f"  noise seeds 1..{s['noise_seeds']}: AZKF vs KF per seed alpha "
                     f"{ns['alpha'][0]:+.1f} .. {ns['alpha'][1]:+.1f}, q {ns['q'][0]:+.1f} .. "
                     f"{ns['q'][1]:+.1f}")
    g = s.get("fig7")
    if g:
        rt = lambda v: "never" if v is None else f"{v:.2f} s"  # noqa: E731
        lines.append(f"Fig. 7, default flight: MLS rho passes {g['level']:g} at "
                     + ", ".join(f"{n.upper()} {rt(g[n]['rho_time'])}" for n in ("kf", "zkf", "azkf"))
                     + f"; true rho at {rt(g['rho_true_time'])} (max {g['rho_true_max']:.3f}); alpha passes "
                     f"{g['alpha_passes_deg']:g} deg at {rt(g['alpha_time'])}; a21 before the "
                     f"pull: MLS (AZKF loop) {g['azkf']['a21_before_pull']:.2f}, true "
                     f"{g['a21_true_before_pull']:.2f}")
    p = s["paper"]
    lines.append("paper Table 5: AZKF {:+.1f}/{:+.1f}, ZKF {:+.1f}/{:+.1f}; alpha/q ratio "
                 "KF {:.3f} ZKF {:.3f} AZKF {:.3f} (Table 4: {:.2f} {:.2f} {:.2f})".format(
                     p["table5"]["azkf"]["alpha"], p["table5"]["azkf"]["q"],
                     p["table5"]["zkf"]["alpha"], p["table5"]["zkf"]["q"],
                     *(p["table5"][n]["alpha_over_q"] for n in ("kf", "zkf", "azkf")),
                     *(p["table4"][n]["alpha_over_q"] for n in ("kf", "zkf", "azkf"))))
    return "\n".join(lines)
