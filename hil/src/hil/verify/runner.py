"""Running a suite's cases against the device under test and judging them."""
from __future__ import annotations

import dataclasses
import json
import shlex
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from hil.bus import load
from hil.scenario.file import Scenario, load_default_scenario, with_extra_faults
from hil.rig.config import RigConfig
from hil.runs.run import run_flight
from hil.verify.attack import ATTACKS, Attacker
from hil.verify.expr import Expectation, evaluate, measured
from hil.verify.fields import read_run, values
from hil.verify.suite import Case, Suite, shipped

PASS, FAIL, ERROR = "pass", "fail", "error"
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


def scenarios(case: Case) -> list[Scenario]:
    """The case's flight: each aircraft's embedded scenario with the case's changes."""
    frames = {m.name for m in load().messages}
    out = []
    for aircraft in case.aircraft:
        sc = load_default_scenario(aircraft, frames)
        if not case.default_faults:
            sc = sc.replace(faults=())
        if case.duration is not None:
            sc = sc.replace(duration=float(case.duration))
        if case.seed is not None:
            sc = sc.replace(seed=int(case.seed))
        if aircraft == "missile" and case.lqg:
            assert sc.lqg is not None
            sc = sc.replace(lqg=dataclasses.replace(sc.lqg, **case.lqg))
        mine = [f for f in case.faults if _fault_aircraft(f, sc, frames)]
        if mine:
            sc = with_extra_faults(sc, mine, frames)
        out.append(sc)
    return out


def _fault_aircraft(spec: str, sc: Scenario, frames: set[str]) -> bool:
    """Whether a fault spec applies to this aircraft (a case flying both gives each its own)."""
    try:
        with_extra_faults(sc, [spec], frames)
        return True
    except ValueError:   # (ScenarioError) the other aircraft's fault
        return False


def judge(expect: Sequence[tuple[str, Expectation]], run: dict[str, Any]) -> list[Check]:
    checks = []
    for req, exp in expect:
        vals = values(run, exp.fields)
        ok = bool(evaluate(exp.tree, vals))
        checks.append(Check(req, exp.text, PASS if ok else FAIL, measured(exp, vals)))
    return checks


def run_case(suite: Suite, case: Case, base: RigConfig, out: Path, refly: str) -> CaseResult:
    """Fly one case in its own run directory (out/cases/ID) and judge it; any failure to fly
    or to read a result is an error, never a pass."""
    run_dir = out / "cases" / case.id
    cfg = dataclasses.replace(base, out_dir=run_dir, mode=case.mode)
    res = CaseResult(suite.name, case, ERROR, run_dir=run_dir, command=refly)
    t0 = time.monotonic()
    try:
        scs = scenarios(case)
        if len(case.aircraft) != len({sc.aircraft for sc in scs}):
            raise ValueError("a fault of the case applies to no aircraft it flies")
        attacker = Attacker(ATTACKS[case.attack], pause=ATTACK_PAUSE_S, iface=cfg.iface) \
            if case.attack else None
        if attacker is not None:
            attacker.start()
        try:
            outcome = run_flight(scs, cfg, "verify", witness=attacker)
        finally:
            if attacker is not None:
                attacker.stop_now()
                attacker.bus.shutdown()
        info = json.loads((run_dir / "run_info.json").read_text(encoding="utf-8"))
        attack = {"forged": float(attacker.sent)} if attacker is not None else None
        res.checks = judge(case.expect, read_run(run_dir, outcome.summary, info, attack))
        res.verdict = PASS if all(c.verdict == PASS for c in res.checks) else FAIL
    except Exception as e:  # noqa: BLE001 - a case that could not run is an error, with its reason
        res.error = (str(e).splitlines() or [type(e).__name__])[0]
    res.seconds = time.monotonic() - t0
    return res


def run_suites(suites: Sequence[Suite], base: RigConfig, out: Path, refly: Callable[[Suite, Case], str],
               show: Callable[[CaseResult], None]) -> list[CaseResult]:
    results = []
    for suite in suites:
        for case in suite.cases:
            r = run_case(suite, case, base, out, refly(suite, case))
            show(r)
            results.append(r)
    return results


def refly_command(suite: Suite, case: Case, argv_tail: Sequence[str]) -> str:
    """The command that flies this case alone again, with the same device options."""
    name = suite.name if shipped().get(suite.name) == suite.path else str(suite.path)
    return shlex.join(["hil", "verify", name, "--case", case.id, *argv_tail])
