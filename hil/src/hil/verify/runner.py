"""Running a suite's cases against the device under test and judging them."""
from __future__ import annotations

import dataclasses
import json
import shlex
import time
from collections.abc import Callable, Mapping, Sequence
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hil.rig.config import RigConfig
from hil.rig.link import CanLink
from hil.runs.run import run_flight
from hil.targets.registry import device_class
from hil.verify.attack import ATTACKS, LIVE_REPLAYS, Attacker
from hil.verify.coverage import profiles_to
from hil.verify.expr import Expectation, evaluate, measured
from hil.verify.fields import read_run, values
from hil.verify.figure import draw, limit
from hil.verify.flights import fly_flights
from hil.verify.platform import INCONCLUSIVE, limited
from hil.verify.series import RunSeries
from hil.verify.statistical import OverFlights
from hil.verify.suite import Case, Suite, shipped
from hil.verify.window import VALUE, Measured, NoWindow, Windowed, measure

PASS, FAIL, ERROR = "pass", "fail", "error"
#: a check every case has (hil.verify.runner.trusted): its run's figures are authentic
EVERY_REQUIREMENT = "(every requirement)"
TRUST_TEXT = "bus_trust.ok == 1 (fcc's outputs authentic: summary.json's bus_trust)"
#: a case's attacker sends a forged frame every 20 ms: a forgery, not a flood (measured: at the
#: attack tests' 2 ms the Cortex-M4F image's 115200-baud SLCAN line is saturated, its sensor
#: frames arrive late and 21 % of its D/A codes differ -- a denial of service, which
#: authentication does not claim to prevent)
ATTACK_PAUSE_S = 0.02


@dataclass
class Check:
    """One expectation of a case, judged."""

    requirement: str
    text: str
    verdict: str
    measured: str
    #: a windowed check: what was measured in which window, and its figure (if drawn)
    windowed: Windowed | None = None
    evidence: Measured | None = None
    figure: Path | None = None


@dataclass
class CaseResult:
    suite: str
    case: Case
    verdict: str
    checks: list[Check] = field(default_factory=list)
    error: str = ""
    seconds: float = 0.0
    run_dir: Path | None = None
    command: str = ""

    @property
    def failed_checks(self) -> list[Check]:
        return [c for c in self.checks if c.verdict != PASS]


def case_verdict(checks: Sequence[Check]) -> str:
    """A failed check fails the case; else one the platform left inconclusive makes it so."""
    found = {c.verdict for c in checks}
    return FAIL if FAIL in found else INCONCLUSIVE if INCONCLUSIVE in found else PASS


def trusted(case: Case, summary: Mapping[str, Any]) -> list[Check]:
    """Every figure of a flight comes from fcc's authenticated frames, but a run whose outputs
    were forged on the bus, sent by another node as fcc or disagree with the reference
    (summary.json's bus_trust not ok: `hil run` exits 7) proves no requirement: its check,
    on every requirement of the case.  A case that names a bus_trust field (an attack on
    fcc's outputs) judges it itself."""
    if any(name.startswith("bus_trust.") for _, e in case.expect for name in _fields(e)):
        return []
    verdict = _trust(summary)
    return [Check(EVERY_REQUIREMENT, TRUST_TEXT, PASS if verdict == "ok" else FAIL,
                  f"bus_trust {verdict}" + ("" if verdict == "ok" else ": " + (
                      (summary.get("bus_trust") or {}).get("message") or "summary.json has no bus_trust")))]


def _trust(summary: Mapping[str, Any]) -> str:
    """summary.json's bus_trust verdict ('missing' when it has none)."""
    return str((summary.get("bus_trust") or {}).get("verdict", "missing"))


def _fields(e: Expectation | Windowed | OverFlights) -> frozenset[str]:
    if isinstance(e, Windowed):
        return frozenset(e.exp.fields)
    if isinstance(e, OverFlights):
        return frozenset(e.per.fields)
    return frozenset(e.fields)


def against_platform(checks: list[Check], timing: Mapping[str, str], summary: Mapping[str, Any]) -> list[Check]:
    """A realtime case's failed checks of timing requirements (requirement: kind), when the
    run's platform did not keep its schedule as that kind needs (hil.verify.platform):
    inconclusive, with the evidence."""
    why = {kind: limited(summary, kind) for kind in set(timing.values())}
    return [dataclasses.replace(c, verdict=INCONCLUSIVE, measured=f"{c.measured}; {why[timing[c.requirement]]}")
            if c.verdict == FAIL and why.get(timing.get(c.requirement, "")) else c for c in checks]


def judge(expect: Sequence[tuple[str, Expectation | Windowed | OverFlights]], run: dict[str, Any],
          series: RunSeries | None = None) -> list[Check]:
    """Every expectation of a case on its flight (series: the run's time series, for the
    windowed ones)."""
    checks = []
    for req, exp in expect:
        assert not isinstance(exp, OverFlights), "an expectation over flights: judge_flights"
        if isinstance(exp, Windowed):
            assert series is not None, "a windowed expectation needs the run's series"
            checks.append(_judge_windowed(req, exp, run, series))
            continue
        vals = values(run, exp.fields)
        ok = bool(evaluate(exp.tree, vals))
        checks.append(Check(req, exp.text, PASS if ok else FAIL, measured(exp, vals)))
    return checks


def _judge_windowed(req: str, w: Windowed, run: dict[str, Any], series: RunSeries) -> Check:
    """Measured in its window; an event that never came, an empty window: a failure, saying so."""
    try:
        got = measure(w.check, series)
    except NoWindow as e:
        return Check(req, w.text, FAIL, str(e), w)
    vals = values(run, w.exp.fields - {VALUE}) | {VALUE: got.value}
    ok = bool(evaluate(w.exp.tree, vals))
    return Check(req, w.text, PASS if ok else FAIL,
                 f"{measured(w.exp, vals)} in [{got.t_from:.4g}, {got.t_to:.4g}] s", w, got)


def judge_flights(expect: Sequence[tuple[str, Expectation | Windowed | OverFlights]],
                  runs: Sequence[dict[str, Any]]) -> list[Check]:
    """Every expectation of a case of many flights, over them all, with its interval."""
    checks = []
    for req, exp in expect:
        assert isinstance(exp, OverFlights), "a case of many flights: expectations over them"
        ok, got = exp.judge(runs)
        checks.append(Check(req, exp.text, PASS if ok else FAIL, got))
    return checks


def trusted_flights(runs: Sequence[Mapping[str, Any]]) -> list[Check]:
    """A case of many flights: every flight's outputs authentic (trusted), one check."""
    bad = [(i, _trust(run["summary"])) for i, run in enumerate(runs) if _trust(run["summary"]) != "ok"]
    return [Check(EVERY_REQUIREMENT, f"{TRUST_TEXT}, every flight", FAIL if bad else PASS,
                  f"{len(bad)} of {len(runs)} flights not ok; first: flight {bad[0][0]}: bus_trust {bad[0][1]}"
                  if bad else f"bus_trust ok in all {len(runs)} flights")]


def draw_checks(checks: Sequence[Check], run_dir: Path, made_by: str) -> None:
    """Each windowed check's evidence figure, check-N.png in the case's run directory."""
    for i, c in enumerate(checks):
        if c.windowed is not None and c.evidence is not None:
            c.figure = draw(c.windowed.check, c.evidence, c.verdict, f"{c.requirement}: {c.windowed.exp.text}",
                            run_dir / f"check-{i}.png", made_by, limit(c.windowed.exp))


def run_case(suite: Suite, case: Case, base: RigConfig, out: Path, refly: str,
             parallel: Mapping[str, Any] | None = None) -> CaseResult:
    """Fly one case in its own run directory (out/cases/ID) and judge it; any failure to fly
    or to read a result is an error, never a pass.  parallel: a case of many flights flies
    them on these workers (hil.verify.flights)."""
    run_dir = out / "cases" / case.id
    cfg = dataclasses.replace(base, out_dir=run_dir, mode=case.mode)
    res = CaseResult(suite.name, case, ERROR, run_dir=run_dir, command=refly)
    t0 = time.monotonic()
    try:
        if case.n_flights > 1:
            runs = fly_flights(case.flights, case.n_flights, cfg, run_dir, parallel)
            res.checks = judge_flights(case.expect, runs) + trusted_flights(runs)
            res.verdict = case_verdict(res.checks)
            res.seconds = time.monotonic() - t0
            return res
        attacker = Attacker(ATTACKS[case.attack], case.attack in LIVE_REPLAYS, pause=ATTACK_PAUSE_S,
                            iface=cfg.iface, record=LIVE_REPLAYS.get(case.attack, ())) if case.attack else None
        if attacker is not None:
            attacker.start()
        try:
            outcome = run_flight(case.flights, cfg, "verify", witness=attacker)
        finally:
            if attacker is not None:
                attacker.stop_now()
                attacker.bus.shutdown()
        info = json.loads((run_dir / "run_info.json").read_text(encoding="utf-8"))
        attack = {"forged": float(attacker.sent)} if attacker is not None else None
        key_file = device_class(cfg.target).bus_key_file(cfg.key_file)
        checks = judge(case.expect, read_run(run_dir, outcome.summary, info, attack), RunSeries(run_dir, key_file))
        if case.mode == "realtime":
            checks = against_platform(checks, suite.timing, outcome.summary)
        res.checks = checks + trusted(case, outcome.summary)
        if cfg.plots:
            draw_checks(res.checks, run_dir, refly)
        res.verdict = case_verdict(res.checks)
    except Exception as e:  # noqa: BLE001 - a case that could not run is an error, with its reason
        res.error = (str(e).splitlines() or [type(e).__name__])[0]
    res.seconds = time.monotonic() - t0
    return res


def check_bus(cfg: RigConfig) -> None:
    """The CAN interface opens as a flight opens it; else LinkError, the one line `hil run`
    gives (exit 1), before anything flies -- not one error per case."""
    CanLink(cfg.iface, (), interface=cfg.interface, bitrate=cfg.bitrate).close()


def run_suites(suites: Sequence[Suite], base: RigConfig, out: Path, refly: Callable[[Suite, Case], str],
               show: Callable[[CaseResult], None], coverage: bool = False,
               parallel: Mapping[str, Any] | None = None) -> list[CaseResult]:
    """Every case, in order (the bus checked first: on the workers' rigs with parallel, each
    its own); with coverage, each case's fcc profiles land in its run directory
    (hil.verify.coverage)."""
    if parallel is None:
        check_bus(base)
    results = []
    for suite in suites:
        for case in suite.cases:
            with profiles_to(out / "cases" / case.id) if coverage else nullcontext():
                r = run_case(suite, case, base, out, refly(suite, case), parallel)
            show(r)
            results.append(r)
    return results


def refly_command(suite: Suite, case: Case, argv_tail: Sequence[str]) -> str:
    """The command that flies this case alone again, with the same device options."""
    name = suite.name if shipped().get(suite.name) == suite.path else str(suite.path)
    return shlex.join(["hil", "verify", name, "--case", case.id, *argv_tail])
